// One add_<name>_command per subcommand (cmd_<name>.cpp): it declares the options on its own
// CLI::App and returns the function that runs it once parsed.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>

namespace standin::cli {

using CommandRun = std::function<int()>;

CommandRun add_info_command(CLI::App& root);
CommandRun add_render_command(CLI::App& root);
CommandRun add_generate_command(CLI::App& root);
CommandRun add_bake_command(CLI::App& root);
CommandRun add_eval_command(CLI::App& root);
CommandRun add_bench_command(CLI::App& root);
CommandRun add_view_command(CLI::App& root);
CommandRun add_export_command(CLI::App& root);

} // namespace standin::cli
