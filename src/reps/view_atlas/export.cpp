// Export of a view atlas (docs/FORMAT.md, "Export: view atlas"): the (hemi-)octahedral views as
// the grid atlas today's impostor shaders read (reps/common/grid_atlas.h: Brucks's Impostor Baker
// for Unreal, 2018; Amplify Impostors; Godot octahedral impostors), and a camera-facing quad node
// carrying in its extras what such a shader needs. Steps: check that the package was baked on a
// grid (icosahedral views have no grid layout), resample the stored crops into the atlas, build the
// quad (textured, for a plain viewer, with the frame that looks along +Z), describe the frames;
// then a convex hull as a second node an impostor shader can draw on instead of the quad, textured
// with the same front frame: the baked proxy (hull.h proxy_polytope, issue #17) moved out by a
// texel, or for packages baked before it the atlas hull (hull.h atlas_hull, issue #16).
#include "reps/view_atlas/hull.h"
#include "reps/view_atlas/view_atlas.h"
#include "reps/common/grid_atlas.h"
#include "reps/common/package_cast.h"

#include <standin/export.h>
#include <standin/files.h>

#include <algorithm>
#include <cstdio>

namespace standin::view_atlas {

namespace {

constexpr int k_grid_export_atlas_cap = 4096;

// The hull as a flat-shaded mesh (each face its own corners, its normal), textured like the quad
// with the front frame: a point's UV is its projection into that frame (through the capture camera
// for perspective packages), so a plain viewer shows the model from the front on the hull's front faces.
ExportMesh hull_mesh(const ViewAtlasPackage& package, const ConvexPolytope& hull, const View& front, int fi, int fj)
{
    const BakeSettings& s = package.settings;
    const float h = package.half_extent(), eye = package.capture_distance();
    ExportMesh mesh;
    mesh.name = "hull";
    for (std::size_t f = 0; f < hull.faces.size(); ++f) {
        const std::uint32_t first = std::uint32_t(mesh.positions.size());
        for (std::uint32_t v : hull.faces[f]) {
            const glm::vec3 p(hull.vertices[v]);
            const glm::vec3 q = p - package.center;
            float scale = 1.0f / h;
            if (s.projection == "perspective") scale *= eye / std::max(eye - glm::dot(q, front.direction), 1e-6f * eye);
            const float fs = std::clamp(glm::dot(q, front.axis_u) * scale * 0.5f + 0.5f, 0.0f, 1.0f);
            const float ft = std::clamp(glm::dot(q, front.axis_v) * scale * 0.5f + 0.5f, 0.0f, 1.0f);
            mesh.positions.push_back(p);
            mesh.normals.push_back(glm::vec3(hull.face_normals[f]));
            mesh.uvs.push_back({(float(fi) + fs) / float(s.frames), (float(fj) + ft) / float(s.frames)});
        }
        for (std::uint32_t k = 1; k + 1 < hull.faces[f].size(); ++k) mesh.indices.insert(mesh.indices.end(), {first, first + k, first + k + 1});
    }
    mesh.base_color_texture = 0;
    mesh.alpha_mode = "MASK";
    mesh.double_sided = false; // closed and convex: the back faces would show the frame mirrored
    return mesh;
}

} // namespace

std::vector<OptionSpec> export_options()
{
    return {
        integer_option("atlas-size", 0, 0, 16384,
                       "Side of the square grid atlas, texels (view-atlas: each frame gets atlas-size / frames); 0: "
                       "frames x capture resolution (one texel per capture pixel), at most 4096"),
        integer_option("frames", 0, 0, 64,
                       "Frames per side of the grid atlas; 0: as baked (a view atlas exports the grid it was baked "
                       "with: bake with --layout octahedral --frames N)"),
    };
}

Result<ExportScene> export_scene(const Package& base, const Options& options)
{
    const auto& package = reps::package_cast<ViewAtlasPackage>(base);
    const BakeSettings& s = package.settings;
    const std::string name = quoted(package.directory.empty() ? std::string("package") : package.directory);
    if (s.layout != "octahedral" && s.layout != "hemi-octahedral")
        return error(StatusCode::unsupported, name + ": a grid atlas needs a view atlas baked with --layout octahedral "
                                                     "or hemi-octahedral (this one is " + s.layout +
                                                     "; e.g. standin bake MODEL -r view-atlas --layout octahedral --frames 16)");
    const int frames = options.integer("frames");
    if (frames != 0 && frames != s.frames)
        return error(StatusCode::invalid_argument, "--frames " + std::to_string(frames) + ": " + name + " was baked with " +
                                                       std::to_string(s.frames) + " frames; re-bake with --frames " +
                                                       std::to_string(frames) + " or leave --frames out");
    // By default one texel per capture pixel: resampling to fewer texels (2048 for 16 frames of
    // 192 pixels, the default until issue #16) rounds cut-outs off and fills the gaps between
    // leaves, which no shader can undo (docs/RESULTS.md "Foliage in the web viewer"). 4096 is the
    // largest texture every WebGL2 and mobile GPU of today takes; a multiple of frames keeps frame
    // borders on texel borders, which the reference shader's texel walk assumes.
    int size = options.integer("atlas-size");
    if (size == 0) size = std::min(s.frames * s.resolution, k_grid_export_atlas_cap / s.frames * s.frames);
    if (size < s.frames)
        return error(StatusCode::invalid_argument, "--atlas-size " + std::to_string(size) + ": smaller than the " +
                                                       std::to_string(s.frames) + " frames per side");

    reps::GridAtlasInput input;
    input.views = &package.views;
    input.color_pages = &package.color_pages;
    input.normal_depth_pages = package.has_surface() ? &package.normal_depth_pages : nullptr;
    input.resolution = s.resolution;
    input.frames = s.frames;
    Result<reps::GridAtlas> atlas = reps::make_grid_atlas(input, size);
    if (!atlas) return atlas.status();

    ExportScene scene;
    Result<ExportTexture> color = make_export_texture("grid_color", atlas->color);
    if (!color) return color.status();
    scene.textures.push_back(std::move(*color));
    int normal_depth_texture = -1;
    if (!atlas->normal_depth.empty()) {
        Result<ExportTexture> nd = make_export_texture("grid_normal_depth", atlas->normal_depth);
        if (!nd) return nd.status();
        scene.textures.push_back(std::move(*nd));
        normal_depth_texture = 1;
    }
    // a PBR package's ORM (linear) and emission (sRGB) pages in the same grid (issue #14), read by
    // the quad's glTF material; the reference shader takes them from the extras
    int orm_texture = -1, emission_texture = -1;
    if (package.has_pbr()) {
        for (bool orm : {true, false}) {
            reps::GridAtlasInput pbr_input = input;
            pbr_input.color_pages = orm ? &package.orm_pages : &package.emission_pages;
            pbr_input.normal_depth_pages = nullptr;
            pbr_input.color_srgb = !orm;
            Result<reps::GridAtlas> grid = reps::make_grid_atlas(pbr_input, size);
            if (!grid) return grid.status();
            Result<ExportTexture> texture = make_export_texture(orm ? "grid_orm" : "grid_emission", grid->color);
            if (!texture) return texture.status();
            (orm ? orm_texture : emission_texture) = int(scene.textures.size());
            scene.textures.push_back(std::move(*texture));
        }
    }

    // the quad through the centre facing +Z, showing the frame that looks along +Z (camera right +X,
    // image down -Y there), so that a viewer without the impostor shader still shows the model
    const float h = package.half_extent();
    const glm::vec3 c = package.center;
    int fi = 0, fj = 0;
    reps::grid_frame(s.layout, s.frames, glm::vec3(0.0f, 0.0f, 1.0f), fi, fj);
    const View& front = package.views[std::size_t(fj) * s.frames + fi];
    ExportMesh quad;
    quad.name = "impostor";
    const glm::vec2 corner[4] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (const glm::vec2& k : corner) {
        quad.positions.push_back(c + h * (k.x * front.axis_u - k.y * front.axis_v));
        quad.normals.push_back(front.direction);
        quad.uvs.push_back({(float(fi) + 0.5f * (k.x + 1.0f)) / float(s.frames), (float(fj) + 0.5f * (1.0f - k.y)) / float(s.frames)});
    }
    quad.indices = {0, 1, 2, 0, 2, 3};
    quad.base_color_texture = 0;
    quad.alpha_mode = "MASK";
    quad.double_sided = true;
    use_pbr_maps(quad, orm_texture, emission_texture);
    nlohmann::json axes = nlohmann::json::array();
    for (const View& v : package.views)
        axes.push_back({v.axis_u.x, v.axis_u.y, v.axis_u.z, v.axis_v.x, v.axis_v.y, v.axis_v.z, v.direction.x, v.direction.y, v.direction.z});
    nlohmann::json block = {{"role", "grid-impostor"},
                            {"layout", s.layout},
                            {"frames", s.frames},
                            {"atlas_size", size},
                            {"color_texture", 0},
                            {"color", s.maps == "lit" ? "lit" : "albedo"},
                            {"center", {c.x, c.y, c.z}},
                            {"radius", package.radius},
                            {"half_extent", h},
                            {"projection", s.projection},
                            {"capture_resolution", s.resolution},
                            {"frame_axes", axes},
                            {"alpha_tested", package.alpha_tested}};
    if (s.projection == "perspective") {
        block["fov"] = s.fov;
        block["capture_distance"] = package.capture_distance();
    }
    if (orm_texture >= 0) block["orm_texture"] = orm_texture, block["emission_texture"] = emission_texture;
    if (normal_depth_texture >= 0) {
        block["normal_depth_texture"] = normal_depth_texture;
        block["depth_near"] = package.radius;        // depth 0: this far in front of the centre
        block["depth_scale"] = 2.0f * package.radius; // depth 1: depth_near - depth_scale
    }
    quad.extras["standin"] = block;
    scene.meshes.push_back(std::move(quad));

    // the hull: the same atlas and frames, drawn on a convex proxy instead of the quad. The baked
    // proxy planes hold every point of the model; the captured views' atlas hull, tighter, cuts a
    // sheet seen edge on (it covers no texel of that view) and is only the fallback for packages
    // without proxy planes. The planes move out by a texel of the atlas (or of the capture, if
    // coarser): a shader draws each texel whole, up to half a texel past the model's outline.
    ClipStats stats;
    const double atlas_texel = capture_texel(package) * double(std::max(s.resolution * s.frames, size)) / double(size);
    const bool baked_proxy = !package.proxy_planes.empty();
    ConvexPolytope hull = baked_proxy ? proxy_polytope(package, atlas_texel) : atlas_hull(package, &stats);
    if (!hull.empty()) {
        ExportMesh mesh = hull_mesh(package, hull, front, fi, fj);
        use_pbr_maps(mesh, orm_texture, emission_texture);
        block["role"] = "grid-impostor-hull";
        block["quad_node"] = "impostor";
        mesh.extras["standin"] = block;
        // its screen area against the quad's (2h x 2h), orthographic, over the frames' directions
        double area_min = 1e30, area_max = 0.0, area_sum = 0.0;
        for (const View& v : package.views) {
            const double a = hull.projected_area(glm::dvec3(v.direction)) / (4.0 * double(h) * double(h));
            area_min = std::min(area_min, a), area_max = std::max(area_max, a), area_sum += a;
        }
        char source[80];
        if (baked_proxy) std::snprintf(source, sizeof source, "the %zu baked proxy planes", package.proxy_planes.size());
        else std::snprintf(source, sizeof source, "%d of %d view planes cut", stats.cut, stats.planes);
        char note[300];
        std::snprintf(note, sizeof note,
                      "hull: %zu triangles, %zu faces (%s); its screen area is %.1f %% of the quad's on average over "
                      "the frames' directions (%.1f-%.1f %%, orthographic)",
                      hull.triangle_count(), hull.faces.size(), source, 100.0 * area_sum / double(package.views.size()),
                      100.0 * area_min, 100.0 * area_max);
        scene.notes.push_back(note);
        scene.meshes.push_back(std::move(mesh));
    }

    std::uint64_t texture_bytes = 0;
    for (const ExportTexture& t : scene.textures) texture_bytes += export_texture_bytes(t);
    char line[240];
    std::snprintf(line, sizeof line, "grid atlas %dx%d, %dx%d %s frames of %.1f texels, %s: %.1f MiB on the GPU (RGBA8 with mips)",
                  size, size, s.frames, s.frames, s.layout.c_str(), double(size) / s.frames,
                  normal_depth_texture >= 0 ? (orm_texture >= 0 ? "colour+alpha, normal+depth, ORM and emission" : "colour+alpha and normal+depth")
                                            : "colour+alpha",
                  double(texture_bytes) / (1 << 20));
    scene.notes.push_back(line);
    return scene;
}

} // namespace standin::view_atlas
