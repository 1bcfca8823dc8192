// `standin bake` over a library (apps/standin/batch.cpp): a folder with a corrupt model bakes the
// others, reports the failure and exits 2; a re-run skips what is up to date; shards (given or from
// Slurm's variables) split the models and an unsharded run merges their summaries.
#include "test_support.h"

#include <standin/files.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

namespace standin {
namespace {

namespace fs = std::filesystem;

// A library: the bundled teapot and bunny, the bunny again under another extension's stem clash,
// and a corrupt PLY.
std::string make_library(const std::string& dir)
{
    std::string models = dir + "/models";
    fs::create_directories(models + "/sub");
    fs::copy_file(test::source_dir() + "/data/teapot.ply", models + "/teapot.ply");
    fs::copy_file(test::source_dir() + "/data/bunny.ply", models + "/sub/bunny.ply");
    std::ofstream(models + "/broken.ply") << "ply\nformat ascii 1.0\nelement vertex 3\nend_header\n1 2\n";
    std::ofstream(models + "/notes.txt") << "not a model\n";
    return models;
}

using test::read_json;

const nlohmann::json* entry(const nlohmann::json& summary, const std::string& package)
{
    for (const nlohmann::json& m : summary["models"])
        if (m["package"] == package) return &m;
    return nullptr;
}

TEST(Batch, BakesTheRestReportsTheFailureAndSkipsWhatIsUpToDate)
{
    std::string dir = test::fresh_directory("batch");
    std::string models = make_library(dir);
    test::CommandResult first = test::run_cli("bake " + models + " -o " + dir + "/out --threads 1");
    EXPECT_EQ(first.exit_code, 2) << first.err;
    EXPECT_NE(first.err.find("broken.ply: failed"), std::string::npos) << first.err;
    nlohmann::json summary = read_json(dir + "/out/standin-batch.json");
    EXPECT_EQ(summary["baked"], 2);
    EXPECT_EQ(summary["failed"], 1);
    ASSERT_EQ(summary["models"].size(), 3u) << "notes.txt is not a model";
    for (const char* name : {"teapot.standin", "bunny.standin"}) {
        const nlohmann::json* m = entry(summary, name);
        ASSERT_TRUE(m) << name;
        EXPECT_EQ((*m)["status"], "baked");
        EXPECT_GT((*m)["package_bytes"].get<double>(), 0.0);
        EXPECT_GT((*m)["error_at_distance_1"]["iou"].get<double>(), 0.95);
        EXPECT_TRUE(read_package(dir + "/out/" + name).is_ok()) << name;
    }
    const nlohmann::json* broken = entry(summary, "broken.standin");
    ASSERT_TRUE(broken);
    EXPECT_EQ((*broken)["status"], "failed");
    EXPECT_NE((*broken)["error"].get<std::string>().find("broken.ply"), std::string::npos);

    // again: the two packages are up to date, with the figures of their bake
    test::CommandResult again = test::run_cli("bake " + models + " -o " + dir + "/out");
    EXPECT_EQ(again.exit_code, 2);
    summary = read_json(dir + "/out/standin-batch.json");
    EXPECT_EQ(summary["baked"], 0);
    EXPECT_EQ(summary["skipped"], 2);
    EXPECT_GT((*entry(summary, "teapot.standin"))["seconds"].get<double>(), 0.0);

    // other options, or a changed model: baked again
    std::ofstream(models + "/teapot.ply", std::ios::app) << "";
    fs::copy_file(test::source_dir() + "/data/bunny.ply", models + "/teapot.ply", fs::copy_options::overwrite_existing);
    test::CommandResult changed = test::run_cli("bake " + models + " -o " + dir + "/out --no-eval");
    summary = read_json(dir + "/out/standin-batch.json");
    EXPECT_EQ((*entry(summary, "teapot.standin"))["status"], "baked") << "the model's bytes changed";
    EXPECT_EQ((*entry(summary, "bunny.standin"))["status"], "skipped");
    test::CommandResult other = test::run_cli("bake " + models + " -o " + dir + "/out --no-eval --resolution 256");
    summary = read_json(dir + "/out/standin-batch.json");
    EXPECT_EQ(summary["baked"], 2) << "other options";
}

TEST(Batch, ShardsSplitTheModelsAndAnUnshardedRunMergesThem)
{
    std::string dir = test::fresh_directory("batch_shards");
    std::string models = make_library(dir);
    fs::remove(models + "/broken.ply");
    std::string list = dir + "/models.txt";
    std::ofstream(list) << "# the library\nmodels/teapot.ply\n\nmodels/sub/bunny.ply\n";
    test::CommandResult a = test::run_cli("bake --list " + list + " -o " + dir + "/out --shard 0/2 --no-eval");
    test::CommandResult b = test::run_command("SLURM_ARRAY_TASK_ID=1 SLURM_ARRAY_TASK_COUNT=2 " + test::cli_path() +
                                              " bake --list " + list + " -o " + dir + "/out --no-eval");
    ASSERT_EQ(a.exit_code, 0) << a.err;
    ASSERT_EQ(b.exit_code, 0) << b.err;
    nlohmann::json shard0 = read_json(dir + "/out/standin-batch.shard-0-of-2.json");
    nlohmann::json shard1 = read_json(dir + "/out/standin-batch.shard-1-of-2.json");
    EXPECT_EQ(shard0["models"].size() + shard1["models"].size(), 2u);
    EXPECT_EQ(shard0["models"].size(), 1u);
    test::CommandResult merge = test::run_cli("bake --list " + list + " -o " + dir + "/out --no-eval");
    EXPECT_EQ(merge.exit_code, 0) << merge.err;
    nlohmann::json merged = read_json(dir + "/out/standin-batch.json");
    EXPECT_EQ(merged["skipped"], 2);
    EXPECT_EQ(merged["shards"], 1);

    test::CommandResult bad = test::run_cli("bake --list " + list + " -o " + dir + "/out --shard 2/2");
    EXPECT_EQ(bad.exit_code, 2);
    EXPECT_NE(bad.err.find("--shard"), std::string::npos);
}

} // namespace
} // namespace standin
