#include "test_support.h"

#include <gtest/gtest.h>

#include <standin/files.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

namespace standin::test {

namespace fs = std::filesystem;

std::string source_dir()
{
    const char* dir = std::getenv("STANDIN_SOURCE_DIR");
    return dir ? dir : STANDIN_TEST_SOURCE_DIR;
}

std::string cli_path()
{
    const char* path = std::getenv("STANDIN_CLI");
    return path ? path : STANDIN_TEST_CLI;
}

int line_count(const std::string& text) { return int(std::count(text.begin(), text.end(), '\n')); }

nlohmann::json read_json(const std::string& path)
{
    Result<std::string> text = read_file(path);
    EXPECT_TRUE(text.is_ok()) << path;
    return text ? nlohmann::json::parse(*text) : nlohmann::json();
}

void expect_near(glm::vec4 a, glm::vec4 b, float tolerance)
{
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(a[i], b[i], tolerance) << "component " << i;
}

std::string fresh_directory(const std::string& name)
{
    fs::path dir = fs::temp_directory_path() / ("standin_test_" + std::to_string(::getpid()) + "_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir.string();
}

static std::string slurp(const fs::path& path)
{
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

CommandResult run_command(const std::string& command_line)
{
    static int counter = 0;
    fs::path base = fs::temp_directory_path() / ("standin_cmd_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    std::string out = base.string() + ".out", err = base.string() + ".err";
    std::string full = command_line + " >" + out + " 2>" + err + " </dev/null";
    int status = std::system(full.c_str());
    CommandResult result;
    result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    result.out = slurp(out);
    result.err = slurp(err);
    fs::remove(out);
    fs::remove(err);
    return result;
}

CommandResult run_cli(const std::string& arguments) { return run_command(cli_path() + " " + arguments); }

GpuContext& gpu_context()
{
    static Result<std::unique_ptr<GpuContext>> context = create_headless_context();
    if (!context) {
        ADD_FAILURE() << context.status().message();
        std::abort();
    }
    return **context;
}

std::unique_ptr<Package> bake(const Mesh& mesh, const std::string& representation,
                              const std::vector<std::pair<std::string, std::string>>& values)
{
    SourceInfo source;
    source.bounds = mesh.bounds();
    OptionValues parameters;
    for (const auto& [name, value] : values) parameters.set(name, value);
    const Representation* r = find_representation(representation);
    EXPECT_TRUE(r) << representation;
    if (!r) return nullptr;
    Result<std::unique_ptr<Package>> package = bake_package(*r, mesh, source, parameters, {}, 1);
    EXPECT_TRUE(package.is_ok()) << package.status().message();
    return package.is_ok() ? std::move(*package) : nullptr;
}

} // namespace standin::test
