// files.h: names quoted onto one line, only regular files read, outputs that never replace inputs,
// package directories exchanged atomically, temporaries of dead processes removed.
#include <standin/files.h>
#include <standin/limits.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sys/stat.h>
#include <unistd.h>

namespace standin {
namespace {

namespace fs = std::filesystem;

std::string scratch(const std::string& name)
{
    fs::path dir = fs::temp_directory_path() / ("standin_files_test_" + std::to_string(::getpid()) + "_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir.string();
}

void write(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

TEST(Files, QuotedKeepsPlainNamesAndPutsOthersOnOneLine)
{
    EXPECT_EQ(quoted("data/bunny.ply"), "data/bunny.ply");
    EXPECT_EQ(quoted("my model.obj"), "\"my model.obj\"");
    EXPECT_EQ(quoted("new\nline.obj"), "\"new\\nline.obj\"");
    EXPECT_EQ(quoted("q\"b\\"), "\"q\\\"b\\\\\"");
    EXPECT_EQ(quoted(""), "\"\"");
    EXPECT_EQ(one_line("a\nb\tc"), "a\\nb\\tc");
    EXPECT_EQ(one_line(std::string(50, 'x'), 10), "xxxxxxx...");
}

TEST(Files, OnlyRegularFilesAreRead)
{
    std::string dir = scratch("regular");
    write(dir + "/a.txt", "hello");
    EXPECT_EQ(*read_file(dir + "/a.txt"), "hello");
    EXPECT_EQ(*read_file_head(dir + "/a.txt", 2), "he");
    ASSERT_EQ(::mkfifo((dir + "/pipe").c_str(), 0600), 0);
    Result<std::string> pipe = read_file(dir + "/pipe"); // must not block
    ASSERT_FALSE(pipe.is_ok());
    EXPECT_NE(pipe.status().message().find("FIFO"), std::string::npos);
    EXPECT_FALSE(read_file("/dev/zero").is_ok());
    EXPECT_FALSE(read_file(dir).is_ok());
    fs::create_symlink(dir + "/loop", dir + "/loop");
    Result<std::string> loop = read_file(dir + "/loop");
    ASSERT_FALSE(loop.is_ok());
    EXPECT_NE(loop.status().message().find("loop"), std::string::npos);
    EXPECT_EQ(read_file(dir + "/missing").status().code(), StatusCode::not_found);
    EXPECT_FALSE(read_file(dir + "/" + std::string(5000, 'n')).is_ok());
    Result<std::string> limited = read_file(dir + "/a.txt", 3);
    ASSERT_FALSE(limited.is_ok());
    EXPECT_NE(limited.status().message().find("a.txt"), std::string::npos);
}

TEST(Files, OutputsNeverReplaceInputs)
{
    std::string dir = scratch("outputs");
    write(dir + "/model.obj", "v 0 0 0\n");
    fs::create_directories(dir + "/p.standin");
    write(dir + "/p.standin/manifest.json", "{}");
    fs::create_symlink(dir + "/model.obj", dir + "/alias.json");
    fs::create_hard_link(dir + "/model.obj", dir + "/hard.json");
    std::vector<std::string> inputs = {dir + "/model.obj", dir + "/p.standin"};
    EXPECT_FALSE(check_output_is_not_input(dir + "/model.obj", inputs).is_ok());
    EXPECT_FALSE(check_output_is_not_input(dir + "/./model.obj", inputs).is_ok());
    EXPECT_FALSE(check_output_is_not_input(dir + "/alias.json", inputs).is_ok());
    EXPECT_FALSE(check_output_is_not_input(dir + "/hard.json", inputs).is_ok());
    EXPECT_FALSE(check_output_is_not_input(dir + "/p.standin/manifest.json", inputs).is_ok());
    EXPECT_FALSE(check_output_is_not_input(dir + "/p.standin/new.png", inputs).is_ok());
    EXPECT_FALSE(check_output_is_not_input(dir + "/p.standin/sub/../x.png", inputs).is_ok());
    EXPECT_FALSE(check_output_is_not_input(dir + "/p.standin", {dir + "/p.standin/manifest.json"}).is_ok());
    EXPECT_TRUE(check_output_is_not_input(dir + "/out.png", inputs).is_ok());
    EXPECT_TRUE(check_output_is_not_input(dir + "/p2.standin", inputs).is_ok());

    EXPECT_TRUE(check_output_path(dir + "/out.png").is_ok());
    EXPECT_TRUE(check_output_path("relative.png").is_ok());
    Status missing = check_output_path(dir + "/missing/dir/k.standin");
    ASSERT_FALSE(missing.is_ok());
    EXPECT_NE(missing.message().find("does not exist"), std::string::npos);
    EXPECT_FALSE(write_file_atomic(dir + "/missing/x.txt", "x").is_ok());
    EXPECT_FALSE(fs::exists(dir + "/missing"));
}

TEST(Files, CommitExchangesADirectoryAtomically)
{
    std::string dir = scratch("commit");
    fs::create_directories(dir + "/k.standin");
    write(dir + "/k.standin/manifest.json", "old");
    std::string temporary = temporary_path_for(dir + "/k.standin");
    fs::create_directories(temporary);
    write(temporary + "/manifest.json", "new");
    ASSERT_TRUE(commit_path(temporary, dir + "/k.standin").is_ok());
    EXPECT_EQ(*read_file(dir + "/k.standin/manifest.json"), "new");
    EXPECT_FALSE(fs::exists(temporary)); // the old package went with the temporary name
    std::size_t entries = 0;
    for (const auto& e : fs::directory_iterator(dir)) entries += e.exists();
    EXPECT_EQ(entries, 1u);
}

TEST(Files, StaleTemporariesOfDeadProcessesAreRemoved)
{
    std::string dir = scratch("stale");
    std::string final_path = dir + "/k.standin";
    fs::create_directories(final_path + ".tmp4194303_7/x");             // no such process
    fs::create_directories(final_path + ".tmp" + std::to_string(::getpid()) + "_0"); // ours
    fs::create_directories(final_path + ".tmp1_0");                      // init runs
    fs::create_directories(dir + "/other.standin.tmp4194303_0");         // another output's
    write(final_path + ".tmp4194303_9.old", "x");
    remove_stale_temporaries(final_path);
    EXPECT_FALSE(fs::exists(final_path + ".tmp4194303_7"));
    EXPECT_FALSE(fs::exists(final_path + ".tmp4194303_9.old"));
    EXPECT_TRUE(fs::exists(final_path + ".tmp" + std::to_string(::getpid()) + "_0"));
    EXPECT_TRUE(fs::exists(final_path + ".tmp1_0"));
    EXPECT_TRUE(fs::exists(dir + "/other.standin.tmp4194303_0"));
}

TEST(Limits, BudgetsRefuseWithTheVariableThatRaisesThem)
{
    Budget saved = budget();
    set_budget({1000, 10});
    Status memory = check_memory(2000, "x");
    EXPECT_FALSE(memory.is_ok());
    EXPECT_NE(memory.message().find("STANDIN_MEMORY_LIMIT"), std::string::npos);
    EXPECT_TRUE(check_memory(1000, "x").is_ok());
    Status triangles = check_triangles(11, "m.ply");
    EXPECT_NE(triangles.message().find("STANDIN_MAX_TRIANGLES"), std::string::npos);
    set_budget(saved);
}

TEST(Files, JsonNestingIsBounded)
{
    EXPECT_TRUE(json_nesting_within("{\"a\": [1, [2]], \"b\": \"[[[[\"}", 3));
    EXPECT_FALSE(json_nesting_within(std::string(100, '['), 64));
}

} // namespace
} // namespace standin
