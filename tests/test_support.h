// Helpers shared by the tests: paths, running the CLI, one GL context per test process.
#pragma once

#include <standin/mesh.h>
#include <standin/package.h>
#include <standin/render.h>

#include <glm/vec4.hpp>
#include <nlohmann/json.hpp>

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace standin::test {

std::string source_dir();  // repository root
std::string cli_path();    // the built `standin` executable
// A new empty directory under the system temp dir, unique to this test process and name.
std::string fresh_directory(const std::string& name);

struct CommandResult {
    int exit_code = -1;
    std::string out, err;
};
// Lines in a program's output (newlines counted).
int line_count(const std::string& text);
// A JSON file the test wrote or had written; fails the test (and returns null) when unreadable.
nlohmann::json read_json(const std::string& path);
// Component-wise EXPECT_NEAR of two colours or points.
void expect_near(glm::vec4 a, glm::vec4 b, float tolerance = 1e-5f);

// Runs a shell command line, capturing stdout and stderr.
CommandResult run_command(const std::string& command_line);
// Runs `standin ARGS`.
CommandResult run_cli(const std::string& arguments);

// The process-wide headless GL context, created on first use; fails the test if none exists.
GpuContext& gpu_context();

// Bakes `mesh` as `representation` (registry name) with bake parameters NAME=VALUE on one thread;
// fails the test and returns null when the baker refuses.
std::unique_ptr<Package> bake(const Mesh& mesh, const std::string& representation,
                              const std::vector<std::pair<std::string, std::string>>& values);

} // namespace standin::test
