// standin: turn a detailed polygon model into lightweight stand-ins, and measure them.
// main only routes to the subcommands (cmd_<name>.cpp).
#include "commands.h"
#include "common.h"

#include <standin/package.h>

#include <cstdio>
#include <malloc.h>
#include <exception>
#include <map>
#include <new>
#include <string>

int main(int argc, char** argv)
{
    // Bakes allocate and free per-texel and per-face arrays of tens to hundreds of MB per capture
    // (billboards: 5 captures a billboard). glibc maps blocks over its threshold (at most 32 MB)
    // afresh and unmaps them on free, so each one page-faulted its memory in again, zeroed by the
    // kernel and then by the program: 37% of the 20,000-face bush's bake. From the heap, and not
    // trimmed back, freed blocks are reused.
    mallopt(M_MMAP_MAX, 0);
    mallopt(M_TRIM_THRESHOLD, 1 << 30);
    using namespace standin::cli;
    std::string names;
    for (const standin::Representation& r : standin::representations())
        names += std::string(names.empty() ? "" : ", ") + r.name;
    CLI::App app{"standin: bakes polygon models into real-time stand-ins (" + names + "), renders them, and "
                 "measures their fidelity and speed.\nRun 'standin COMMAND --help' for the options of one command."};
    app.require_subcommand(1);
    // -v and -q may follow the subcommand too
    app.fallthrough();
    Verbosity verbosity;
    app.add_flag("-v,--verbose", verbosity.verbose, "Print informational messages on stderr");
    app.add_flag("-q,--quiet", verbosity.quiet, "Print errors only (no progress, no 'wrote ...')");
    app.set_version_flag("--version", "standin 0.1.0");

    std::map<std::string, CommandRun> runs;
    auto route = [&](const char* name, CommandRun run) { runs[name] = std::move(run); };
    route("info", add_info_command(app));
    route("render", add_render_command(app));
    route("generate", add_generate_command(app));
    route("bake", add_bake_command(app));
    route("eval", add_eval_command(app));
    route("bench", add_bench_command(app));
    route("view", add_view_command(app));
    route("export", add_export_command(app));

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::string message = e.what();
        return fail(message + " (see 'standin --help')");
    }
    install_log_sink(verbosity);
    // the boundary: whatever a command did not turn into a Status is still one line and exit 2
    try {
        for (CLI::App* sub : app.get_subcommands()) {
            auto it = runs.find(sub->get_name());
            if (it != runs.end()) return it->second();
        }
    } catch (const std::bad_alloc&) {
        return fail("out of memory (STANDIN_MEMORY_LIMIT sets the budget that refuses such inputs up front)");
    } catch (const std::exception& e) {
        return fail(std::string("unexpected error: ") + e.what());
    }
    return fail("no command given (see 'standin --help')");
}
