// The interactive viewer behind `standin view`: a GLFW window with an OpenGL 4.5 core context,
// the original model and any number of its packages drawn by the same renderers the CLI uses,
// Dear ImGui panels, and a script mode for unattended runs (script.h).
#pragma once

#include <standin/camera.h>
#include <standin/render.h>
#include <standin/status.h>

#include <cmath>
#include <string>
#include <vector>

namespace standin::viewer {

struct ViewerArgs {
    std::vector<std::string> inputs; // at most one model file, any number of NAME.standin packages
    std::string script_path;         // empty: interactive
    int window_width = 800, window_height = 600;
    int render_width = 0, render_height = 0; // 0: follow the window
    OrbitView view;                  // the initial camera, and where `reset` returns to
    float light_azimuth = NAN, light_elevation = NAN; // NAN: the protocol light, following the camera
    OptionValues options;            // initial run-time options, given to every package that declares them
    std::string debug_view;          // initial debug view: a shared one (debug_view.h), "holes" or empty
};

// Runs the viewer until the window closes, `quit`, or the end of the script. Everything is checked
// before a window opens: the script parses, the inputs load. Errors (one line each):
// invalid_argument for a bad script line or option (naming the script line), not_found / bad_data
// for inputs (naming the file), unsupported when there is no display ("no display for the viewer
// ...; use 'standin render' ...") or gpu_error when no OpenGL 4.5 core window can be made.
Status run_viewer(const ViewerArgs& args);

} // namespace standin::viewer
