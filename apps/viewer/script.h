// The viewer's script language: one command per line, run in order between frames, so that the
// viewer can be driven (and tested) without a person. `#` starts a comment; blank lines are skipped.
//
//   camera AZIMUTH ELEVATION DISTANCE   orbit camera (degrees, degrees, relative to the base distance)
//   pan X Y                             shift the orbit centre, in bounding-sphere radii
//   projection perspective|orthographic
//   reset                               camera, pan and light back to their defaults
//   light AZIMUTH ELEVATION             fixed world-space light; `light camera` follows the camera
//   shadows on|off                      shadows of the light (a shadow map per subject and frame)
//   show original | show package N      N counts packages from 1 in command-line order
//   split on|off|side                   split screen (original left) or side by side
//   split-position F                    where the split lies, 0..1 of the width
//   debug NAME|off                      a shared debug view (parts, depth, normal, fetches, proxies,
//                                       level, error) or holes (against the model)
//   set OPTION VALUE                    a run-time option of the package shown, as declared by its
//                                       representation (`standin render --help` lists them)
//   resolution WxH | resolution window  render resolution, independent of the window
//   window WxH                          window size
//   panels on|off, overlay on|off       the control panels and the statistics overlay
//   reload                              rebuild shaders from the source tree
//   screenshot FILE.png                 the window as shown, overlay and panels included
//   wait FRAMES                         draw this many frames
//   quit
#pragma once

#include <standin/options.h>
#include <standin/status.h>

#include <span>

#include <string>
#include <string_view>
#include <vector>

namespace standin::viewer {

enum class ScriptOp {
    camera, pan, projection, reset, light, show, split, split_position, debug, set, resolution, window,
    panels, overlay, reload, screenshot, wait, quit, shadows,
};

// One parsed line. Which fields are meaningful depends on op:
//   camera: numbers[0..2]; pan, light: numbers[0..1] (light: word "camera" instead when it follows
//   the camera); split_position: numbers[0]; resolution, window: size (resolution: word "window"
//   with size 0x0 to follow the window); wait: count; show: word "original" or "package" with
//   count = N (1-based); projection, split, debug, panels, overlay, shadows: word (debug "off" is "");
//   set: word = option name, value = its value; screenshot: word = path.
struct ScriptCommand {
    ScriptOp op = ScriptOp::quit;
    int line = 0; // 1-based line in the script
    std::string word, value;
    float numbers[3] = {0.0f, 0.0f, 0.0f};
    int size[2] = {0, 0};
    int count = 0;
};

// The words `debug` takes: the shared debug views (render.h names), "holes" and "off".
std::vector<std::string> script_debug_views();

// Parses a whole script. Pure: no files, no GL. `options` are the run-time options `set` may name
// (every representation's declarations; a name may appear once per representation), and its value
// must satisfy one of them. The first bad line stops parsing with invalid_argument
// "NAME line N: MESSAGE", where NAME is `name` (the script's path).
Result<std::vector<ScriptCommand>> parse_script(std::string_view text, const std::string& name,
                                                std::span<const OptionSpec> options = {});

// Parses "WxH" (1..16384 each); false when it does not parse or lies out of range.
bool parse_size(std::string_view text, int& width, int& height);

} // namespace standin::viewer
