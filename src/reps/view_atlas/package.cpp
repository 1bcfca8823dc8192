// View-atlas packages on disk (docs/FORMAT.md, "View atlas"): manifest.json with every view's
// direction, axes and rectangles, and the atlas pages as PNG (colour + coverage; normal + depth for
// "surface" maps; ORM + emission for PBR models, issue #14). Writing is deterministic (sorted keys, fixed PNG encoder); reading validates
// every field and file and refuses what it does not understand with a status naming file and field.
#include "reps/common/package_codec.h"
#include "reps/common/package_cast.h"
#include "reps/view_atlas/view_atlas.h"

#include <standin/files.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace standin::view_atlas {

namespace fs = std::filesystem;

namespace {

std::string page_file(std::size_t index, const char* map) { return manifest_io::numbered_png("page", index, map); }

} // namespace

float ViewAtlasPackage::half_extent() const
{
    if (settings.projection == "ortho") return radius;
    return radius / std::cos(glm::radians(settings.fov) * 0.5f);
}

float ViewAtlasPackage::capture_distance() const { return base_distance(radius, settings.fov); }

Status write(const Package& base, const std::string& directory)
{
    const auto& package = reps::package_cast<ViewAtlasPackage>(base);
    nlohmann::json files = nlohmann::json::object();
    nlohmann::json pages = nlohmann::json::array();
    for (std::size_t k = 0; k < package.color_pages.size(); ++k) {
        nlohmann::json page = {{"color", page_file(k, "color")}, {"normal_depth", nullptr}};
        STANDIN_RETURN_IF_ERROR(manifest_io::write_image(package.color_pages[k], directory, page_file(k, "color"), files));
        if (package.has_surface()) {
            STANDIN_RETURN_IF_ERROR(
                manifest_io::write_image(package.normal_depth_pages[k], directory, page_file(k, "normal_depth"), files));
            page["normal_depth"] = page_file(k, "normal_depth");
        }
        if (package.has_pbr()) { // only then, so that packages of other models stay as they were
            STANDIN_RETURN_IF_ERROR(manifest_io::write_image(package.orm_pages[k], directory, page_file(k, "orm"), files));
            STANDIN_RETURN_IF_ERROR(
                manifest_io::write_image(package.emission_pages[k], directory, page_file(k, "emission"), files));
            page["orm"] = page_file(k, "orm");
            page["emission"] = page_file(k, "emission");
        }
        pages.push_back(page);
    }
    nlohmann::json views = nlohmann::json::array();
    for (const View& v : package.views)
        views.push_back(manifest_io::view_json(v));
    nlohmann::json manifest = manifest_io::manifest_header(package, package.parameters);
    manifest["sphere"] = {{"center", manifest_io::vec3_json(package.center)}, {"radius", package.radius}};
    manifest["half_extent"] = package.half_extent();
    manifest["pages"] = pages;
    manifest["views"] = views;
    manifest["files"] = files;
    return manifest_io::write_manifest(directory, manifest, 1);
}

Result<std::unique_ptr<Package>> read(const std::string& directory, const nlohmann::json& manifest)
{
    manifest_io::Reader in(directory);
    return manifest_io::read_fields([&]() -> std::unique_ptr<Package> {
        auto package = std::make_unique<ViewAtlasPackage>();
        package->source = manifest_io::read_source(in, manifest);
        package->parameters = manifest_io::read_settings(in, manifest, registration().bake_options);
        package->settings = settings_from(package->parameters);
        if (Status valid = check_settings(package->settings); !valid) in.fail("bake", valid.message());
        const BakeSettings& s = package->settings;
        const nlohmann::json& sphere = in.member(manifest, "sphere", "");
        package->center = in.vec3(sphere, "center", "sphere.");
        package->radius = float(in.number(sphere, "radius", "sphere.", 1e-30, 1e30));
        const nlohmann::json& files = in.member(manifest, "files", "");
        if (!files.is_object()) in.fail("files", "is not an object");
        const nlohmann::json& pages = in.member(manifest, "pages", "");
        if (!pages.is_array() || pages.size() > 4096) in.fail("pages", "is not an array of at most 4096 pages");
        if (pages.empty()) in.fail("pages", "is empty: the package draws nothing");
        for (std::size_t k = 0; k < pages.size(); ++k) {
            std::string where = "pages[" + std::to_string(k) + "].";
            package->color_pages.push_back(
                manifest_io::read_image8(in, files, in.string(pages[k], "color", where), s.page_size, s.page_size));
            if (package->has_surface())
                package->normal_depth_pages.push_back(manifest_io::read_image8(
                    in, files, in.string(pages[k], "normal_depth", where), s.page_size, s.page_size));
            const bool pbr = pages[k].is_object() && (pages[k].contains("orm") || pages[k].contains("emission"));
            if (k > 0 && pbr != package->has_pbr()) in.fail(where + "orm", "is on some pages only: every page or none");
            if (pbr && !package->has_surface()) in.fail(where + "orm", "needs surface maps (bake.maps \"surface\")");
            if (pbr) {
                package->orm_pages.push_back(
                    manifest_io::read_image8(in, files, in.string(pages[k], "orm", where), s.page_size, s.page_size));
                package->emission_pages.push_back(
                    manifest_io::read_image8(in, files, in.string(pages[k], "emission", where), s.page_size, s.page_size));
            }
        }
        const nlohmann::json& views = in.member(manifest, "views", "");
        if (!views.is_array() || views.empty()) in.fail("views", "is not a non-empty array");
        for (std::size_t k = 0; k < views.size(); ++k)
            package->views.push_back(
                manifest_io::read_view(in, views[k], "views[" + std::to_string(k) + "].", s.resolution, s.page_size, int(pages.size())));
        if (std::none_of(package->views.begin(), package->views.end(), [](const View& v) { return v.width > 0; }))
            in.fail("views", "are all empty: the package draws nothing");
        return package;
    });
}

} // namespace standin::view_atlas
