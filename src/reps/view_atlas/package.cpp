// View-atlas packages on disk (docs/FORMAT.md, "View atlas"): manifest.json with every view's
// direction, axes and rectangles, and the atlas pages (colour + coverage; normal + depth for
// "surface" maps; ORM + emission for PBR models, issue #14). With --compression none every page is
// a PNG (format version 1). With bc (format version 5, issue #17) a surface page's normals are BC5
// blocks of octahedral normals (Meyer et al. 2010) fitted over covered texels only, in the KTX2
// files of reps/common/package_codec.h, and its depth exact as an 8-bit grey PNG (an R8 KTX2 in
// format version 4, still read), as the enhanced billboards store theirs; colour stays PNG (BC3 colour cost the billboards +0.77 Luv, docs/RESULTS.md).
// Depth of more than 8 bits (bake.depth_bits, format version 6) is a 16-bit grey PNG in either
// mode, beside the normal-depth page or the BC5 normals, and read into depth_pages.
// bc-color stores the colour as the premultiplied DXT5 levels --texture-format bc3 uploads, so that
// loading compresses nothing. ORM and emission pages stay PNG in every mode (rare, and BC3 would
// round the linear ORM channels to 5:6:5). Reading decodes the blocks into the in-memory pages PNG
// packages give (uncovered texels 0) and keeps them, so that writing a read package stores the
// same blocks. Writing is deterministic (sorted keys, fixed PNG encoder, zlib 9, blocks fitted
// independently of the thread count); reading validates every field and file and refuses what it
// does not understand with a status naming file and field.
#include "reps/common/block_compress.h"
#include "reps/common/package_codec.h"
#include "reps/common/package_cast.h"
#include "reps/view_atlas/view_atlas.h"

#include <standin/files.h>

#include <squish.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace standin::view_atlas {

namespace fs = std::filesystem;

namespace {

std::string page_file(std::size_t index, const char* map) { return manifest_io::numbered_png("page", index, map); }

std::string page_blocks_file(std::size_t index, const char* map)
{
    std::string name = page_file(index, map);
    return name.substr(0, name.size() - 4) + ".ktx2";
}

using manifest_io::BlockFormat;
using manifest_io::BlockImage;

// The colour coverage from which a page's texels hold a normal and depth in the package: compressed
// packages keep them where the texel is at least half covered (BC5 normals are fitted there), PNG
// packages wherever it is covered at all.
unsigned min_surface_alpha(const ViewAtlasPackage& package) { return package.settings.compression != "none" ? 128u : 1u; }

// A page's depth codes (depth_bits over 8, depth_code) as a 16-bit grey PNG, "depth" on the page: 0
// where the page holds no surface (min_surface_alpha), as a reader gives them.
Status write_fine_depth(const ViewAtlasPackage& package, std::size_t k, const std::string& directory,
                        nlohmann::json& files, nlohmann::json& page)
{
    const int size = package.settings.page_size;
    const std::vector<std::uint16_t>& samples = package.depth_pages[k];
    const ImageRGBA8& color = package.color_pages[k];
    BlockImage depth{BlockFormat::r16, size, size, {std::vector<std::uint8_t>(samples.size() * 2)}};
    for (std::size_t t = 0; t < samples.size(); ++t) {
        if (color.pixels[t * 4 + 3] < min_surface_alpha(package)) continue;
        depth.levels[0][2 * t] = std::uint8_t(samples[t] & 0xff);
        depth.levels[0][2 * t + 1] = std::uint8_t(samples[t] >> 8);
    }
    STANDIN_RETURN_IF_ERROR(manifest_io::write_exact_channel(depth, directory, page_file(k, "depth"), files));
    page["depth"] = page_file(k, "depth");
    return Status::ok();
}

// Reads a page's depth codes into depth_pages where the page holds a surface (min_surface_alpha),
// and puts them, rounded to 8 bits (depth8), into the A of its normal-depth page, already read. A
// code off the depth_bits grid (low bits set) is refused: the file is not what the manifest says.
void read_fine_depth(const manifest_io::Reader& in, const nlohmann::json& files, const std::string& name, int size,
                     ViewAtlasPackage& package, std::size_t k)
{
    BlockImage depth = manifest_io::read_exact_channel(in, files, name, BlockFormat::r16, size, size);
    std::vector<std::uint16_t> samples(std::size_t(size) * std::size_t(size));
    const int bits = package.settings.depth_bits;
    const unsigned low_bits = (1u << (16 - bits)) - 1u;
    const ImageRGBA8& color = package.color_pages[k];
    ImageRGBA8& nd = package.normal_depth_pages[k];
    for (std::size_t t = 0; t < samples.size(); ++t) {
        if (color.pixels[t * 4 + 3] < min_surface_alpha(package)) continue;
        samples[t] = std::uint16_t(depth.levels[0][2 * t] | (depth.levels[0][2 * t + 1] << 8));
        if (samples[t] & low_bits)
            in.fail(name, "holds depth " + std::to_string(samples[t]) + ", not a multiple of " + std::to_string(low_bits + 1) +
                              " as " + std::to_string(bits) + "-bit depth (bake.depth_bits) is");
        nd.pixels[t * 4 + 3] = depth8(samples[t], bits);
    }
    package.depth_pages[k] = std::move(samples);
}

// A surface page's normals (BC5, octahedral) and depth (8 bits, or more: write_fine_depth; exact,
// a grey PNG) as the package stores them.
Status write_surface_blocks(const ViewAtlasPackage& package, std::size_t k, const std::string& directory,
                            nlohmann::json& files, nlohmann::json& page)
{
    const int size = package.settings.page_size;
    const ImageRGBA8& color = package.color_pages[k];
    const ImageRGBA8& nd = package.normal_depth_pages[k];
    BlockImage normal{BlockFormat::bc5, size, size, {}};
    if (k < package.normal_bc5.size() && !package.normal_bc5[k].empty())
        normal.levels.push_back(package.normal_bc5[k]);
    else
        normal.levels.push_back(reps::compress_octahedral_normals(size, size, [&](std::size_t t, glm::vec3& n) {
            if (color.pixels[t * 4 + 3] < 128) return false;
            n = glm::vec3(nd.pixels[t * 4], nd.pixels[t * 4 + 1], nd.pixels[t * 4 + 2]) / 255.0f * 2.0f - 1.0f;
            return true;
        }));
    STANDIN_RETURN_IF_ERROR(manifest_io::write_blocks(normal, directory, page_blocks_file(k, "normal"), files));
    page["normal"] = page_blocks_file(k, "normal");
    if (package.has_fine_depth()) return write_fine_depth(package, k, directory, files, page);
    BlockImage depth{BlockFormat::r8, size, size, {std::vector<std::uint8_t>(std::size_t(size) * std::size_t(size))}};
    for (std::size_t t = 0; t < depth.levels[0].size(); ++t) // uncovered texels 0, as a reader gives them
        depth.levels[0][t] = color.pixels[t * 4 + 3] >= 128 ? nd.pixels[t * 4 + 3] : std::uint8_t(0);
    STANDIN_RETURN_IF_ERROR(manifest_io::write_exact_channel(depth, directory, page_file(k, "depth"), files));
    page["depth"] = page_file(k, "depth");
    return Status::ok();
}

// Decodes page k's compressed colour (bc-color) into its colour page, zero where not covered.
void read_color_blocks(const manifest_io::Reader& in, const nlohmann::json& files, const std::string& name, int size,
                       ViewAtlasPackage& package, std::size_t k)
{
    BlockImage blocks = manifest_io::read_blocks(in, files, name, BlockFormat::bc3_srgb, size, size, k_mip_levels);
    ImageRGBA8 color(size, size);
    color.pixels = reps::decompress_blocks(blocks.levels[0].data(), size, size, squish::kDxt5);
    for (std::size_t t = 0; t < color.pixels.size(); t += 4)
        if (color.pixels[t + 3] < 128) std::fill_n(&color.pixels[t], 4, std::uint8_t(0));
    package.color_pages[k] = std::move(color);
    package.color_bc3[k] = std::move(blocks.levels);
}

// Decodes page k's normals and depth into the normal-depth page PNG packages hold.
void read_surface_blocks(const manifest_io::Reader& in, const nlohmann::json& files, const std::string& normal_name,
                         const std::string& depth_name, int size, ViewAtlasPackage& package, std::size_t k)
{
    BlockImage normal = manifest_io::read_blocks(in, files, normal_name, BlockFormat::bc5, size, size, 1);
    const bool depth16 = package.settings.depth_bits > 8;
    BlockImage depth = depth16 ? BlockImage{} // read_fine_depth, below
                               : manifest_io::read_exact_channel(in, files, depth_name, BlockFormat::r8, size, size); // .ktx2 before version 5
    const std::vector<std::uint8_t> octahedral = reps::decompress_blocks(normal.levels[0].data(), size, size, squish::kBc5);
    const ImageRGBA8& color = package.color_pages[k];
    ImageRGBA8 nd(size, size);
    for (std::size_t t = 0; t < std::size_t(size) * std::size_t(size); ++t) {
        if (color.pixels[t * 4 + 3] < 128) continue;
        const glm::vec3 n = reps::octahedral_texel(octahedral, t);
        for (int c = 0; c < 3; ++c)
            nd.pixels[t * 4 + std::size_t(c)] = std::uint8_t(std::lround(std::clamp(n[c] * 0.5f + 0.5f, 0.0f, 1.0f) * 255.0f));
        if (!depth16) nd.pixels[t * 4 + 3] = depth.levels[0][t];
    }
    package.normal_depth_pages[k] = std::move(nd);
    package.normal_bc5[k] = std::move(normal.levels[0]);
    if (depth16) read_fine_depth(in, files, depth_name, size, package, k);
}

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
    const std::string& compression = package.settings.compression;
    const bool compressed = compression != "none";
    const std::size_t page_texels = std::size_t(package.settings.page_size) * std::size_t(package.settings.page_size);
    if (package.has_surface() && package.settings.depth_bits == 0)
        return error(StatusCode::invalid_argument, "view atlas: depth_bits 0 (a bake chooses 8..16) in a package to write");
    if (package.has_fine_depth() &&
        (package.depth_pages.size() != package.color_pages.size() ||
         std::any_of(package.depth_pages.begin(), package.depth_pages.end(), [&](const auto& d) { return d.size() != page_texels; })))
        return error(StatusCode::invalid_argument, "view atlas: depth_bits over 8 without a depth page per page");
    // a newer format version only where the layout needs it: a lit package of bc is laid out as
    // version 1; KTX2 colour needs 4, grey PNG depth 5, depth over 8 bits 6
    const int version = package.has_fine_depth()              ? k_package_format_version
                        : compressed && package.has_surface() ? k_package_format_version_exact_depth
                        : compression == "bc-color"           ? k_package_format_version_block_pages
                                                              : 1;
    // the pages side by side (manifest_io::write_each)
    std::vector<nlohmann::json> page_entries(package.color_pages.size());
    STANDIN_RETURN_IF_ERROR(manifest_io::write_each(page_entries.size(), [&](std::size_t k, nlohmann::json& listed) -> Status {
        nlohmann::json page = {{"color", page_file(k, "color")}};
        if (compression == "bc-color") {
            BlockImage color{BlockFormat::bc3_srgb, package.settings.page_size, package.settings.page_size, {}};
            color.levels = k < package.color_bc3.size() && !package.color_bc3[k].empty() ? package.color_bc3[k]
                                                                                        : color_page_blocks(package.color_pages[k]);
            STANDIN_RETURN_IF_ERROR(manifest_io::write_blocks(color, directory, page_blocks_file(k, "color"), listed));
            page["color"] = page_blocks_file(k, "color");
        } else {
            STANDIN_RETURN_IF_ERROR(manifest_io::write_image(package.color_pages[k], directory, page_file(k, "color"), listed));
        }
        if (compressed) {
            if (package.has_surface()) STANDIN_RETURN_IF_ERROR(write_surface_blocks(package, k, directory, listed, page));
        } else if (!package.has_surface()) {
            page["normal_depth"] = nullptr;
        } else {
            STANDIN_RETURN_IF_ERROR(
                manifest_io::write_image(package.normal_depth_pages[k], directory, page_file(k, "normal_depth"), listed));
            page["normal_depth"] = page_file(k, "normal_depth");
            if (package.has_fine_depth()) STANDIN_RETURN_IF_ERROR(write_fine_depth(package, k, directory, listed, page));
        }
        if (package.has_pbr()) { // only then, so that packages of other models stay as they were
            STANDIN_RETURN_IF_ERROR(manifest_io::write_image(package.orm_pages[k], directory, page_file(k, "orm"), listed));
            STANDIN_RETURN_IF_ERROR(
                manifest_io::write_image(package.emission_pages[k], directory, page_file(k, "emission"), listed));
            page["orm"] = page_file(k, "orm");
            page["emission"] = page_file(k, "emission");
        }
        page_entries[k] = std::move(page);
        return Status::ok();
    }, files));
    for (nlohmann::json& page : page_entries) pages.push_back(std::move(page));
    nlohmann::json views = nlohmann::json::array();
    for (const View& v : package.views)
        views.push_back(manifest_io::view_json(v));
    nlohmann::json manifest = manifest_io::manifest_header(package, package.parameters, version);
    manifest["sphere"] = {{"center", manifest_io::vec3_json(package.center)}, {"radius", package.radius}};
    manifest["half_extent"] = package.half_extent();
    if (package.alpha_tested) manifest["alpha_tested"] = true; // only then: other packages stay as they were
    if (!package.proxy_planes.empty()) {
        nlohmann::json planes = nlohmann::json::array();
        for (const glm::vec4& p : package.proxy_planes) planes.push_back({p.x, p.y, p.z, p.w});
        manifest["proxy_planes"] = planes;
    }
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
        // packages from before --compression hold PNG pages, and from before --depth-bits 8-bit depth
        nlohmann::json patched, patched_again;
        const nlohmann::json& settings = manifest_io::with_setting_default(
            manifest_io::with_setting_default(manifest, "compression", "none", patched), "depth_bits", 8, patched_again);
        package->parameters = manifest_io::read_settings(in, settings, registration().bake_options);
        package->settings = settings_from(package->parameters);
        if (Status valid = check_settings(package->settings); !valid) in.fail("bake", valid.message());
        if (package->settings.depth_bits == 0) in.fail("bake.depth_bits", "is 0, which only a bake resolves (8..16)");
        const BakeSettings& s = package->settings;
        const nlohmann::json& sphere = in.member(manifest, "sphere", "");
        package->center = in.vec3(sphere, "center", "sphere.");
        package->radius = float(in.number(sphere, "radius", "sphere.", 1e-30, 1e30));
        if (manifest.contains("alpha_tested")) { // optional (issue #14): absent means false
            if (!manifest["alpha_tested"].is_boolean()) in.fail("alpha_tested", "is not true or false");
            else package->alpha_tested = manifest["alpha_tested"].get<bool>();
        }
        if (manifest.contains("proxy_planes")) { // optional (issue #17): without it the renderer draws the prism
            const nlohmann::json& planes = manifest["proxy_planes"];
            if (!planes.is_array() || planes.size() > 64) in.fail("proxy_planes", "is not an array of at most 64 planes");
            for (std::size_t k = 0; k < planes.size(); ++k) {
                const std::string where = "proxy_planes[" + std::to_string(k) + "]";
                if (!planes[k].is_array() || planes[k].size() != 4 ||
                    !std::all_of(planes[k].begin(), planes[k].end(), [](const nlohmann::json& v) { return v.is_number(); }))
                    in.fail(where, "is not [nx, ny, nz, offset]");
                const glm::vec4 p(planes[k][0].get<float>(), planes[k][1].get<float>(), planes[k][2].get<float>(),
                                  planes[k][3].get<float>());
                if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !std::isfinite(p.w) ||
                    std::abs(glm::length(glm::vec3(p)) - 1.0f) > 1e-3f)
                    in.fail(where, "is not a finite plane with a unit normal");
                package->proxy_planes.push_back(p);
            }
        }
        const nlohmann::json& files = in.member(manifest, "files", "");
        if (!files.is_object()) in.fail("files", "is not an object");
        const nlohmann::json& pages = in.member(manifest, "pages", "");
        if (!pages.is_array() || pages.size() > 4096) in.fail("pages", "is not an array of at most 4096 pages");
        if (pages.empty()) in.fail("pages", "is empty: the package draws nothing");
        auto has_pbr = [&](std::size_t k) { return pages[k].is_object() && (pages[k].contains("orm") || pages[k].contains("emission")); };
        const bool pbr = has_pbr(0);
        for (std::size_t k = 1; k < pages.size(); ++k)
            if (has_pbr(k) != pbr) in.fail("pages[" + std::to_string(k) + "].orm", "is on some pages only: every page or none");
        if (pbr && !package->has_surface()) in.fail("pages[0].orm", "needs surface maps (bake.maps \"surface\")");
        const std::size_t count = pages.size();
        const bool surface_blocks = package->has_surface() && s.compression != "none";
        package->color_pages.resize(count);
        package->color_bc3.resize(s.compression == "bc-color" ? count : 0);
        package->normal_depth_pages.resize(package->has_surface() ? count : 0);
        package->normal_bc5.resize(surface_blocks ? count : 0);
        package->depth_pages.resize(package->has_fine_depth() ? count : 0);
        package->orm_pages.resize(pbr ? count : 0);
        package->emission_pages.resize(pbr ? count : 0);
        // the pages side by side (manifest_io::read_each)
        manifest_io::read_each(count, [&](std::size_t k) {
            std::string where = "pages[" + std::to_string(k) + "].";
            if (s.compression == "bc-color")
                read_color_blocks(in, files, in.string(pages[k], "color", where), s.page_size, *package, k);
            else
                package->color_pages[k] = manifest_io::read_image8(in, files, in.string(pages[k], "color", where), s.page_size, s.page_size);
            if (surface_blocks)
                read_surface_blocks(in, files, in.string(pages[k], "normal", where), in.string(pages[k], "depth", where),
                                    s.page_size, *package, k);
            else if (package->has_surface()) {
                package->normal_depth_pages[k] =
                    manifest_io::read_image8(in, files, in.string(pages[k], "normal_depth", where), s.page_size, s.page_size);
                if (s.depth_bits > 8) read_fine_depth(in, files, in.string(pages[k], "depth", where), s.page_size, *package, k);
            }
            if (pbr) {
                package->orm_pages[k] = manifest_io::read_image8(in, files, in.string(pages[k], "orm", where), s.page_size, s.page_size);
                package->emission_pages[k] =
                    manifest_io::read_image8(in, files, in.string(pages[k], "emission", where), s.page_size, s.page_size);
            }
        });
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
