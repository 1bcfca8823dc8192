// The representations' declared options (include/standin/options.h) on a subcommand's command
// line: typed CLI11 options, grouped per representation, defaults shown in --help. Nothing here
// knows a representation: everything comes from representations().
#pragma once

#include <standin/options.h>
#include <standin/package.h>

#include <CLI/CLI.hpp>

#include <memory>
#include <span>
#include <string>
#include <vector>

namespace standin::cli {

enum class OptionKind { bake, render, export_ };

class DeclaredOptions {
public:
    // Adds every registered representation's options of `kind` to `command`. An option several
    // representations declare appears once, its help naming each one's meaning.
    void add_to(CLI::App& command, OptionKind kind);
    // What was given on the command line, after parsing.
    OptionValues given() const;
    // " --NAME VALUE" for each given option: the part of a command line that reproduces them.
    std::string command_line() const;

private:
    struct Entry {
        std::string name;
        std::string value;          // options
        bool flag = false;          // given as --NAME or --no-NAME
        std::string flag_value;     // what the flag sets ("on" or "off")
        CLI::Option* option = nullptr;
    };
    std::vector<std::unique_ptr<Entry>> entries_;
};

// Run-time options must apply to something at hand: each given name must be declared by one of
// `representations` (the packages' representations; none for a model, whose renderer has no
// options). "--style does not apply to enhanced-billboards packages (view-atlas declares it)".
Status check_render_options_apply(const RenderOptions& options,
                                  std::span<const Representation* const> representations);

// --debug-view NAME over the shared debug views (render.h), for render and view.
void add_debug_view_option(CLI::App& command, std::string& name, bool with_holes = false);

} // namespace standin::cli
