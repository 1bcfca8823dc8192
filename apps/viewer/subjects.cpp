// The viewer's subjects: the original model and its packages, loaded and drawn by the same library
// functions as `standin render` (import_mesh + make_mesh_renderer, read_package +
// find_representation(...)->make_renderer), and the camera that frames them all alike.
#include "viewer_state.h"


#include <algorithm>
#include <cassert>
#include <cstdio>
#include <filesystem>

namespace standin::viewer {

namespace fs = std::filesystem;

static std::string base_name(const std::string& path)
{
    fs::path p(path);
    if (!p.has_filename()) p = p.parent_path(); // "bunny.standin/"
    return p.filename().string();
}

static Result<Subject> load_model(const std::string& path)
{
    Result<Mesh> mesh = import_mesh(path, nullptr, ImportOptions{.isolate_parser = true});
    if (!mesh) return mesh.status();
    Subject subject;
    subject.path = path;
    subject.label = "original: " + base_name(path);
    subject.contents = std::to_string(mesh->triangle_count()) + " triangles";
    subject.mesh = std::move(*mesh);
    return subject;
}

static Result<Subject> load_package(const std::string& path, const OptionValues& options)
{
    Result<std::unique_ptr<Package>> package = read_package(path);
    if (!package) return package.status();
    Subject subject;
    subject.path = path;
    subject.package = std::move(*package);
    subject.options.values = options.only(representation_of(*subject.package).render_options);
    subject.contents = summarise_package(*subject.package).headline; // what `standin info` says
    return subject;
}

Status load_subjects(const std::vector<std::string>& inputs, const OptionValues& options, ViewerState& state)
{
    if (inputs.empty()) return error(StatusCode::invalid_argument, "view: give a model and/or packages");
    // a directory is a package, a file is the model (at most one, shown first)
    std::vector<Subject> packages;
    std::optional<Subject> original;
    for (const std::string& input : inputs) {
        std::error_code ec;
        if (fs::is_directory(input, ec)) {
            Result<Subject> subject = load_package(input, options);
            if (!subject) return subject.status();
            packages.push_back(std::move(*subject));
        } else {
            if (original)
                return error(StatusCode::invalid_argument,
                             input + ": one model at most (already showing " + original->path + ")");
            Result<Subject> subject = load_model(input);
            if (!subject) return subject.status();
            original = std::move(*subject);
        }
    }

    // every option given must apply to some package
    for (const auto& [name, value] : options.items()) {
        bool applies = std::any_of(packages.begin(), packages.end(), [&](const Subject& p) { return p.options.values.has(name); });
        if (!applies) return error(StatusCode::invalid_argument, "--" + name + " does not apply to any package given");
    }

    // packages of another model are shown, with a warning
    SourceInfo source;
    if (original) {
        Result<SourceInfo> described = describe_source(original->path, *original->mesh);
        if (described) source = *described;
    }
    for (std::size_t i = 0; i < packages.size(); ++i) {
        Subject& p = packages[i];
        p.label = "package " + std::to_string(i + 1) + ": " + base_name(p.path) + " (" + p.representation() + ")";
        if (original && !source.content_hash.empty() && p.package->source.content_hash != source.content_hash) {
            state.message = p.path + " was baked from " + p.package->source.file_name + ", not " + base_name(original->path);
            std::fprintf(stderr, "standin: warning: %s\n", state.message.c_str());
        }
    }

    // frame everything as the model (packages store their source's bounds)
    if (original) {
        state.sphere = original->mesh->bounding_sphere();
    } else {
        state.sphere = bounding_sphere_of(packages.front().package->source.bounds);
    }
    state.subjects.clear();
    state.original = original ? 0 : -1;
    if (original) state.subjects.push_back(std::move(*original));
    for (Subject& p : packages) state.subjects.push_back(std::move(p));
    state.shown = 0;
    state.stand_in = package_subject(state, 1);
    return Status::ok();
}

Status build_renderer(Subject& subject)
{
    Result<std::unique_ptr<Renderer>> made = error(StatusCode::gpu_error, "no renderer");
    if (subject.is_original()) {
        made = make_mesh_renderer(*subject.mesh);
    } else {
        made = make_package_renderer(*subject.package, subject.options);
    }
    if (!made) return error(made.status().code(), subject.path + ": " + made.status().message());
    subject.renderer = std::move(*made);
    return Status::ok();
}

static bool draws(const Subject& subject, DebugView view)
{
    if (subject.is_original()) return false;
    const std::vector<DebugView>& views = representation_of(*subject.package).debug_views;
    return std::find(views.begin(), views.end(), view) != views.end();
}

std::vector<std::string> available_debug_views(const ViewerState& state)
{
    std::vector<std::string> names;
    for (int v = 1; v < k_debug_view_count; ++v)
        if (std::any_of(state.subjects.begin(), state.subjects.end(), [&](const Subject& s) { return draws(s, DebugView(v)); }))
            names.push_back(debug_view_name(DebugView(v)));
    if (state.original >= 0 && state.stand_in >= 0) names.push_back("holes");
    return names;
}

Status set_debug_view(ViewerState& state, const std::string& name)
{
    // "holes" compares ordinary pictures; the renderers' own views are theirs
    DebugView view = DebugView::none;
    if (name != "holes") {
        Result<DebugView> parsed = parse_debug_view(name);
        if (!parsed) return parsed.status();
        view = *parsed;
        bool drawn = std::any_of(state.subjects.begin(), state.subjects.end(), [&](const Subject& s) { return draws(s, view); });
        if (view != DebugView::none && !drawn)
            return error(StatusCode::invalid_argument, "debug " + name + ": no package shown draws it");
    }
    state.debug_view = name;
    Status result;
    for (Subject& subject : state.subjects) {
        if (subject.is_original()) continue;
        DebugView wanted = draws(subject, view) ? view : DebugView::none;
        if (subject.options.debug_view == wanted) continue;
        DebugView previous = subject.options.debug_view;
        subject.options.debug_view = wanted;
        if (!subject.renderer) continue; // not built yet: built later with this view
        if (Status s = build_renderer(subject); !s) {
            subject.options.debug_view = previous;
            result = s;
        }
    }
    return result;
}

Status set_package_option(Subject& subject, const std::string& name, const std::string& value)
{
    assert(!subject.is_original());
    const Representation& representation = representation_of(*subject.package);
    bool declared = std::any_of(representation.render_options.begin(), representation.render_options.end(),
                                [&](const OptionSpec& s) { return s.name == name; });
    if (!declared) return error(StatusCode::invalid_argument, name + ": not an option of " + representation.name + " packages");
    RenderOptions previous = subject.options;
    subject.options.values.set(name, value);
    if (Status s = build_renderer(subject); !s) {
        subject.options = previous;
        return s;
    }
    return Status::ok();
}

Status reload_shaders(ViewerState& state, const std::string& shader_directory)
{
    if (!fs::is_directory(shader_directory))
        return error(StatusCode::not_found, "reload: no shader sources at " + shader_directory +
                                                " (set STANDIN_SHADER_DIR to the src/ folder of a source tree)");
    set_shader_source_directory(shader_directory);
    Status result;
    for (Subject& subject : state.subjects)
        if (Status s = build_renderer(subject); !s && result) result = s;
    return result;
}

int package_count(const ViewerState& state)
{
    return int(state.subjects.size()) - (state.original >= 0 ? 1 : 0);
}

int package_subject(const ViewerState& state, int n)
{
    if (n < 1 || n > package_count(state)) return -1;
    return n - 1 + (state.original >= 0 ? 1 : 0);
}

Camera current_camera(const ViewerState& state, float aspect)
{
    // pan moves the orbit centre in the camera's plane
    Camera unpanned = orbit_camera(state.sphere, state.orbit, aspect);
    if (state.pan == glm::vec2(0.0f)) return unpanned;
    glm::mat4 world_from_view = glm::inverse(unpanned.view_from_world);
    glm::vec3 right = glm::vec3(world_from_view[0]), up = glm::vec3(world_from_view[1]);
    BoundingSphere moved = state.sphere;
    moved.center += (right * state.pan.x + up * state.pan.y) * state.sphere.radius;
    return orbit_camera(moved, state.orbit, aspect);
}

Light current_light(const ViewerState& state, const Camera& camera)
{
    if (state.light_follows_camera) return default_light(camera);
    return light_from_angles(state.light_azimuth, state.light_elevation);
}

void reset_view(ViewerState& state)
{
    state.orbit = state.home;
    state.pan = glm::vec2(0.0f);
    state.light_follows_camera = state.home_light_follows;
    state.light_azimuth = state.home_light_azimuth;
    state.light_elevation = state.home_light_elevation;
}

void show_subject(ViewerState& state, int index)
{
    if (index < 0 || index >= int(state.subjects.size())) return;
    state.shown = index;
    if (!state.subjects[index].is_original()) state.stand_in = index;
}

} // namespace standin::viewer
