// The view-atlas package codec with a hand-built package: round trip, byte-identical writes, and
// refusal (with the file and field named) of damaged or inconsistent packages.
#include "test_support.h"

#include "reps/view_atlas/view_atlas.h"

#include <standin/files.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace standin::view_atlas {
namespace {

namespace fs = std::filesystem;

ViewAtlasPackage small_package()
{
    ViewAtlasPackage p;
    p.source.file_name = "tiny.ply";
    p.source.bounds = {glm::vec3(-1.0f), glm::vec3(1.0f)};
    OptionValues values;
    values.set("resolution", "32");
    values.set("page-size", "256");
    p.parameters = *Options::parse(registration().bake_options, values, "test");
    p.settings = settings_from(p.parameters);
    p.center = glm::vec3(0.0f);
    p.radius = std::sqrt(3.0f);
    const glm::vec3 directions[2] = {{0, 0, 1}, {1, 0, 0}};
    for (int k = 0; k < 2; ++k) {
        View v;
        v.direction = directions[k];
        v.axis_u = k == 0 ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, -1);
        v.axis_v = glm::vec3(0, -1, 0);
        v.crop_x = 7;
        v.crop_y = 3;
        v.width = 16;
        v.height = 32;
        v.atlas_x = 16 * k;
        p.views.push_back(v);
    }
    p.color_pages.assign(1, ImageRGBA8(256, 256));
    p.normal_depth_pages.assign(1, ImageRGBA8(256, 256));
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            std::uint8_t* c = p.color_pages[0].at(x, y);
            c[0] = std::uint8_t(x * 8), c[1] = std::uint8_t(y * 8), c[2] = 100, c[3] = (x + y) % 3 ? 255 : 0;
            std::uint8_t* n = p.normal_depth_pages[0].at(x, y);
            n[0] = 128, n[1] = 128, n[2] = 255, n[3] = std::uint8_t(x + y);
        }
    return p;
}

std::string read_text(const std::string& path) { return *read_file(path); }

TEST(ViewAtlasPackage, RoundTripAndDeterminism)
{
    std::string dir = test::fresh_directory("view_atlas_roundtrip");
    ViewAtlasPackage p = small_package();
    ASSERT_TRUE(write_package(p, dir + "/a.standin").is_ok());
    ASSERT_TRUE(write_package(p, dir + "/b.standin").is_ok());
    for (const char* name : {"manifest.json", "page_000_color.png", "page_000_normal_depth.png"})
        EXPECT_EQ(read_text(dir + "/a.standin/" + name), read_text(dir + "/b.standin/" + name)) << name;

    Result<std::unique_ptr<Package>> read_back = read_package(dir + "/a.standin");
    ASSERT_TRUE(read_back.is_ok()) << read_back.status().message();
    const auto& q = dynamic_cast<const ViewAtlasPackage&>(**read_back);
    EXPECT_EQ(q.representation(), "view-atlas");
    ASSERT_EQ(q.views.size(), 2u);
    EXPECT_EQ(q.views[1].axis_u, p.views[1].axis_u);
    EXPECT_EQ(q.views[1].crop_x, 7);
    EXPECT_EQ(q.views[1].atlas_x, 16);
    EXPECT_EQ(q.views[1].height, 32);
    EXPECT_EQ(q.color_pages[0].pixels, p.color_pages[0].pixels);
    EXPECT_EQ(q.normal_depth_pages[0].pixels, p.normal_depth_pages[0].pixels);
    EXPECT_FLOAT_EQ(q.radius, p.radius);
    EXPECT_FLOAT_EQ(q.half_extent(), p.radius); // orthographic
    EXPECT_EQ(summarise_package(q).details["views"], 2);
}

TEST(ViewAtlasPackage, PbrPagesRoundTripAndOnlyWhenBaked)
{
    // issue #14: ORM and emission pages are written, named in the page entries and read back; a
    // package without them writes exactly the files and manifest keys it wrote before
    std::string dir = test::fresh_directory("view_atlas_pbr_roundtrip");
    ViewAtlasPackage plain = small_package();
    ASSERT_TRUE(write_package(plain, dir + "/plain.standin").is_ok());
    EXPECT_FALSE(fs::exists(dir + "/plain.standin/page_000_orm.png"));
    nlohmann::json plain_manifest = nlohmann::json::parse(read_text(dir + "/plain.standin/manifest.json"));
    EXPECT_FALSE(plain_manifest["pages"][0].contains("orm"));
    EXPECT_FALSE(plain_manifest["pages"][0].contains("emission"));

    ViewAtlasPackage p = small_package();
    p.orm_pages.assign(1, ImageRGBA8(256, 256));
    p.emission_pages.assign(1, ImageRGBA8(256, 256));
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            if (p.color_pages[0].at(x, y)[3] == 0) continue;
            std::uint8_t* o = p.orm_pages[0].at(x, y);
            o[0] = 255, o[1] = std::uint8_t(x * 7), o[2] = std::uint8_t(y * 5), o[3] = 255;
            std::uint8_t* e = p.emission_pages[0].at(x, y);
            e[0] = 0, e[1] = std::uint8_t(x + y), e[2] = 250, e[3] = 255;
        }
    ASSERT_TRUE(write_package(p, dir + "/a.standin").is_ok());
    ASSERT_TRUE(write_package(p, dir + "/b.standin").is_ok());
    for (const char* name : {"manifest.json", "page_000_orm.png", "page_000_emission.png"})
        EXPECT_EQ(read_text(dir + "/a.standin/" + name), read_text(dir + "/b.standin/" + name)) << name;
    Result<std::unique_ptr<Package>> read_back = read_package(dir + "/a.standin");
    ASSERT_TRUE(read_back.is_ok()) << read_back.status().message();
    const auto& q = dynamic_cast<const ViewAtlasPackage&>(**read_back);
    ASSERT_TRUE(q.has_pbr());
    EXPECT_EQ(q.orm_pages[0].pixels, p.orm_pages[0].pixels);
    EXPECT_EQ(q.emission_pages[0].pixels, p.emission_pages[0].pixels);

    // one of the two missing is refused, naming the field
    nlohmann::json manifest = nlohmann::json::parse(read_text(dir + "/a.standin/manifest.json"));
    manifest["pages"][0].erase("emission");
    std::ofstream(dir + "/a.standin/manifest.json") << manifest.dump(1);
    Result<std::unique_ptr<Package>> bad = read_package(dir + "/a.standin");
    ASSERT_FALSE(bad.is_ok());
    EXPECT_NE(bad.status().message().find("emission"), std::string::npos) << bad.status().message();
}

TEST(ViewAtlasPackage, RefusesDamage)
{
    std::string dir = test::fresh_directory("view_atlas_damage");
    ViewAtlasPackage p = small_package();
    std::string path = dir + "/p.standin";

    // a changed byte in a page
    ASSERT_TRUE(write_package(p, path).is_ok());
    {
        std::fstream f(path + "/page_000_color.png", std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(60);
        f.put('\x5a');
    }
    Result<std::unique_ptr<Package>> damaged = read_package(path);
    ASSERT_FALSE(damaged.is_ok());
    EXPECT_NE(damaged.status().message().find("page_000_color.png"), std::string::npos) << damaged.status().message();

    // a view outside its page, a missing field, a non-unit axis, an unknown projection
    struct Edit {
        const char* field;
        void (*apply)(nlohmann::json&);
    };
    const Edit edits[] = {
        {"atlas_x", [](nlohmann::json& m) { m["views"][1]["atlas_x"] = 250; }},
        {"crop_y", [](nlohmann::json& m) { m["views"][0].erase("crop_y"); }},
        {"axis_u", [](nlohmann::json& m) { m["views"][0]["axis_u"] = {2.0, 0.0, 0.0}; }},
        {"projection", [](nlohmann::json& m) { m["bake"]["projection"] = "fisheye"; }},
        {"page", [](nlohmann::json& m) { m["views"][0]["page"] = 3; }},
        // a package that draws nothing
        {"pages", [](nlohmann::json& m) { m["pages"] = nlohmann::json::array(); }},
        {"views", [](nlohmann::json& m) {
             for (auto& v : m["views"]) v["width"] = 0;
         }},
    };
    for (const Edit& edit : edits) {
        fs::remove_all(path);
        ASSERT_TRUE(write_package(p, path).is_ok());
        nlohmann::json manifest = nlohmann::json::parse(read_text(path + "/manifest.json"));
        edit.apply(manifest);
        std::ofstream(path + "/manifest.json") << manifest.dump(1);
        Result<std::unique_ptr<Package>> bad = read_package(path);
        ASSERT_FALSE(bad.is_ok()) << edit.field;
        EXPECT_NE(bad.status().message().find(edit.field), std::string::npos) << bad.status().message();
    }
}

} // namespace
} // namespace standin::view_atlas
