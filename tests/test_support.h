// Helpers shared by the tests: paths, running the CLI, one GL context per test process.
#pragma once

#include <standin/render.h>

#include <string>

namespace standin::test {

std::string source_dir();  // repository root
std::string cli_path();    // the built `standin` executable
// A new empty directory under the system temp dir, unique to this test process and name.
std::string fresh_directory(const std::string& name);

struct CommandResult {
    int exit_code = -1;
    std::string out, err;
};
// Runs a shell command line, capturing stdout and stderr.
CommandResult run_command(const std::string& command_line);
// Runs `standin ARGS`.
CommandResult run_cli(const std::string& arguments);

// The process-wide headless GL context, created on first use; fails the test if none exists.
GpuContext& gpu_context();

} // namespace standin::test
