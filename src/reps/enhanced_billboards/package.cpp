// Enhanced-billboards packages on disk (docs/FORMAT.md): manifest.json, the maps of every billboard
// and the coarse mesh (PLY; with bc the compact meshoptimizer-coded file of reps/common/coarse_mesh.h). Maps: with --compression none two PNG images per billboard (colour +
// coverage, normal + depth; the seed's two-image layout, 000 §3.1); with bc (format version 2)
// three KTX2 files: BC3 colour + coverage (coverage is 0 or 255, which BC3's alpha keeps exactly),
// BC5 octahedral normals fitted over covered texels only, and depth exact (R16, or R8 at
// --depth-bits 8) as a grey PNG (format version 5; a KTX2 under zlib before, still read). Depth is not block-compressed: BC4's 8-bit end points would undo
// the 16-bit depth the exact march needs (docs/RESULTS.md, "Compressed packages"). Reading decodes
// the blocks into the same in-memory images as PNG packages (no recompression). Writing is deterministic (no timings, sorted keys, fixed PNG and PLY
// encoders); reading validates every field and every file, and refuses what it does not
// understand with a status naming the file and the field.
#include "reps/enhanced_billboards/billboards.h"
#include "reps/common/package_cast.h"
#include "reps/common/package_codec.h"
#include "reps/common/block_compress.h"
#include "reps/common/coarse_mesh.h"
#include "reps/common/surface_image.h"

#include <squish.h>

#include <standin/files.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace standin::billboards {

namespace fs = std::filesystem;

namespace {

std::string billboard_file(std::size_t index, const char* map) { return manifest_io::numbered_png("billboard", index, map); }

ImageRGBA8 to_8_bits(const ImageRGBA16& image)
{
    ImageRGBA8 out(image.width, image.height);
    for (std::size_t k = 0; k < image.pixels.size(); ++k) out.pixels[k] = std::uint8_t((image.pixels[k] + 128) / 257);
    return out;
}

std::string compressed_file(std::size_t index, const char* map)
{
    char name[64];
    std::snprintf(name, sizeof name, "billboard_%03zu_%s.ktx2", index, map);
    return name;
}

// The three compressed maps of a billboard (see the file comment).
Status write_compressed(const Billboard& b, std::size_t index, int depth_bits, const std::string& directory,
                        nlohmann::json& files, nlohmann::json& entry)
{
    using manifest_io::BlockFormat;
    const std::size_t texels = std::size_t(b.width) * std::size_t(b.height);
    manifest_io::BlockImage depth{depth_bits == 8 ? BlockFormat::r8 : BlockFormat::r16, b.width, b.height, {}};
    std::vector<std::uint8_t> depths(texels * (depth_bits == 8 ? 1 : 2));
    for (std::size_t k = 0; k < texels; ++k) {
        if (b.color.pixels[k * 4 + 3] < 128) continue; // uncovered texels 0, as a reader gives them
        const std::uint16_t* nd = &b.normal_depth.pixels[k * 4];
        if (depth_bits == 8) {
            depths[k] = std::uint8_t((nd[3] + 128) / 257);
        } else {
            depths[2 * k] = std::uint8_t(nd[3] & 0xff);
            depths[2 * k + 1] = std::uint8_t(nd[3] >> 8);
        }
    }
    manifest_io::BlockImage normal{BlockFormat::bc5, b.width, b.height, {}};
    normal.levels.push_back(!b.normal_bc5.empty()
                                ? b.normal_bc5
                                : reps::compress_octahedral_normals(b.width, b.height, [&](std::size_t k, glm::vec3& n) {
                                      if (b.color.pixels[k * 4 + 3] < 128) return false;
                                      n = reps::decode_normal(&b.normal_depth.pixels[k * 4]);
                                      return true;
                                  }));
    depth.levels.push_back(std::move(depths));
    const std::string names[3] = {billboard_file(index, "color"), compressed_file(index, "normal"), billboard_file(index, "depth")};
    STANDIN_RETURN_IF_ERROR(manifest_io::write_image(b.color, directory, names[0], files));
    STANDIN_RETURN_IF_ERROR(manifest_io::write_blocks(normal, directory, names[1], files));
    STANDIN_RETURN_IF_ERROR(manifest_io::write_exact_channel(depth, directory, names[2], files));
    entry["color"] = {{"file", names[0]}, {"bits", 8}, {"channels", "albedo.rgb (sRGB), coverage"}};
    entry["normal"] = {{"file", names[1]}, {"format", "BC5"}, {"channels", "octahedral world normal (x, y) * 0.5 + 0.5"}};
    entry["depth"] = {{"file", names[2]}, {"format", depth_bits == 8 ? "R8" : "R16"}, {"bits", depth_bits}};
    return Status::ok();
}

// Decodes the compressed maps into the in-memory images PNG packages give (uncovered texels 0).
void read_compressed(const manifest_io::Reader& in, const nlohmann::json& files, const nlohmann::json& entry,
                     const std::string& where, int depth_bits, Billboard& b)
{
    using manifest_io::BlockFormat;
    auto map_file = [&](const char* map, const char* format) {
        const nlohmann::json& m = in.member(entry, map, where);
        in.choice(m, "format", where + map + ".", {format});
        return in.string(m, "file", where + map + ".");
    };
    std::string normal_name = map_file("normal", "BC5"), depth_name = map_file("depth", depth_bits == 8 ? "R8" : "R16");
    manifest_io::BlockImage normal = manifest_io::read_blocks(in, files, normal_name, BlockFormat::bc5, b.width, b.height, 1);
    manifest_io::BlockImage depth = manifest_io::read_exact_channel( // a grey PNG; a KTX2 before format version 5
        in, files, depth_name, depth_bits == 8 ? BlockFormat::r8 : BlockFormat::r16, b.width, b.height);
    const nlohmann::json& color_entry = in.member(entry, "color", where);
    const std::string color_name = in.string(color_entry, "file", where + "color.");
    if (color_entry.contains("format")) { // BC3 colour: read, not written by this version (see the file comment)
        in.choice(color_entry, "format", where + "color.", {"BC3_SRGB"});
        manifest_io::BlockImage color = manifest_io::read_blocks(in, files, color_name, BlockFormat::bc3_srgb, b.width, b.height, 1);
        b.color = ImageRGBA8(b.width, b.height);
        b.color.pixels = reps::decompress_blocks(color.levels[0].data(), b.width, b.height, squish::kDxt5);
    } else {
        b.color = manifest_io::read_image8(in, files, color_name, b.width, b.height);
    }
    std::vector<std::uint8_t> octahedral = reps::decompress_blocks(normal.levels[0].data(), b.width, b.height, squish::kBc5);
    b.normal_bc5 = std::move(normal.levels[0]);
    b.normal_depth = ImageRGBA16(b.width, b.height);
    const std::size_t texels = std::size_t(b.width) * std::size_t(b.height);
    for (std::size_t k = 0; k < texels; ++k) {
        if (b.color.pixels[k * 4 + 3] < 128) {
            std::fill_n(&b.color.pixels[k * 4], 4, std::uint8_t(0));
            continue;
        }
        glm::vec3 n = reps::octahedral_texel(octahedral, k);
        std::uint16_t* nd = &b.normal_depth.pixels[k * 4];
        for (int a = 0; a < 3; ++a) nd[a] = reps::encode_normal(n[a]);
        nd[3] = depth_bits == 8 ? std::uint16_t(depth.levels[0][k] * 257)
                                : std::uint16_t(depth.levels[0][2 * k] | (depth.levels[0][2 * k + 1] << 8));
    }
}

Billboard read_billboard(const manifest_io::Reader& in, const nlohmann::json& files, const nlohmann::json& entry,
                         std::size_t index, int depth_bits)
{
    std::string where = "billboards[" + std::to_string(index) + "].";
    Billboard b;
    b.origin = in.vec3(entry, "origin", where);
    b.axis_u = in.vec3(entry, "axis_u", where);
    b.axis_v = in.vec3(entry, "axis_v", where);
    b.direction = in.vec3(entry, "direction", where);
    manifest_io::check_axes(in, where, b.axis_u, b.axis_v, b.direction);
    b.texel_size = float(in.number(entry, "texel_size", where, 1e-30, 1e30));
    b.depth_range = float(in.number(entry, "depth_range", where, 1e-30, 1e30));
    b.width = int(in.integer(entry, "width", where, 1, 1 << 15));
    b.height = int(in.integer(entry, "height", where, 1, 1 << 15));
    b.captured_faces = std::size_t(in.integer(entry, "captured_faces", where, 0, INT64_MAX));
    b.captured_area = in.number(entry, "captured_area", where, 0.0, 1e300);
    if (entry.contains("normal")) {
        read_compressed(in, files, entry, where, depth_bits, b);
    } else {
        std::string color = in.string(in.member(entry, "color", where), "file", where + "color.");
        std::string normal_depth = in.string(in.member(entry, "normal_depth", where), "file", where + "normal_depth.");
        b.color = manifest_io::read_image8(in, files, color, b.width, b.height);
        b.normal_depth = manifest_io::read_image16(in, files, normal_depth, b.width, b.height, depth_bits);
    }
    // PBR maps (issue #14), in either layout: both or neither; absent in packages of models without
    // PBR materials (the compressed layout's reader returned before them until session 28, so every
    // PBR package baked with the default --compression bc drew its default material)
    if (entry.contains("orm") || entry.contains("emission")) {
        std::string orm = in.string(in.member(entry, "orm", where), "file", where + "orm.");
        std::string emission = in.string(in.member(entry, "emission", where), "file", where + "emission.");
        b.orm = manifest_io::read_image8(in, files, orm, b.width, b.height);
        b.emission = manifest_io::read_image8(in, files, emission, b.width, b.height);
    }
    return b;
}

// One billboard's maps written, its manifest entry made and its files listed.
Status write_billboard(const EnhancedBillboardsPackage& package, std::size_t k, const std::string& directory,
                       nlohmann::json& entry, nlohmann::json& files)
{
    const bool compressed = package.settings.compression == "bc";
    const Billboard& b = package.billboards[k];
    entry = {{"origin", manifest_io::vec3_json(b.origin)},
             {"axis_u", manifest_io::vec3_json(b.axis_u)},
             {"axis_v", manifest_io::vec3_json(b.axis_v)},
             {"direction", manifest_io::vec3_json(b.direction)},
             {"extent", {b.width * b.texel_size, b.height * b.texel_size, b.depth_range}},
             {"texel_size", b.texel_size},
             {"depth_range", b.depth_range},
             {"width", b.width},
             {"height", b.height},
             {"captured_faces", b.captured_faces},
             {"captured_area", b.captured_area}};
    if (compressed) {
        STANDIN_RETURN_IF_ERROR(write_compressed(b, k, package.settings.depth_bits, directory, files, entry));
    } else {
        std::string color = billboard_file(k, "color"), normal_depth = billboard_file(k, "normal_depth");
        STANDIN_RETURN_IF_ERROR(manifest_io::write_image(b.color, directory, color, files));
        if (package.settings.depth_bits == 8)
            STANDIN_RETURN_IF_ERROR(manifest_io::write_image(to_8_bits(b.normal_depth), directory, normal_depth, files));
        else
            STANDIN_RETURN_IF_ERROR(manifest_io::write_image(b.normal_depth, directory, normal_depth, files));
        entry["color"] = {{"file", color}, {"bits", 8}, {"channels", "albedo.rgb (sRGB), coverage"}};
        entry["normal_depth"] = {{"file", normal_depth},
                                 {"bits", package.settings.depth_bits},
                                 {"channels", "normal.xyz * 0.5 + 0.5 (world), depth"}};
    }
    if (!b.orm.empty()) {
        std::string orm = billboard_file(k, "orm"), emission = billboard_file(k, "emission");
        STANDIN_RETURN_IF_ERROR(manifest_io::write_image(b.orm, directory, orm, files));
        STANDIN_RETURN_IF_ERROR(manifest_io::write_image(b.emission, directory, emission, files));
        entry["orm"] = {{"file", orm}, {"bits", 8}, {"channels", "occlusion, roughness, metallic (linear), coverage"}};
        entry["emission"] = {{"file", emission}, {"bits", 8}, {"channels", "emission.rgb (sRGB), coverage"}};
    }
    return Status::ok();
}

} // namespace

Status write(const Package& base, const std::string& directory)
{
    const auto& package = reps::package_cast<EnhancedBillboardsPackage>(base);
    nlohmann::json files = nlohmann::json::object();
    const bool compressed = package.settings.compression == "bc";
    // the billboards side by side (a 46-billboard foliage bake wrote its maps in 5 of its 31 s one
    // at a time)
    std::vector<nlohmann::json> entries(package.billboards.size());
    STANDIN_RETURN_IF_ERROR(manifest_io::write_each(
        entries.size(), [&](std::size_t k, nlohmann::json& listed) { return write_billboard(package, k, directory, entries[k], listed); },
        files));
    nlohmann::json boards = nlohmann::json::array();
    for (nlohmann::json& entry : entries) boards.push_back(std::move(entry));
    nlohmann::json coarse = nullptr;
    if (package.coarse_mesh.triangle_count() > 0) {
        // compressed packages: the compact coarse mesh (reps/common/coarse_mesh.h); PNG packages
        // keep the PLY that format version 1 readers know
        const std::string name = compressed ? "coarse.meshopt" : "coarse.ply";
        const std::string path = (fs::path(directory) / name).string();
        if (compressed)
            STANDIN_RETURN_IF_ERROR(write_file_atomic(
                path, !package.coarse_file.empty() ? package.coarse_file : reps::encode_coarse_mesh(package.coarse_mesh)));
        else
            STANDIN_RETURN_IF_ERROR(write_ply(package.coarse_mesh, path));
        STANDIN_RETURN_IF_ERROR(manifest_io::record_file(directory, name, files));
        coarse = {{"file", name},
                  {"triangles", package.coarse_mesh.triangle_count()},
                  {"vertices", package.coarse_mesh.vertex_count()}};
        if (compressed) coarse["format"] = "meshopt-q16";
        if (package.coarse_rims) coarse["rims"] = true; // only then: other packages keep their bytes
    }
    nlohmann::json left = nlohmann::json::object();
    for (const auto& [reason, what] : package.left)
        left[reason] = {{"faces", what.faces}, {"area", what.area}, {"area_fraction", package.area_total > 0 ? what.area / package.area_total : 0.0}};

    nlohmann::json manifest =
        manifest_io::manifest_header(package, package.parameters, compressed ? k_package_format_version_exact_depth : 1);
    manifest["faces_total"] = package.faces_total;
    manifest["area_total"] = package.area_total;
    manifest["area_captured"] = package.area_captured;
    manifest["area_captured_fraction"] = package.area_total > 0 ? std::min(1.0, package.area_captured / package.area_total) : 0.0;
    manifest["left"] = left;
    if (package.one_closed_surface) manifest["one_closed_surface"] = true; // only then: other packages keep their bytes
    if (package.backs_unseen) manifest["backs_unseen"] = true;
    manifest["billboards"] = boards;
    manifest["coarse_mesh"] = coarse;
    manifest["files"] = files;
    return manifest_io::write_manifest(directory, manifest, 2);
}

Result<std::unique_ptr<Package>> read(const std::string& directory, const nlohmann::json& manifest)
{
    manifest_io::Reader in(directory);
    return manifest_io::read_fields([&]() -> std::unique_ptr<Package> {
        auto package = std::make_unique<EnhancedBillboardsPackage>();
        package->source = manifest_io::read_source(in, manifest);
        // packages from before --compression hold PNG maps
        nlohmann::json patched, patched_sheets, patched_back, patched_assignment;
        const nlohmann::json& with_compression = manifest_io::with_setting_default(manifest, "compression", "none", patched);
        // and from before --sheet-edges covered texels by their centres
        const nlohmann::json& with_sheets =
            manifest_io::with_setting_default(with_compression, "sheet_edges", "centre", patched_sheets);
        // and from before --back-hits drew every back hit
        const nlohmann::json& with_back = manifest_io::with_setting_default(with_sheets, "back_hits", "show", patched_back);
        // and from before --face-assignment put each face on the first billboard that could hold it
        const nlohmann::json& settings =
            manifest_io::with_setting_default(with_back, "face_assignment", "first", patched_assignment);
        package->parameters = manifest_io::read_settings(in, settings, registration().bake_options);
        package->settings = settings_from(package->parameters);
        int depth_bits = package->settings.depth_bits;
        if (depth_bits != 8 && depth_bits != 16) in.fail("bake.depth_bits", "must be 8 or 16");
        package->faces_total = std::size_t(in.integer(manifest, "faces_total", "", 0, INT64_MAX));
        package->area_total = in.number(manifest, "area_total", "", 0.0, 1e300);
        package->area_captured = in.number(manifest, "area_captured", "", 0.0, 1e300);
        if (package->area_captured > package->area_total * (1.0 + 1e-9)) in.fail("area_captured", "exceeds area_total");
        const nlohmann::json& left = in.member(manifest, "left", "");
        if (!left.is_object()) in.fail("left", "is not an object");
        for (const auto& [reason, entry] : left.items()) {
            LeftOver& l = package->left[reason];
            l.faces = std::size_t(in.integer(entry, "faces", "left." + reason + ".", 0, INT64_MAX));
            l.area = in.number(entry, "area", "left." + reason + ".", 0.0, 1e300);
        }
        for (const auto& [key, mark] : {std::pair<const char*, bool*>{"one_closed_surface", &package->one_closed_surface},
                                        std::pair<const char*, bool*>{"backs_unseen", &package->backs_unseen}})
            if (manifest.contains(key)) { // absent in older packages and those of other models
                if (!manifest[key].is_boolean()) in.fail(key, "is not true or false");
                *mark = manifest[key].get<bool>();
            }
        const nlohmann::json& files = in.member(manifest, "files", "");
        if (!files.is_object()) in.fail("files", "is not an object");
        const nlohmann::json& boards = in.member(manifest, "billboards", "");
        if (!boards.is_array()) in.fail("billboards", "is not an array");
        // side by side (PNG and BC decoding are most of a read; the lowest billboard's refusal is reported)
        package->billboards.resize(boards.size());
        manifest_io::read_each(boards.size(), [&](std::size_t k) {
            package->billboards[k] = read_billboard(in, files, boards[k], k, package->settings.depth_bits);
        });
        const nlohmann::json& coarse = in.member(manifest, "coarse_mesh", "");
        if (!coarse.is_null()) {
            std::string name = in.string(coarse, "file", "coarse_mesh.");
            manifest_io::check_file(in, directory, files, name);
            const std::string path = (fs::path(directory) / name).string();
            Result<Mesh> mesh = error(StatusCode::bad_data, "");
            if (coarse.contains("format")) { // the compact coarse mesh (packages of --compression bc)
                in.choice(coarse, "format", "coarse_mesh.", {"meshopt-q16"});
                auto triangles = std::uint64_t(in.integer(coarse, "triangles", "coarse_mesh.", 1, UINT32_MAX));
                auto vertices = std::uint64_t(in.integer(coarse, "vertices", "coarse_mesh.", 1, UINT32_MAX));
                Result<std::string> bytes = read_file(path);
                if (!bytes) throw manifest_io::BadField{bytes.status().message()};
                mesh = reps::decode_coarse_mesh(*bytes, path, triangles, vertices);
                package->coarse_file = std::move(*bytes);
            } else {
                mesh = import_mesh(path);
            }
            if (!mesh) throw manifest_io::BadField{mesh.status().message()};
            package->coarse_mesh = std::move(*mesh);
            if (coarse.contains("rims")) { // absent in older packages and those without sheet rims
                if (!coarse["rims"].is_boolean()) in.fail("coarse_mesh.rims", "is not true or false");
                package->coarse_rims = coarse["rims"].get<bool>();
            }
        }
        if (package->billboards.empty() && package->coarse_mesh.triangle_count() == 0)
            in.fail("billboards", "is empty and there is no coarse mesh: the package draws nothing");
        return package;
    });
}

} // namespace standin::billboards
