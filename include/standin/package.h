// Packages: what a bake produces and a renderer draws. On disk a package is a directory
// NAME.standin/ with manifest.json and the representation's files (docs/FORMAT.md). In memory it
// is a Package subclass owned by its representation (src/reps/<name>/).
#pragma once

#include <standin/mesh.h>
#include <standin/options.h>
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

struct ExportScene; // export.h

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
    SourceInfo source;
    // Filled by read_package: where the package was read from and the bytes its files take.
    std::string directory;
    std::uint64_t package_bytes = 0;
};

// What a representation's baker receives: the model and its bake parameters, already checked
// against the representation's declaration (Representation::bake_options).
struct BakeContext {
    const Mesh& mesh;
    const SourceInfo& source;
    const Options& parameters;
    const Progress& progress;
    int threads = 0; // 0: all cores. Results never depend on it.
};

// What a representation's make_renderer receives: its run-time options, already checked against
// Representation::render_options, and a debug view from Representation::debug_views.
struct RenderSettings {
    Options options;
    DebugView debug_view = DebugView::none;
};

// What `standin info` and the viewer say about a package.
struct PackageSummary {
    std::string headline;   // one line: what the package holds and how much of the model it captured
    nlohmann::json details; // `standin info --json`: at least "representation"
};

// One entry per representation (src/reps/registry.cpp). A representation describes itself: its
// options and debug views drive the command line, --help, the viewer's knobs and its script.
struct Representation {
    std::string name;        // lowercase words joined by '-': -r NAME, and "representation" in manifests
    std::string title;       // capitalised, for --help groups and the viewer
    std::string description; // one line for --help
    std::string reference;   // the papers it implements, by author and year (docs/REFERENCES.md)
    std::vector<OptionSpec> bake_options;
    std::vector<OptionSpec> render_options;
    std::vector<DebugView> debug_views;      // those its renderer draws, besides none
    std::vector<OptionValues> bench_variants; // run-time variants `standin bench` measures too
    Result<std::unique_ptr<Package>> (*bake)(const BakeContext& context);
    // Writes the package's files into an existing empty directory (manifest.json last).
    Status (*write)(const Package& package, const std::string& directory);
    // Reads and validates a package directory whose manifest names this representation.
    Result<std::unique_ptr<Package>> (*read)(const std::string& directory, const nlohmann::json& manifest);
    // Uploads a package to the current GL context.
    Result<std::unique_ptr<Renderer>> (*make_renderer)(const Package& package, const RenderSettings& settings);
    PackageSummary (*summarise)(const Package& package);
    // `standin export` (export.h): the options it declares (checked before the call), and the scene
    // it exports, its geometry in the source model's object space. Null: not exported yet.
    std::vector<OptionSpec> export_options = {};
    Result<ExportScene> (*export_scene)(const Package& package, const Options& options) = nullptr;
};

const std::vector<Representation>& representations();
const Representation* find_representation(const std::string& name);
// The representation of a package (every package's representation is registered).
const Representation& representation_of(const Package& package);

// Bakes `mesh` (read from the file `source` describes) into a package. `parameters` are checked
// against the representation's bake_options: a name it does not declare, or a value of the wrong
// type or out of range, is refused with invalid_argument naming the option.
Result<std::unique_ptr<Package>> bake_package(const Representation& representation, const Mesh& mesh,
                                              const SourceInfo& source, const OptionValues& parameters,
                                              const Progress& progress = {}, int threads = 0);

// Uploads a package to the current GL context for drawing. options.values are checked against the
// representation's render_options (a name it does not declare is refused: "--style does not apply
// to enhanced-billboards packages"), and options.debug_view against its debug_views.
Result<std::unique_ptr<Renderer>> make_package_renderer(const Package& package, const RenderOptions& options);

PackageSummary summarise_package(const Package& package);

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
// 1: PNG maps only; 2: may hold KTX2 maps (docs/FORMAT.md, "Compressed images"); 3: and, for
// enhanced billboards, the compact coarse mesh (a version-2 reader would try to import it as a
// model); 4: and, for the view atlas, block-compressed pages (a version-3 reader would miss the
// pages' normal-depth PNGs and refuse by field, not by version); 5: exact depth of compressed
// packages as grey PNGs instead of R16/R8 KTX2 files (a version-4 reader would try to parse them as
// KTX2); 6: and, for the view atlas, 16-bit depth (a version-5 reader would read its grey PNGs as
// 8-bit and refuse them by file, not by version). Packages are written with the lowest version that
// describes them: without compressed maps 1; view atlases whose only compressed pages are colour 4;
// compressed packages with exact depth 5; 7: and, for the displaced mesh, its arrays as gzip files
// (a version-6 reader would read them as raw arrays and refuse them by size, not by version).
constexpr int k_package_format_version = 7;
constexpr int k_package_format_version_gzip_arrays = 7;
constexpr int k_package_format_version_exact_depth = 5;
constexpr int k_package_format_version_block_pages = 4;

} // namespace standin
