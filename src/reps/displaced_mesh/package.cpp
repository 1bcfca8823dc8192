// Displaced-mesh packages on disk (docs/FORMAT.md, "Displaced control mesh"): manifest.json, the
// control mesh as PLY, and little-endian arrays (as gzip members by default, "Compressed arrays"): elevations of every level (uint16 codes over the
// package's range, or float32), ∆_f per face (float32), and on the shading pattern (the finest
// level, or 2 or 4 times finer: bake.shading_detail) octahedral shading normals and RGBA8 albedo (and coverage, uint8, for models with alpha-masked materials). Writing is deterministic; reading checks every field, size and hash and
// that the control mesh is the one the manifest describes, and refuses with a status naming file
// and field.
#include "reps/displaced_mesh/displaced_mesh.h"
#include "io/read_ply.h"
#include "reps/common/package_cast.h"
#include "reps/common/package_codec.h"

#include <standin/files.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>

namespace standin::displaced_mesh {

namespace fs = std::filesystem;

static_assert(std::endian::native == std::endian::little, "package arrays are written as little-endian bytes");

namespace {

const char* const k_control_file = "control.ply";
const char* const k_elevation_file = "elevation.bin";
const char* const k_face_error_file = "face_error.bin";
const char* const k_normal_file = "normal.bin";
const char* const k_albedo_file = "albedo.bin";
const char* const k_orm_file = "orm.bin";           // PBR packages only
const char* const k_emission_file = "emission.bin"; // PBR packages only
const char* const k_coverage_file = "coverage.bin"; // alpha-masked models only (issue #14)
const char* const k_face_texture_file = "face_texture.bin"; // source textures only (source_textures.h)

constexpr std::uint64_t k_max_source_texels = std::uint64_t(1) << 29;

std::string source_texture_name(std::size_t layer) { return manifest_io::numbered_png("source_texture", layer, "color"); }

// An array's bytes as written: NAME, or NAME.gz (package.settings.compressed).
struct ArrayFile {
    std::string name;
    std::string_view bytes;
};

std::string stored_name(const DisplacedMeshPackage& p, const char* name)
{
    return p.settings.compressed ? std::string(name) + ".gz" : std::string(name);
}

template <typename T>
ArrayFile array_file(const DisplacedMeshPackage& p, const char* name, const std::vector<T>& values)
{
    return {stored_name(p, name), std::string_view(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T))};
}

// A listed array of `count` values, raw or (a name ending .gz) gzip-compressed.
template <typename T>
std::vector<T> read_array(const manifest_io::Reader& in, const std::string& directory, const nlohmann::json& files,
                          const std::string& name, std::size_t count)
{
    std::string path = (fs::path(directory) / name).string();
    std::string bytes;
    if (name.ends_with(".gz")) {
        bytes = manifest_io::read_gzip(in, files, name, count * sizeof(T));
    } else {
        manifest_io::check_file(in, directory, files, name);
        Result<std::string> raw = read_file(path);
        if (!raw) throw manifest_io::BadField{raw.status().message()};
        if (raw->size() != count * sizeof(T))
            throw manifest_io::BadField{path + ": holds " + std::to_string(raw->size()) + " bytes, the manifest implies " +
                                        std::to_string(count * sizeof(T))};
        bytes = std::move(*raw);
    }
    std::vector<T> values(count);
    std::memcpy(values.data(), bytes.data(), bytes.size());
    return values;
}

// The source textures' layers and per-face records, checked: every layer index names a layer, UVs
// are finite, cutoffs within [0, 1].
void read_source_textures(const manifest_io::Reader& in, const std::string& directory, const nlohmann::json& files,
                          const nlohmann::json& entry, std::size_t faces, DisplacedMeshPackage& p)
{
    SourceTextures& t = p.source_textures;
    const nlohmann::json& sizes = in.member(entry, "layers", "source_textures.");
    if (!sizes.is_array() || sizes.empty() || sizes.size() > 256) in.fail("source_textures.layers", "is not a list of 1 to 256 sizes");
    const std::size_t layers = sizes.size();
    std::vector<glm::ivec2> size(layers);
    std::uint64_t texels = 0;
    for (std::size_t k = 0; k < layers; ++k) {
        const std::string where = "source_textures.layers[" + std::to_string(k) + "].";
        size[k] = {int(in.integer(sizes[k], "width", where, 1, 16384)), int(in.integer(sizes[k], "height", where, 1, 16384))};
        texels += std::uint64_t(size[k].x) * std::uint64_t(size[k].y);
    }
    // decoded before anything else is checked: a few well-compressed PNGs could ask for far more
    if (texels > k_max_source_texels)
        in.fail("source_textures.layers", "hold " + std::to_string(texels) + " texels, over the " + std::to_string(k_max_source_texels) +
                                              " (2 GiB of RGBA8) standin reads");
    const std::string name = in.string(entry, "file", "source_textures.");
    t.faces = read_array<FaceTexture>(in, directory, files, name, faces);
    t.layers.resize(layers);
    manifest_io::read_each(layers, [&](std::size_t k) {
        ImageRGBA8 image = manifest_io::read_image8(in, files, source_texture_name(k), size[k].x, size[k].y);
        t.layers[k].name = source_texture_name(k);
        t.layers[k].width = image.width;
        t.layers[k].height = image.height;
        t.layers[k].rgba = std::move(image.pixels);
    });
    for (const FaceTexture& f : t.faces) {
        if (f.layer == k_no_texture) continue;
        if (f.layer >= layers) in.fail("source_textures.file", "names texture layer " + std::to_string(f.layer) + " of " + std::to_string(layers));
        for (glm::vec2 uv : f.uv)
            if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) in.fail("source_textures.file", "holds a UV that is not finite");
        if (!(f.cutoff >= 0.0f && f.cutoff <= 1.0f)) in.fail("source_textures.file", "holds an alpha cutoff outside [0, 1]");
    }
}

Mesh control_as_mesh(const DisplacedMeshPackage& p)
{
    Mesh m;
    m.positions = p.positions;
    m.normals = p.normals;
    m.indices = p.indices;
    m.colors.assign(p.positions.size(), glm::vec4(1.0f));
    m.face_materials.assign(p.face_count(), 0);
    m.materials.push_back(Material{});
    return m;
}

// The control mesh back from its PLY, checked against the manifest. Read with the PLY reader itself
// rather than import_mesh: the normals are displacement directions and must come back bit for bit
// (import renormalises them).
void read_control(const manifest_io::Reader& in, const std::string& directory, const nlohmann::json& files,
                  const nlohmann::json& control, DisplacedMeshPackage& p)
{
    std::string name = in.string(control, "file", "control.");
    manifest_io::check_file(in, directory, files, name);
    std::size_t faces = std::size_t(in.integer(control, "faces", "control.", 1, 100'000'000));
    std::size_t vertices = std::size_t(in.integer(control, "vertices", "control.", 3, 100'000'000));
    Result<PlyData> ply = read_ply((fs::path(directory) / name).string());
    if (!ply) throw manifest_io::BadField{ply.status().message()};
    if (ply->triangles.size() != 3 * faces || ply->positions.size() != vertices || ply->normals.size() != vertices)
        in.fail("control.faces", "the control mesh holds " + std::to_string(ply->triangles.size() / 3) + " faces and " +
                                     std::to_string(ply->positions.size()) + " vertices with " +
                                     std::to_string(ply->normals.size()) + " normals");
    for (glm::vec3 v : ply->positions)
        if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) in.fail("control.file", "has a position that is not finite");
    p.positions = std::move(ply->positions);
    p.normals = std::move(ply->normals);
    for (glm::vec3& n : p.normals) {
        float length = glm::length(n);
        if (!(std::abs(length - 1.0f) < 1e-3f)) in.fail("control.file", "has a normal that is not unit");
    }
    p.indices = std::move(ply->triangles);
    p.control.input_faces = std::size_t(in.integer(control, "input_faces", "control.", 0, 1'000'000'000));
    p.control.target_faces = std::size_t(in.integer(control, "target_faces", "control.", 0, 1'000'000'000));
    const nlohmann::json& reached = in.member(control, "reached_target", "control.");
    if (!reached.is_boolean()) in.fail("control.reached_target", "is not a boolean");
    p.control.reached_target = reached.get<bool>();
    p.control.stopped_by = in.choice(control, "stopped_by", "control.", {"target", "no valid collapse"});
    p.control.collapses = std::size_t(in.integer(control, "collapses", "control.", 0, 1'000'000'000));
    p.control.refused_cone = std::size_t(in.integer(control, "refused_cone", "control.", 0, 1'000'000'000'000));
    p.control.refused_flip = std::size_t(in.integer(control, "refused_flip", "control.", 0, 1'000'000'000'000));
    p.control.refused_topology = std::size_t(in.integer(control, "refused_topology", "control.", 0, 1'000'000'000'000));
}

} // namespace

Status write(const Package& base, const std::string& directory)
{
    const auto& p = reps::package_cast<DisplacedMeshPackage>(base);
    const PatternLayout layout = p.layout();
    nlohmann::json files = nlohmann::json::object();
    STANDIN_RETURN_IF_ERROR(write_ply(control_as_mesh(p), (fs::path(directory) / k_control_file).string()));
    STANDIN_RETURN_IF_ERROR(manifest_io::record_file(directory, k_control_file, files));
    std::vector<ArrayFile> arrays = {
        p.settings.elevation_bits == 16 ? array_file(p, k_elevation_file, p.elevation_codes) : array_file(p, k_elevation_file, p.elevations),
        array_file(p, k_face_error_file, p.face_error),
        array_file(p, k_normal_file, p.shading_normals),
        array_file(p, k_albedo_file, p.albedo),
    };
    if (!p.orm.empty()) {
        arrays.push_back(array_file(p, k_orm_file, p.orm));
        arrays.push_back(array_file(p, k_emission_file, p.emission));
    }
    if (!p.coverage.empty()) arrays.push_back(array_file(p, k_coverage_file, p.coverage));
    const SourceTextures& textures = p.source_textures;
    if (!textures.faces.empty()) {
        arrays.push_back(array_file(p, k_face_texture_file, textures.faces));
        for (std::size_t k = 0; k < textures.layers.size(); ++k) {
            ImageRGBA8 image(textures.layers[k].width, textures.layers[k].height);
            image.pixels = textures.layers[k].rgba;
            STANDIN_RETURN_IF_ERROR(manifest_io::write_image(image, directory, source_texture_name(k), files));
        }
    }
    // side by side: deflating the shading arrays (tens of MB on foliage) is most of the writing
    STANDIN_RETURN_IF_ERROR(manifest_io::write_each(arrays.size(), [&](std::size_t k, nlohmann::json& files_k) -> Status {
        const ArrayFile& a = arrays[k];
        if (p.settings.compressed) return manifest_io::write_gzip(a.bytes, directory, a.name, files_k);
        STANDIN_RETURN_IF_ERROR(write_file_atomic((fs::path(directory) / a.name).string(), a.bytes));
        return manifest_io::record_file(directory, a.name, files_k);
    }, files));

    const ControlStats& c = p.control;
    const SamplingStats& s = p.sampling;
    nlohmann::json manifest =
        manifest_io::manifest_header(p, p.parameters, p.settings.compressed ? k_package_format_version_gzip_arrays : 1);
    manifest.update({
        {"control", {{"file", k_control_file}, {"faces", p.face_count()}, {"vertices", p.positions.size()},
                     {"input_faces", c.input_faces}, {"target_faces", c.target_faces}, {"reached_target", c.reached_target},
                     {"stopped_by", c.stopped_by}, {"collapses", c.collapses}, {"refused_cone", c.refused_cone},
                     {"refused_flip", c.refused_flip}, {"refused_topology", c.refused_topology}}},
        {"pattern", {{"degree", layout.degree}, {"levels", layout.exponent + 1}, {"samples_per_face", layout.samples_per_face},
                     {"finest_samples", layout.finest_samples}}},
        {"elevation", {{"file", stored_name(p, k_elevation_file)}, {"bits", p.settings.elevation_bits},
                       {"minimum", p.elevation_minimum}, {"step", p.elevation_step}}},
        {"face_error", {{"file", stored_name(p, k_face_error_file)}}},
        {"shading_normal", {{"file", stored_name(p, k_normal_file)}, {"encoding", "octahedral-snorm16x2"}}},
        {"albedo", {{"file", stored_name(p, k_albedo_file)}, {"encoding", "rgba8-srgb"}}},
        {"sampling", {{"rays", s.rays}, {"misses", s.misses},
                      {"original_to_sampled_mean", s.original_to_sampled_mean}, {"original_to_sampled_max", s.original_to_sampled_max},
                      {"sampled_to_original_mean", s.sampled_to_original_mean}, {"sampled_to_original_max", s.sampled_to_original_max}}},
        {"files", files},
    });
    if (!p.orm.empty()) {
        manifest["orm"] = {{"file", stored_name(p, k_orm_file)}, {"encoding", "rgba8: occlusion, roughness, metallic (linear), 255"}};
        manifest["emission"] = {{"file", stored_name(p, k_emission_file)}, {"encoding", "rgba8-srgb"}};
    }
    if (!textures.faces.empty()) {
        nlohmann::json sizes = nlohmann::json::array();
        for (const Texture& layer : textures.layers) sizes.push_back({{"width", layer.width}, {"height", layer.height}});
        manifest["source_textures"] = {{"file", stored_name(p, k_face_texture_file)}, {"layers", sizes}, {"matched_faces", textures.matched_faces()},
                                       {"encoding", "per control face 48 bytes: float32 u0 v0 u1 v1 u2 v2, uint32 layer (0xffffffff: none), "
                                                    "float32 alpha cutoff, uint32 rgba8 colour x 3, uint32 0; layers " +
                                                        source_texture_name(0) + "..."}};
    }
    if (!p.coverage.empty())
        manifest["coverage"] = {{"file", stored_name(p, k_coverage_file)}, {"encoding", "unorm8: 255 covered, 0 cut out; drawn where the interpolation >= 1/2"}};
    return manifest_io::write_manifest(directory, manifest, 1);
}

Result<std::unique_ptr<Package>> read(const std::string& directory, const nlohmann::json& manifest)
{
    manifest_io::Reader in(directory);
    return manifest_io::read_fields([&]() -> std::unique_ptr<Package> {
        auto p = std::make_unique<DisplacedMeshPackage>();
        p->source = manifest_io::read_source(in, manifest);
        // packages from before --back-faces drew both sides
        nlohmann::json patched, patched_again, patched_thrice;
        const nlohmann::json& settings = manifest_io::with_setting_default(
            manifest_io::with_setting_default(
                manifest_io::with_setting_default(manifest, "back_faces", "show", patched), "shading_detail", "1", patched_again),
            "compression", "none", patched_thrice);
        // packages from before source textures drew every face from its samples
        nlohmann::json patched_source;
        const nlohmann::json& settings_now = manifest_io::with_setting_default(settings, "source_textures", "off", patched_source);
        p->parameters = manifest_io::read_settings(in, settings_now, registration().bake_options);
        p->settings = settings_from(p->parameters);
        if (Status checked = check_settings(p->settings); !checked) in.fail("bake", checked.message());
        // a package records the detail its bake resolved
        if (p->settings.shading_detail == 0) in.fail("bake.shading_detail", "is auto; a package holds 1, 2 or 4");
        const nlohmann::json& files = in.member(manifest, "files", "");
        if (!files.is_object()) in.fail("files", "is not an object");
        read_control(in, directory, files, in.member(manifest, "control", ""), *p);
        Result<ControlTopology> topology = build_topology(p->positions.size(), p->indices);
        if (!topology) throw manifest_io::BadField{in.path() + ": control mesh: " + topology.status().message()};
        p->topology = std::move(*topology);

        const PatternLayout layout = p->layout();
        const std::size_t faces = p->face_count();
        const nlohmann::json& pattern = in.member(manifest, "pattern", "");
        if (in.integer(pattern, "degree", "pattern.", 5, 33) != layout.degree ||
            std::size_t(in.integer(pattern, "samples_per_face", "pattern.", 1, 1'000'000)) != layout.samples_per_face)
            in.fail("pattern", "does not match bake.degree");
        const nlohmann::json& elevation = in.member(manifest, "elevation", "");
        std::string elevation_file = in.string(elevation, "file", "elevation.");
        if (in.integer(elevation, "bits", "elevation.", 16, 32) != p->settings.elevation_bits)
            in.fail("elevation.bits", "differs from bake.elevation_bits");
        std::size_t samples = faces * layout.samples_per_face, shading = faces * p->shading_samples_per_face();
        if (p->settings.elevation_bits == 16) {
            p->elevation_minimum = float(in.number(elevation, "minimum", "elevation.", -1e30, 1e30));
            p->elevation_step = float(in.number(elevation, "step", "elevation.", 0.0, 1e30));
        }
        auto file_of = [&](const char* key) {
            return in.string(in.member(manifest, key, ""), "file", std::string(key) + ".");
        };
        // the arrays side by side (inflating the shading arrays is most of reading a foliage package),
        // in the manifest's order, so the first refusal is the same line on any thread count
        std::vector<std::function<void()>> arrays;
        if (p->settings.elevation_bits == 16)
            arrays.push_back([&, name = elevation_file] { p->elevation_codes = read_array<std::uint16_t>(in, directory, files, name, samples); });
        else
            arrays.push_back([&, name = elevation_file] { p->elevations = read_array<float>(in, directory, files, name, samples); });
        arrays.push_back([&, name = file_of("face_error")] { p->face_error = read_array<float>(in, directory, files, name, faces); });
        arrays.push_back([&, name = file_of("shading_normal")] {
            p->shading_normals = read_array<std::uint32_t>(in, directory, files, name, shading);
        });
        arrays.push_back([&, name = file_of("albedo")] { p->albedo = read_array<std::uint32_t>(in, directory, files, name, shading); });
        if (manifest.contains("orm") || manifest.contains("emission")) {
            arrays.push_back([&, name = file_of("orm")] { p->orm = read_array<std::uint32_t>(in, directory, files, name, shading); });
            arrays.push_back([&, name = file_of("emission")] {
                p->emission = read_array<std::uint32_t>(in, directory, files, name, shading);
            });
        }
        if (manifest.contains("coverage"))
            arrays.push_back([&, name = file_of("coverage")] { p->coverage = read_array<std::uint8_t>(in, directory, files, name, shading); });
        manifest_io::read_each(arrays.size(), [&](std::size_t k) { arrays[k](); });
        if (manifest.contains("source_textures"))
            read_source_textures(in, directory, files, in.member(manifest, "source_textures", ""), faces, *p);
        if (p->settings.elevation_bits == 16) {
            p->elevations.resize(samples);
            for (std::size_t i = 0; i < samples; ++i)
                p->elevations[i] = p->elevation_minimum + float(p->elevation_codes[i]) * p->elevation_step;
        } else {
            for (float h : p->elevations)
                if (!std::isfinite(h)) in.fail("elevation.file", "holds a value that is not finite");
        }
        for (float e : p->face_error)
            if (!(e >= 0.0f && std::isfinite(e))) in.fail("face_error.file", "holds a value that is negative or not finite");
        const nlohmann::json& sampling = in.member(manifest, "sampling", "");
        SamplingStats& s = p->sampling;
        s.rays = std::size_t(in.integer(sampling, "rays", "sampling.", 0, INT64_MAX));
        s.misses = std::size_t(in.integer(sampling, "misses", "sampling.", 0, INT64_MAX));
        s.original_to_sampled_mean = in.number(sampling, "original_to_sampled_mean", "sampling.", 0.0, 1e30);
        s.original_to_sampled_max = in.number(sampling, "original_to_sampled_max", "sampling.", 0.0, 1e30);
        s.sampled_to_original_mean = in.number(sampling, "sampled_to_original_mean", "sampling.", 0.0, 1e30);
        s.sampled_to_original_max = in.number(sampling, "sampled_to_original_max", "sampling.", 0.0, 1e30);
        return p;
    });
}

} // namespace standin::displaced_mesh
