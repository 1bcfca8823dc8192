// Packages: what a bake produces and a renderer draws. On disk a package is a directory
// NAME.standin/ with manifest.json and the representation's files (docs/FORMAT.md). In memory it
// is a Package subclass owned by its representation (src/reps/<name>/).
#pragma once

#include <standin/mesh.h>
#include <standin/progress.h>
#include <standin/render.h>
#include <standin/status.h>

#include <nlohmann/json.hpp>

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace standin {

// Where a package came from; stored in every manifest so that a package names its source.
struct SourceInfo {
    std::string file_name;      // base name of the model file
    std::string content_hash;   // hex FNV-1a 64 of the file bytes
    std::uint64_t file_bytes = 0;
    std::size_t triangles = 0;
    std::size_t vertices = 0;
    Bounds bounds;
    double surface_area = 0.0;
};
Result<SourceInfo> describe_source(const std::string& model_path, const Mesh& mesh);

class Package {
public:
    virtual ~Package() = default;
    virtual std::string representation() const = 0;
    // The summary `standin info PACKAGE --json` prints; at least "representation".
    virtual nlohmann::json summary() const = 0;
    SourceInfo source;
};

// Representation-specific bake parameters by name (as given on the command line, e.g.
// {"resolution", "512"}). Each baker reads the ones it knows and reports the rest as unknown.
class BakeParameters {
public:
    void set(const std::string& name, const std::string& value) { values_[name] = value; }
    bool has(const std::string& name) const { return values_.count(name) != 0; }
    // Typed reads; a value that does not parse or lies outside [min, max] is an error naming it.
    Result<int> get_int(const std::string& name, int fallback, int min, int max) const;
    Result<float> get_float(const std::string& name, float fallback, float min, float max) const;
    Result<std::string> get_choice(const std::string& name, const std::string& fallback,
                                   const std::vector<std::string>& choices) const;
    // Names that were set but never read: a baker calls this last and refuses them.
    Status check_all_used(const std::string& representation) const;

private:
    std::map<std::string, std::string> values_;
    mutable std::map<std::string, bool> used_;
};

struct BakeContext {
    const Mesh& mesh;
    const SourceInfo& source;
    const BakeParameters& parameters;
    const Progress& progress;
    int threads = 0; // 0: all cores. Results never depend on it.
};

// One entry per representation (src/reps/registry.cpp): name -> bake, write, read, renderer.
struct Representation {
    std::string name;         // "enhanced-billboards", "view-atlas", ...
    std::string description;  // one line for --help
    Result<std::unique_ptr<Package>> (*bake)(const BakeContext& context);
    // Writes the package's files into an existing empty directory (manifest.json last).
    Status (*write)(const Package& package, const std::string& directory);
    // Reads and validates a package directory whose manifest names this representation.
    Result<std::unique_ptr<Package>> (*read)(const std::string& directory, const nlohmann::json& manifest);
    // Uploads a package to the current GL context.
    Result<std::unique_ptr<Renderer>> (*make_renderer)(const Package& package, const RenderOptions& options);
};

const std::vector<Representation>& representations();
const Representation* find_representation(const std::string& name);

// Writes a package atomically: into a temporary directory beside `directory`, exchanged with an
// older package in one step when done (files.h commit_path). The parent folder must exist;
// temporaries left by killed bakes of the same output are removed first.
Status write_package(const Package& package, const std::string& directory);
// Reads manifest.json (a regular file of at most k_max_manifest_bytes), checks format name and
// version and every entry of "files" (plain names of regular files inside the package, of the
// recorded size; PNGs are RGBA), then dispatches to the representation's reader. Errors name the
// package or the file, on one line; nothing here throws.
Result<std::unique_ptr<Package>> read_package(const std::string& directory);
constexpr std::uint64_t k_max_manifest_bytes = 64ull << 20;
// Total size of the files in a package directory.
Result<std::uint64_t> package_bytes(const std::string& directory);

constexpr const char* k_package_format = "standin-package";
constexpr int k_package_format_version = 1;

} // namespace standin
