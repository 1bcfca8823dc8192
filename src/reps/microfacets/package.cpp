// Microfacet packages on disk (docs/FORMAT.md, "Microfacets"): manifest.json with the grid, the
// octree levels, the captured views and the pages; voxels.bin with every level's Morton codes; the
// pages as PNG (colour + coverage 8-bit, normal + depth 16-bit, or 8-bit for depth_bits 8; ORM and
// emission 8-bit for models with PBR materials, issue #14).
// Writing is deterministic (sorted keys, fixed PNG encoder); reading checks every field and file and
// refuses what it does not understand with a status naming the file and the field.
#include "reps/common/package_cast.h"
#include "reps/common/package_codec.h"
#include "reps/microfacets/microfacets.h"

#include <standin/files.h>

#include <cmath>
#include <cstring>
#include <filesystem>

namespace standin::microfacets {

namespace fs = std::filesystem;

namespace {

constexpr const char* k_voxels_file = "voxels.bin";

std::string page_file(std::size_t index, const char* map) { return manifest_io::numbered_png("page", index, map); }

// The octree's levels from voxels.bin: codes inside their level's grid, ascending, and each level
// exactly the OR of the next finer one.
Octree read_octree(const manifest_io::Reader& in, const std::string& directory, const nlohmann::json& manifest,
                   const nlohmann::json& files, const BakeSettings& s)
{
    Octree tree;
    tree.min_level = s.min_level;
    tree.max_level = s.level;
    const nlohmann::json& grid = in.member(manifest, "grid", "");
    tree.grid.origin = in.vec3(grid, "origin", "grid.");
    tree.grid.size = float(in.number(grid, "size", "grid.", 1e-30, 1e30));
    std::string name = in.string(manifest, "voxels", "");
    manifest_io::check_file(in, directory, files, name);
    std::string path = (fs::path(directory) / name).string();
    Result<std::string> bytes = read_file(path);
    if (!bytes) throw manifest_io::BadField{bytes.status().message()};
    const nlohmann::json& levels = in.member(manifest, "levels", "");
    if (!levels.is_array() || levels.size() != std::size_t(s.level - s.min_level + 1))
        in.fail("levels", "does not list the levels min_level..level");
    std::size_t offset = 0;
    for (std::size_t k = 0; k < levels.size(); ++k) {
        std::string where = "levels[" + std::to_string(k) + "].";
        int level = s.min_level + int(k);
        if (in.integer(levels[k], "level", where, level, level) != level) in.fail(where + "level", "is out of order");
        auto count = std::size_t(in.integer(levels[k], "count", where, 0, std::int64_t(1) << (3 * level)));
        if (std::size_t(in.integer(levels[k], "offset", where, 0, INT64_MAX)) != offset)
            in.fail(where + "offset", "does not follow the previous level");
        if ((offset + count) * 4 > bytes->size()) in.fail(where + "count", "reaches beyond the end of " + name);
        std::vector<std::uint32_t> codes(count);
        std::memcpy(codes.data(), bytes->data() + offset * 4, count * 4); // little-endian, as written
        const std::uint64_t cells = std::uint64_t(1) << (3 * level);
        for (std::size_t i = 0; i < count; ++i)
            if (codes[i] >= cells || (i > 0 && codes[i] <= codes[i - 1]))
                throw manifest_io::BadField{path + ": level " + std::to_string(level) + " code " + std::to_string(i) +
                                            " is outside the grid or not ascending"};
        tree.levels.push_back(std::move(codes));
        offset += count;
    }
    if (offset * 4 != bytes->size()) throw manifest_io::BadField{path + ": holds more codes than the levels list"};
    for (int level = s.min_level; level < s.level; ++level)
        if (coarsen(tree.at(level + 1)) != tree.at(level))
            throw manifest_io::BadField{path + ": level " + std::to_string(level) + " is not the OR of level " + std::to_string(level + 1)};
    return tree;
}

// 8-bit normal-depth pages hold the quantised values (normals 8-bit, depth 8-bit), 16-bit in memory
ImageRGBA8 narrowed(const ImageRGBA16& page)
{
    ImageRGBA8 narrow(page.width, page.height);
    for (std::size_t i = 0; i < narrow.pixels.size(); ++i) narrow.pixels[i] = std::uint8_t(page.pixels[i] / 257);
    return narrow;
}

} // namespace

Status write(const Package& base, const std::string& directory)
{
    const auto& package = reps::package_cast<MicrofacetsPackage>(base);
    const BakeSettings& s = package.settings;
    nlohmann::json files = nlohmann::json::object();

    // voxels.bin: every level's codes, coarsest first, little-endian uint32
    std::string voxels;
    nlohmann::json levels = nlohmann::json::array();
    for (int level = s.min_level; level <= s.level; ++level) {
        const std::vector<std::uint32_t>& codes = package.octree.at(level);
        levels.push_back({{"level", level}, {"voxel_size", package.octree.grid.voxel_size(level)},
                          {"count", codes.size()}, {"offset", voxels.size() / 4}});
        voxels.append(reinterpret_cast<const char*>(codes.data()), codes.size() * 4);
    }
    STANDIN_RETURN_IF_ERROR(write_file_atomic((fs::path(directory) / k_voxels_file).string(), voxels));
    STANDIN_RETURN_IF_ERROR(manifest_io::record_file(directory, k_voxels_file, files));

    // the pages side by side (manifest_io::write_each)
    std::vector<nlohmann::json> page_entries(package.color_pages.size());
    STANDIN_RETURN_IF_ERROR(manifest_io::write_each(page_entries.size(), [&](std::size_t k, nlohmann::json& listed) -> Status {
        std::string color = page_file(k, "color"), normal_depth = page_file(k, "normal_depth");
        STANDIN_RETURN_IF_ERROR(manifest_io::write_image(package.color_pages[k], directory, color, listed));
        if (s.depth_bits == 16)
            STANDIN_RETURN_IF_ERROR(manifest_io::write_image(package.normal_depth_pages[k], directory, normal_depth, listed));
        else
            STANDIN_RETURN_IF_ERROR(manifest_io::write_image(narrowed(package.normal_depth_pages[k]), directory, normal_depth, listed));
        nlohmann::json page = {{"color", color}, {"normal_depth", normal_depth}};
        if (package.has_pbr()) { // only then, so that packages of other models stay as they were
            std::string orm = page_file(k, "orm"), emission = page_file(k, "emission");
            STANDIN_RETURN_IF_ERROR(manifest_io::write_image(package.orm_pages[k], directory, orm, listed));
            STANDIN_RETURN_IF_ERROR(manifest_io::write_image(package.emission_pages[k], directory, emission, listed));
            page["orm"] = orm;
            page["emission"] = emission;
        }
        page_entries[k] = std::move(page);
        return Status::ok();
    }, files));
    nlohmann::json pages = nlohmann::json::array();
    for (nlohmann::json& page : page_entries) pages.push_back(std::move(page));
    nlohmann::json views = nlohmann::json::array();
    for (const View& v : package.views) views.push_back(manifest_io::view_json(v));
    nlohmann::json manifest = manifest_io::manifest_header(package, package.parameters);
    manifest["grid"] = {{"origin", manifest_io::vec3_json(package.octree.grid.origin)}, {"size", package.octree.grid.size}};
    manifest["levels"] = levels;
    manifest["voxels"] = k_voxels_file;
    manifest["sphere"] = {{"center", manifest_io::vec3_json(package.center)}, {"radius", package.radius}};
    manifest["half_extent"] = package.radius;
    manifest["max_view_angle_degrees"] = glm::degrees(package.max_view_angle);
    manifest["pages"] = pages;
    manifest["views"] = views;
    manifest["files"] = files;
    return manifest_io::write_manifest(directory, manifest, 1);
}

Result<std::unique_ptr<Package>> read(const std::string& directory, const nlohmann::json& manifest)
{
    manifest_io::Reader in(directory);
    return manifest_io::read_fields([&]() -> std::unique_ptr<Package> {
        auto package = std::make_unique<MicrofacetsPackage>();
        package->source = manifest_io::read_source(in, manifest);
        package->parameters = manifest_io::read_settings(in, manifest, registration().bake_options);
        package->settings = settings_from(package->parameters);
        if (Status valid = check_settings(package->settings); !valid) in.fail("bake", valid.message());
        const BakeSettings& s = package->settings;
        const nlohmann::json& files = in.member(manifest, "files", "");
        if (!files.is_object()) in.fail("files", "is not an object");
        package->octree = read_octree(in, directory, manifest, files, s);
        const nlohmann::json& sphere = in.member(manifest, "sphere", "");
        package->center = in.vec3(sphere, "center", "sphere.");
        package->radius = float(in.number(sphere, "radius", "sphere.", 1e-30, 1e30));
        if (std::abs(in.number(manifest, "half_extent", "", 1e-30, 1e30) - package->radius) > 1e-6 * package->radius)
            in.fail("half_extent", "differs from sphere.radius (captures are orthographic)");
        package->max_view_angle = glm::radians(float(in.number(manifest, "max_view_angle_degrees", "", 0.0, 180.0)));
        const nlohmann::json& pages = in.member(manifest, "pages", "");
        if (!pages.is_array() || pages.size() > 4096) in.fail("pages", "is not an array of at most 4096 pages");
        auto has_pbr = [&](std::size_t k) { return pages[k].is_object() && (pages[k].contains("orm") || pages[k].contains("emission")); };
        const bool pbr = !pages.empty() && has_pbr(0);
        for (std::size_t k = 1; k < pages.size(); ++k)
            if (has_pbr(k) != pbr) in.fail("pages[" + std::to_string(k) + "].orm", "is on some pages only: every page or none");
        package->color_pages.resize(pages.size());
        package->normal_depth_pages.resize(pages.size());
        package->orm_pages.resize(pbr ? pages.size() : 0);
        package->emission_pages.resize(pbr ? pages.size() : 0);
        // the pages side by side (manifest_io::read_each)
        manifest_io::read_each(pages.size(), [&](std::size_t k) {
            std::string where = "pages[" + std::to_string(k) + "].";
            package->color_pages[k] = manifest_io::read_image8(in, files, in.string(pages[k], "color", where), s.page_size, s.page_size);
            package->normal_depth_pages[k] = manifest_io::read_image16(in, files, in.string(pages[k], "normal_depth", where),
                                                                       s.page_size, s.page_size, s.depth_bits);
            if (pbr) {
                package->orm_pages[k] = manifest_io::read_image8(in, files, in.string(pages[k], "orm", where), s.page_size, s.page_size);
                package->emission_pages[k] =
                    manifest_io::read_image8(in, files, in.string(pages[k], "emission", where), s.page_size, s.page_size);
            }
        });
        const nlohmann::json& views = in.member(manifest, "views", "");
        if (!views.is_array() || views.empty() || views.size() > 65535) in.fail("views", "is not an array of 1..65535 views");
        for (std::size_t k = 0; k < views.size(); ++k)
            package->views.push_back(
                manifest_io::read_view(in, views[k], "views[" + std::to_string(k) + "].", s.resolution, s.page_size, int(pages.size())));
        return package;
    });
}

} // namespace standin::microfacets
