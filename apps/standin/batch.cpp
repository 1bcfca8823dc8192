// Batch baking (batch.h). Steps: collect the models (files, folders searched recursively for files
// assimp reads, list files), sorted so that every shard of a job array agrees on the order; keep
// this shard's; for each, skip it when its package is up to date, else import, bake, write and
// measure it; write the shard's summary (or the whole batch's), carrying the figures of skipped
// packages over from earlier summaries.
#include "batch.h"

#include "common.h"

#include <standin/eval.h>
#include <standin/files.h>
#include <standin/mesh.h>
#include <standin/render.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <optional>
#include <set>

namespace standin::cli {

namespace fs = std::filesystem;

namespace {

constexpr const char* k_summary_format = "standin-batch";
constexpr const char* k_summary_name = "standin-batch.json";

bool ends_with(const std::string& text, const std::string& suffix)
{
    return text.size() >= suffix.size() && text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// The models of the inputs and the list, sorted and without repeats.
Result<std::vector<std::string>> collect_models(const std::vector<std::string>& inputs, const std::string& list)
{
    std::set<std::string> models;
    std::vector<std::string> given = inputs;
    if (!list.empty()) {
        Result<std::string> text = read_file(list, 64 << 20);
        if (!text) return text.status();
        fs::path base = fs::path(list).parent_path();
        std::size_t start = 0;
        while (start < text->size()) {
            std::size_t end = text->find('\n', start);
            if (end == std::string::npos) end = text->size();
            std::string line = text->substr(start, end - start);
            start = end + 1;
            while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t')) line.pop_back();
            std::size_t first = line.find_first_not_of(" \t");
            if (first == std::string::npos || line[first] == '#') continue;
            line = line.substr(first);
            given.push_back(fs::path(line).is_absolute() ? line : (base / line).string());
        }
    }
    for (const std::string& input : given) {
        std::error_code ec;
        if (fs::is_directory(input, ec)) {
            fs::recursive_directory_iterator it(input, fs::directory_options::skip_permission_denied, ec), end;
            if (ec) return error(StatusCode::io_error, quoted(input) + ": cannot list the folder: " + ec.message());
            for (; it != end; it.increment(ec)) {
                if (ec) return error(StatusCode::io_error, quoted(input) + ": cannot list the folder: " + ec.message());
                std::string path = it->path().string();
                if (ends_with(it->path().parent_path().string(), ".standin")) continue; // inside a package
                if (it->is_regular_file(ec) && is_model_file_name(path)) models.insert(path);
            }
        } else {
            models.insert(input); // a missing or unreadable file fails its own bake, naming it
        }
    }
    if (models.empty()) return error(StatusCode::invalid_argument, "bake: no models given (the folders hold none assimp reads)");
    return std::vector<std::string>(models.begin(), models.end());
}

// NAME.standin for each model: its stem, or stem.ext where two models share a stem.
std::vector<std::string> package_names(const std::vector<std::string>& models)
{
    std::map<std::string, int> stems;
    for (const std::string& m : models) stems[fs::path(m).stem().string()] += 1;
    std::vector<std::string> names;
    for (const std::string& m : models) {
        fs::path p(m);
        std::string stem = p.stem().string();
        names.push_back((stems[stem] > 1 ? p.filename().string() : stem) + ".standin");
    }
    return names;
}

std::string summary_path(const BatchArgs& args)
{
    if (args.shards <= 1) return (fs::path(args.output) / k_summary_name).string();
    return (fs::path(args.output) / ("standin-batch.shard-" + std::to_string(args.shard) + "-of-" +
                                     std::to_string(args.shards) + ".json"))
        .string();
}

// Entries of earlier summaries in the output folder (whole batches and shards), by package name:
// what a skipped package's entry repeats.
std::map<std::string, nlohmann::json> earlier_entries(const std::string& output)
{
    std::map<std::string, nlohmann::json> entries;
    std::error_code ec;
    for (const auto& file : fs::directory_iterator(output, ec)) {
        std::string name = file.path().filename().string();
        if (name.rfind("standin-batch", 0) != 0 || !ends_with(name, ".json")) continue;
        Result<std::string> text = read_file(file.path().string(), 256 << 20);
        if (!text) continue;
        nlohmann::json doc = nlohmann::json::parse(*text, nullptr, false);
        if (!doc.is_object() || doc.value("format", "") != k_summary_format || !doc["models"].is_array()) continue;
        for (const nlohmann::json& entry : doc["models"])
            if (entry.is_object() && entry.contains("package") && entry.value("status", "") != "failed")
                entries[entry["package"].get<std::string>()] = entry;
    }
    return entries;
}

// Whether the package at `directory` was baked from these bytes, by this representation, with
// these requested options (its manifest says so).
bool up_to_date(const std::string& directory, const std::string& content_hash, const Representation& representation,
                const nlohmann::json& requested)
{
    Result<std::string> text = read_file((fs::path(directory) / "manifest.json").string(), 256 << 20);
    if (!text) return false;
    nlohmann::json manifest = nlohmann::json::parse(*text, nullptr, false);
    if (!manifest.is_object()) return false;
    auto at = [&](const char* a, const char* b = nullptr) -> nlohmann::json {
        if (!manifest.contains(a)) return nullptr;
        const nlohmann::json& v = manifest[a];
        if (!b) return v;
        return v.is_object() && v.contains(b) ? v[b] : nlohmann::json(nullptr);
    };
    // any version this standin reads: packages are written with the lowest version that describes
    // them (include/standin/package.h), so an up-to-date package may hold 1, 3 or 4
    const nlohmann::json version = at("version");
    const bool readable = version.is_number_integer() && version.get<std::int64_t>() >= 1 &&
                          version.get<std::int64_t>() <= k_package_format_version;
    return at("format") == k_package_format && readable &&
           at("representation") == representation.name && at("source", "content_hash") == content_hash &&
           at("requested") == requested;
}

// The stand-in against its model at distance 1 (the quick protocol, untimed).
Result<nlohmann::json> error_at_distance_1(const Mesh& mesh, const Package& package)
{
    Result<std::unique_ptr<Renderer>> truth = make_mesh_renderer(mesh);
    if (!truth) return truth.status();
    Result<std::unique_ptr<Renderer>> standin = make_package_renderer(package, {});
    if (!standin) return standin.status();
    Result<Protocol> protocol = make_protocol("quick");
    if (!protocol) return protocol.status();
    EvalOptions options;
    options.timed_frames = 0;
    Result<EvalResult> result = evaluate(**truth, **standin, mesh.bounding_sphere(), *protocol, options, {});
    if (!result) return result.status();
    auto mean = [&](double (*figure)(const ViewResult&)) { return stats_over_views(*result, figure).mean; };
    return nlohmann::json{{"protocol", "quick"},
                          {"de2000_mean", mean([](const ViewResult& v) { return v.metrics.de2000_mean; })},
                          {"luv_mean", mean([](const ViewResult& v) { return v.metrics.luv_mean; })},
                          {"iou", mean([](const ViewResult& v) { return v.metrics.iou; })}};
}

// Bakes one model into `directory`; fills the entry (status, figures) and returns ok, or the
// failure.
Status bake_one(const BatchArgs& args, const std::string& model, const std::string& directory,
                std::optional<std::unique_ptr<GpuContext>>& context, nlohmann::json& entry)
{
    auto start = std::chrono::steady_clock::now();
    Result<Mesh> mesh = import_mesh(model, nullptr, k_isolated_import);
    if (!mesh) return mesh.status();
    Result<SourceInfo> source = describe_source(model, *mesh);
    if (!source) return source.status();
    Result<std::unique_ptr<Package>> package =
        bake_package(*args.representation, *mesh, *source, args.parameters, stderr_progress(), args.threads);
    if (!package) return naming_file(package.status(), model);
    STANDIN_RETURN_IF_ERROR(write_package(**package, directory));
    Result<std::uint64_t> bytes = package_bytes(directory);
    if (!bytes) return bytes.status();
    entry["status"] = "baked";
    entry["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    entry["package_bytes"] = *bytes;
    entry["source_bytes"] = source->file_bytes;
    entry["triangles"] = source->triangles;
    entry["summary"] = summarise_package(**package).headline;
    entry["error_at_distance_1"] = nullptr;
    if (!args.evaluate) return Status::ok();
    if (!context) {
        Result<std::unique_ptr<GpuContext>> made = create_headless_context();
        if (!made) return made.status();
        context.emplace(std::move(*made));
    }
    Result<nlohmann::json> measured = error_at_distance_1(*mesh, **package);
    if (!measured) return naming_file(measured.status(), directory);
    entry["error_at_distance_1"] = *measured;
    return Status::ok();
}

} // namespace

bool is_batch(const std::vector<std::string>& inputs, const std::string& list, const std::string& output)
{
    if (inputs.size() != 1 || !list.empty()) return true;
    std::error_code ec;
    if (fs::is_directory(inputs.front(), ec)) return true;
    std::string out = output;
    while (out.size() > 1 && out.back() == '/') out.pop_back();
    return !ends_with(out, ".standin");
}

Status parse_shard(const std::string& text, int& shard, int& shards)
{
    shard = 0;
    shards = 1;
    std::string value = text;
    if (value.empty()) {
        const char* id = std::getenv("SLURM_ARRAY_TASK_ID");
        const char* count = std::getenv("SLURM_ARRAY_TASK_COUNT");
        if (!id || !count) return Status::ok();
        const char* min = std::getenv("SLURM_ARRAY_TASK_MIN");
        long first = min ? std::atol(min) : 0;
        value = std::to_string(std::atol(id) - first) + "/" + count;
    }
    int i = -1, n = 0;
    char slash = 0, rest = 0;
    if (std::sscanf(value.c_str(), "%d%c%d%c", &i, &slash, &n, &rest) != 3 || slash != '/' || n < 1 || n > 100000 ||
        i < 0 || i >= n)
        return error(StatusCode::invalid_argument,
                     "--shard: expected I/N with 0 <= I < N (or SLURM_ARRAY_TASK_ID and SLURM_ARRAY_TASK_COUNT), got " +
                         quoted(value));
    shard = i;
    shards = n;
    return Status::ok();
}

int run_batch(const BatchArgs& args)
{
    // the options first: a batch with a bad option fails before any model is read
    Result<Options> options = Options::parse(args.representation->bake_options, args.parameters, args.representation->name);
    if (!options) return fail(options.status());
    nlohmann::json requested = options->requested();
    Result<std::vector<std::string>> models = collect_models(args.inputs, args.list);
    if (!models) return fail(models.status());
    std::error_code ec;
    if (!fs::is_directory(args.output, ec)) {
        if (Status s = check_output_path(args.output); !s) return fail(s);
        fs::create_directory(args.output, ec); // shards of a job array may race to make it
        if (!fs::is_directory(args.output, ec)) return fail(quoted(args.output) + ": cannot make the output folder");
    }
    std::vector<std::string> names = package_names(*models);
    std::map<std::string, nlohmann::json> earlier = earlier_entries(args.output);

    std::optional<std::unique_ptr<GpuContext>> context;
    nlohmann::json entries = nlohmann::json::array();
    int baked = 0, skipped = 0, failed = 0, mine = 0;
    for (std::size_t k = 0; k < models->size(); ++k) mine += int(k % std::size_t(args.shards)) == args.shard;
    int done = 0;
    for (std::size_t k = 0; k < models->size(); ++k) {
        if (int(k % std::size_t(args.shards)) != args.shard) continue;
        const std::string& model = (*models)[k];
        std::string directory = (fs::path(args.output) / names[k]).string();
        nlohmann::json entry = {{"model", model}, {"package", names[k]}};
        std::string progress = "[" + std::to_string(++done) + "/" + std::to_string(mine) + "] " + model;
        Result<std::string> bytes = read_file(model);
        std::string hash = bytes ? hex64(hash_bytes(*bytes)) : std::string();
        if (!args.force && bytes && up_to_date(directory, hash, *args.representation, requested)) {
            if (earlier.count(names[k])) entry = earlier[names[k]];
            entry["model"] = model;
            entry["status"] = "skipped";
            ++skipped;
            note(progress + ": " + directory + " is up to date");
        } else {
            Status status = bytes ? bake_one(args, model, directory, context, entry) : bytes.status();
            if (status) {
                ++baked;
                char line[200];
                std::snprintf(line, sizeof line, ": baked in %.2f s, %llu bytes", entry["seconds"].get<double>(),
                              (unsigned long long)entry["package_bytes"].get<std::uint64_t>());
                std::string measured;
                if (entry["error_at_distance_1"].is_object())
                    measured = ", CIEDE2000 " + std::to_string(entry["error_at_distance_1"]["de2000_mean"].get<double>()).substr(0, 5) +
                               " at distance 1";
                note(progress + " -> " + directory + line + measured);
            } else {
                ++failed;
                entry["status"] = "failed";
                entry["error"] = status.message();
                std::fprintf(stderr, "standin: %s: failed: %s\n", progress.c_str(), one_line(status.message(), 400).c_str());
            }
        }
        entries.push_back(entry);
    }

    nlohmann::json summary = {{"format", k_summary_format},
                              {"version", 1},
                              {"representation", args.representation->name},
                              {"requested", requested},
                              {"shard", args.shard},
                              {"shards", args.shards},
                              {"baked", baked},
                              {"skipped", skipped},
                              {"failed", failed},
                              {"models", entries}};
    std::string path = summary_path(args);
    if (Status s = write_file_atomic(path, summary.dump(2) + "\n"); !s) return fail(s);
    note("batch: " + std::to_string(baked) + " baked, " + std::to_string(skipped) + " up to date, " +
         std::to_string(failed) + " failed; summary " + path);
    return failed > 0 ? k_exit_failure : k_exit_ok;
}

} // namespace standin::cli
