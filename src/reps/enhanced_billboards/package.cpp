// Enhanced-billboards packages on disk (docs/FORMAT.md): manifest.json, two PNG images per
// billboard (colour + coverage, normal + depth; the seed's two-image layout, 000 §3.1) and the
// coarse mesh as PLY. Writing is deterministic (no timings, sorted keys, fixed PNG and PLY
// encoders); reading validates every field and every file, and refuses what it does not
// understand with a status naming the file and the field.
#include "reps/enhanced_billboards/billboards.h"
#include "reps/common/package_cast.h"
#include "reps/common/package_codec.h"

#include <standin/files.h>

#include <algorithm>
#include <cmath>
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
    std::string color = in.string(in.member(entry, "color", where), "file", where + "color.");
    std::string normal_depth = in.string(in.member(entry, "normal_depth", where), "file", where + "normal_depth.");
    b.color = manifest_io::read_image8(in, files, color, b.width, b.height);
    b.normal_depth = manifest_io::read_image16(in, files, normal_depth, b.width, b.height, depth_bits);
    // PBR maps (issue #14): both or neither; absent in packages of models without PBR materials
    if (entry.contains("orm") || entry.contains("emission")) {
        std::string orm = in.string(in.member(entry, "orm", where), "file", where + "orm.");
        std::string emission = in.string(in.member(entry, "emission", where), "file", where + "emission.");
        b.orm = manifest_io::read_image8(in, files, orm, b.width, b.height);
        b.emission = manifest_io::read_image8(in, files, emission, b.width, b.height);
    }
    return b;
}

} // namespace

Status write(const Package& base, const std::string& directory)
{
    const auto& package = reps::package_cast<EnhancedBillboardsPackage>(base);
    nlohmann::json files = nlohmann::json::object();
    nlohmann::json boards = nlohmann::json::array();
    for (std::size_t k = 0; k < package.billboards.size(); ++k) {
        const Billboard& b = package.billboards[k];
        std::string color = billboard_file(k, "color"), normal_depth = billboard_file(k, "normal_depth");
        STANDIN_RETURN_IF_ERROR(manifest_io::write_image(b.color, directory, color, files));
        if (package.settings.depth_bits == 8)
            STANDIN_RETURN_IF_ERROR(manifest_io::write_image(to_8_bits(b.normal_depth), directory, normal_depth, files));
        else
            STANDIN_RETURN_IF_ERROR(manifest_io::write_image(b.normal_depth, directory, normal_depth, files));
        boards.push_back({{"origin", manifest_io::vec3_json(b.origin)},
                          {"axis_u", manifest_io::vec3_json(b.axis_u)},
                          {"axis_v", manifest_io::vec3_json(b.axis_v)},
                          {"direction", manifest_io::vec3_json(b.direction)},
                          {"extent", {b.width * b.texel_size, b.height * b.texel_size, b.depth_range}},
                          {"texel_size", b.texel_size},
                          {"depth_range", b.depth_range},
                          {"width", b.width},
                          {"height", b.height},
                          {"color", {{"file", color}, {"bits", 8}, {"channels", "albedo.rgb (sRGB), coverage"}}},
                          {"normal_depth",
                           {{"file", normal_depth},
                            {"bits", package.settings.depth_bits},
                            {"channels", "normal.xyz * 0.5 + 0.5 (world), depth"}}},
                          {"captured_faces", b.captured_faces},
                          {"captured_area", b.captured_area}});
        if (!b.orm.empty()) {
            std::string orm = billboard_file(k, "orm"), emission = billboard_file(k, "emission");
            STANDIN_RETURN_IF_ERROR(manifest_io::write_image(b.orm, directory, orm, files));
            STANDIN_RETURN_IF_ERROR(manifest_io::write_image(b.emission, directory, emission, files));
            boards.back()["orm"] = {{"file", orm}, {"bits", 8}, {"channels", "occlusion, roughness, metallic (linear), coverage"}};
            boards.back()["emission"] = {{"file", emission}, {"bits", 8}, {"channels", "emission.rgb (sRGB), coverage"}};
        }
    }
    nlohmann::json coarse = nullptr;
    if (package.coarse_mesh.triangle_count() > 0) {
        STANDIN_RETURN_IF_ERROR(write_ply(package.coarse_mesh, (fs::path(directory) / "coarse.ply").string()));
        STANDIN_RETURN_IF_ERROR(manifest_io::record_file(directory, "coarse.ply", files));
        coarse = {{"file", "coarse.ply"},
                  {"triangles", package.coarse_mesh.triangle_count()},
                  {"vertices", package.coarse_mesh.vertex_count()}};
    }
    nlohmann::json left = nlohmann::json::object();
    for (const auto& [reason, what] : package.left)
        left[reason] = {{"faces", what.faces}, {"area", what.area}, {"area_fraction", package.area_total > 0 ? what.area / package.area_total : 0.0}};

    nlohmann::json manifest = manifest_io::manifest_header(package, package.parameters);
    manifest["faces_total"] = package.faces_total;
    manifest["area_total"] = package.area_total;
    manifest["area_captured"] = package.area_captured;
    manifest["area_captured_fraction"] = package.area_total > 0 ? std::min(1.0, package.area_captured / package.area_total) : 0.0;
    manifest["left"] = left;
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
        package->parameters = manifest_io::read_settings(in, manifest, registration().bake_options);
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
        const nlohmann::json& files = in.member(manifest, "files", "");
        if (!files.is_object()) in.fail("files", "is not an object");
        const nlohmann::json& boards = in.member(manifest, "billboards", "");
        if (!boards.is_array()) in.fail("billboards", "is not an array");
        for (std::size_t k = 0; k < boards.size(); ++k)
            package->billboards.push_back(read_billboard(in, files, boards[k], k, package->settings.depth_bits));
        const nlohmann::json& coarse = in.member(manifest, "coarse_mesh", "");
        if (!coarse.is_null()) {
            std::string name = in.string(coarse, "file", "coarse_mesh.");
            manifest_io::check_file(in, directory, files, name);
            Result<Mesh> mesh = import_mesh((fs::path(directory) / name).string());
            if (!mesh) throw manifest_io::BadField{mesh.status().message()};
            package->coarse_mesh = std::move(*mesh);
        }
        if (package->billboards.empty() && package->coarse_mesh.triangle_count() == 0)
            in.fail("billboards", "is empty and there is no coarse mesh: the package draws nothing");
        return package;
    });
}

} // namespace standin::billboards
