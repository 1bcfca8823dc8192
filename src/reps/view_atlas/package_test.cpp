// The view-atlas package codec with a hand-built package: round trip, byte-identical writes, and
// refusal (with the file and field named) of damaged or inconsistent packages.
#include "test_support.h"

#include "reps/common/block_compress.h"
#include "reps/common/package_codec.h"
#include "reps/view_atlas/view_atlas.h"

#include <standin/files.h>
#include <standin/image.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace standin::view_atlas {
namespace {

namespace fs = std::filesystem;

// depth_bits 10 (what 512 px captures get): depths that 8 bits cannot hold
ViewAtlasPackage small_package(int depth_bits = 10)
{
    ViewAtlasPackage p;
    p.source.file_name = "tiny.ply";
    p.source.bounds = {glm::vec3(-1.0f), glm::vec3(1.0f)};
    OptionValues values;
    values.set("resolution", "32");
    values.set("page-size", "256");
    values.set("compression", "none"); // exact round trips; BcPagesRoundTrip tests bc
    values.set("depth-bits", std::to_string(depth_bits));
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
    p.proxy_planes = {{0.0f, 0.6f, 0.8f, 1.25f}, {-1.0f, 0.0f, 0.0f, 0.75f}};
    p.color_pages.assign(1, ImageRGBA8(256, 256));
    p.normal_depth_pages.assign(1, ImageRGBA8(256, 256));
    if (depth_bits > 8) p.depth_pages.assign(1, std::vector<std::uint16_t>(256 * 256, 0));
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            std::uint8_t* c = p.color_pages[0].at(x, y);
            c[0] = std::uint8_t(x * 8), c[1] = std::uint8_t(y * 8), c[2] = 100, c[3] = (x + y) % 3 ? 255 : 0;
            std::uint8_t* n = p.normal_depth_pages[0].at(x, y);
            n[0] = 128, n[1] = 128, n[2] = 255, n[3] = std::uint8_t(x + y);
            if (depth_bits > 8 && c[3] != 0) { // uncovered texels hold 0, as the bake leaves them
                const std::uint16_t code = std::uint16_t(((x + y) * 4 + x % 4) << (16 - depth_bits));
                p.depth_pages[0][std::size_t(y) * 256 + std::size_t(x)] = code;
                n[3] = depth8(code, depth_bits);
            }
        }
    return p;
}

std::string read_text(const std::string& path) { return *read_file(path); }

ViewAtlasPackage with_compression(ViewAtlasPackage p, const char* compression)
{
    OptionValues values;
    values.set("resolution", "32");
    values.set("page-size", "256");
    values.set("compression", compression);
    values.set("depth-bits", std::to_string(p.settings.depth_bits));
    p.parameters = *Options::parse(registration().bake_options, values, "test");
    p.settings = settings_from(p.parameters);
    // unit normals (small_package's are +Z), spread over the sphere to exercise the octahedral fold
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            if (p.color_pages[0].at(x, y)[3] == 0) continue;
            glm::vec3 n = glm::normalize(glm::vec3(std::sin(x * 0.1f), std::cos(y * 0.07f), std::sin(float(x + y) * 0.05f) - 0.3f));
            for (int c = 0; c < 3; ++c) p.normal_depth_pages[0].at(x, y)[c] = std::uint8_t(std::lround((n[c] * 0.5f + 0.5f) * 255.0f));
        }
    return p;
}

// --compression bc / bc-color (issue #17): format version 5, KTX2 pages and grey PNG depth; coverage and depth exact,
// normals within BC5's error, colour exact (bc) or within DXT5's (bc-color); a read package writes
// the same blocks back; the stored colour blocks are what --texture-format bc3 would have made.
TEST(ViewAtlasPackage, BcPagesRoundTrip)
{
    for (const char* compression : {"bc", "bc-color"}) {
        SCOPED_TRACE(compression);
        const bool bc_color = std::string(compression) == "bc-color";
        std::string dir = test::fresh_directory(std::string("view_atlas_") + compression);
        ViewAtlasPackage p = with_compression(small_package(), compression);
        ASSERT_TRUE(write_package(p, dir + "/a.standin").is_ok());
        ASSERT_TRUE(write_package(p, dir + "/b.standin").is_ok());
        nlohmann::json manifest = nlohmann::json::parse(read_text(dir + "/a.standin/manifest.json"));
        EXPECT_EQ(manifest["version"], k_package_format_version);
        EXPECT_EQ(manifest["bake"]["compression"], compression);
        EXPECT_FALSE(fs::exists(dir + "/a.standin/page_000_normal_depth.png"));
        EXPECT_EQ(fs::exists(dir + "/a.standin/page_000_color.png"), !bc_color);
        for (const std::string name : {"manifest.json", "page_000_normal.ktx2", "page_000_depth.png",
                                       bc_color ? "page_000_color.ktx2" : "page_000_color.png"})
            EXPECT_EQ(read_text(dir + "/a.standin/" + name), read_text(dir + "/b.standin/" + name)) << name;

        Result<std::unique_ptr<Package>> read_back = read_package(dir + "/a.standin");
        ASSERT_TRUE(read_back.is_ok()) << read_back.status().message();
        const auto& q = dynamic_cast<const ViewAtlasPackage&>(**read_back);
        EXPECT_EQ(q.settings.compression, compression);
        float worst_normal = 0.0f;
        int worst_color = 0;
        for (std::size_t t = 0; t < p.color_pages[0].pixels.size() / 4; ++t) {
            const std::uint8_t *a = &q.color_pages[0].pixels[t * 4], *b = &p.color_pages[0].pixels[t * 4];
            const std::uint8_t *na = &q.normal_depth_pages[0].pixels[t * 4], *nb = &p.normal_depth_pages[0].pixels[t * 4];
            ASSERT_EQ(a[3], b[3]) << "coverage, texel " << t;
            if (b[3] == 0) {
                ASSERT_EQ(na[0] | na[1] | na[2] | na[3], 0) << "uncovered texel " << t;
                if (bc_color) { // PNG colour is as stored
                    ASSERT_EQ(a[0] | a[1] | a[2], 0) << "uncovered texel " << t;
                }
                continue;
            }
            ASSERT_EQ(na[3], nb[3]) << "depth, texel " << t;
            ASSERT_EQ(q.depth_pages[0][t], p.depth_pages[0][t]) << "16-bit depth, texel " << t;
            for (int c = 0; c < 3; ++c) worst_color = std::max(worst_color, std::abs(int(a[c]) - int(b[c])));
            auto normal = [](const std::uint8_t* n) { return glm::normalize(glm::vec3(n[0], n[1], n[2]) / 255.0f * 2.0f - 1.0f); };
            worst_normal = std::max(worst_normal, glm::degrees(std::acos(std::min(glm::dot(normal(na), normal(nb)), 1.0f))));
        }
        EXPECT_LT(worst_normal, 12.0f); // as the billboards' BC5 normals
        if (bc_color) {
            EXPECT_LT(worst_color, 40); // 5:6:5 end points of a gradient
            ASSERT_EQ(q.color_bc3.size(), 1u);
            EXPECT_EQ(q.color_bc3[0], color_page_blocks(p.color_pages[0])); // what bc3 uploads, stored
        } else {
            EXPECT_EQ(worst_color, 0); // colour stays PNG
            EXPECT_TRUE(q.color_bc3.empty());
        }

        // writing the read package stores the blocks it read (no refit of decoded normals)
        ASSERT_TRUE(write_package(q, dir + "/c.standin").is_ok());
        for (const char* name : {"page_000_normal.ktx2", "page_000_depth.png"})
            EXPECT_EQ(read_text(dir + "/a.standin/" + name), read_text(dir + "/c.standin/" + name)) << name;
        if (bc_color) {
            EXPECT_EQ(read_text(dir + "/a.standin/page_000_color.ktx2"), read_text(dir + "/c.standin/page_000_color.ktx2"));
        }
    }
    // none with 8-bit depth keeps format version 1 (older standins read it) and the PNG layout;
    // 8-bit depth with bc keeps version 5
    std::string dir = test::fresh_directory("view_atlas_none");
    ASSERT_TRUE(write_package(small_package(8), dir + "/p.standin").is_ok());
    nlohmann::json manifest = nlohmann::json::parse(read_text(dir + "/p.standin/manifest.json"));
    EXPECT_EQ(manifest["version"], 1);
    EXPECT_TRUE(manifest["pages"][0].contains("normal_depth"));
    EXPECT_FALSE(manifest["pages"][0].contains("depth"));
    ASSERT_TRUE(write_package(with_compression(small_package(8), "bc"), dir + "/q.standin").is_ok());
    EXPECT_EQ(nlohmann::json::parse(read_text(dir + "/q.standin/manifest.json"))["version"], k_package_format_version_exact_depth);
    Result<std::unique_ptr<Package>> eight = read_package(dir + "/q.standin");
    ASSERT_TRUE(eight.is_ok()) << eight.status().message();
    EXPECT_TRUE(dynamic_cast<const ViewAtlasPackage&>(**eight).depth_pages.empty());
}

// Hostile compressed pages: every refusal names the file (or field) and nothing crashes.
TEST(ViewAtlasPackage, RefusesBadCompressedPages)
{
    std::string dir = test::fresh_directory("view_atlas_bc_damage");
    const std::string path = dir + "/p.standin";
    auto fresh = [&](const char* compression, int depth_bits = 10) {
        fs::remove_all(path);
        EXPECT_TRUE(write_package(with_compression(small_package(depth_bits), compression), path).is_ok());
        return nlohmann::json::parse(read_text(path + "/manifest.json"));
    };
    auto replace = [&](nlohmann::json& manifest, const std::string& name, const std::string& bytes) {
        EXPECT_TRUE(write_file_atomic(path + "/" + name, bytes).is_ok());
        manifest["files"][name] = {{"bytes", bytes.size()}, {"fnv1a64", hex64(hash_bytes(bytes))}};
        std::ofstream(path + "/manifest.json") << manifest.dump(1);
    };
    auto expect_refused = [&](const std::string& what) {
        Result<std::unique_ptr<Package>> bad = read_package(path);
        ASSERT_FALSE(bad.is_ok()) << what;
        EXPECT_EQ(bad.status().code(), StatusCode::bad_data) << bad.status().message();
        EXPECT_NE(bad.status().message().find(what), std::string::npos) << bad.status().message();
    };
    using manifest_io::BlockFormat;
    using manifest_io::BlockImage;
    // a valid KTX2 of the wrong size, of the wrong format, of too few levels; a truncated one
    nlohmann::json m = fresh("bc");
    BlockImage small{BlockFormat::bc5, 128, 128, {std::vector<std::uint8_t>(manifest_io::level_bytes(BlockFormat::bc5, 128, 128))}};
    replace(m, "page_000_normal.ktx2", manifest_io::encode_ktx2(small));
    expect_refused("page_000_normal.ktx2");
    m = fresh("bc");
    Result<std::string> rgba_depth = encode_png_bytes(ImageRGBA8(256, 256));
    ASSERT_TRUE(rgba_depth);
    replace(m, "page_000_depth.png", *rgba_depth);
    expect_refused("page_000_depth.png");
    // format version 4 kept depth as an R8 KTX2: still read, and one of another format refused
    m = fresh("bc", 8);
    BlockImage r8{BlockFormat::r8, 256, 256, {std::vector<std::uint8_t>(manifest_io::level_bytes(BlockFormat::r8, 256, 256))}};
    m["version"] = 4;
    m["bake"].erase("depth_bits");
    m["pages"][0]["depth"] = "page_000_depth.ktx2";
    replace(m, "page_000_depth.ktx2", manifest_io::encode_ktx2(r8));
    Result<std::unique_ptr<Package>> version4 = read_package(path);
    EXPECT_TRUE(version4.is_ok()) << version4.status().message();
    BlockImage bc4{BlockFormat::bc4, 256, 256, {std::vector<std::uint8_t>(manifest_io::level_bytes(BlockFormat::bc4, 256, 256))}};
    replace(m, "page_000_depth.ktx2", manifest_io::encode_ktx2(bc4));
    expect_refused("page_000_depth.ktx2");
    m = fresh("bc");
    std::string normal = read_text(path + "/page_000_normal.ktx2");
    replace(m, "page_000_normal.ktx2", normal.substr(0, normal.size() - 7));
    expect_refused("page_000_normal.ktx2");
    m = fresh("bc-color");
    BlockImage one_level{BlockFormat::bc3_srgb, 256, 256,
                         {std::vector<std::uint8_t>(manifest_io::level_bytes(BlockFormat::bc3_srgb, 256, 256))}};
    replace(m, "page_000_color.ktx2", manifest_io::encode_ktx2(one_level));
    expect_refused("page_000_color.ktx2");
    // a bc package whose entry lacks its depth file; an unknown compression
    m = fresh("bc");
    m["pages"][0].erase("depth");
    std::ofstream(path + "/manifest.json") << m.dump(1);
    expect_refused("pages[0].depth");
    m = fresh("bc");
    m["bake"]["compression"] = "bc7";
    std::ofstream(path + "/manifest.json") << m.dump(1);
    expect_refused("compression");
    // a package of an older standin (no bake.compression, no bake.depth_bits) still reads, as PNG
    // pages of 8-bit depth
    fs::remove_all(path);
    ASSERT_TRUE(write_package(small_package(8), path).is_ok());
    m = nlohmann::json::parse(read_text(path + "/manifest.json"));
    m["bake"].erase("compression");
    m["bake"].erase("depth_bits");
    std::ofstream(path + "/manifest.json") << m.dump(1);
    Result<std::unique_ptr<Package>> old = read_package(path);
    ASSERT_TRUE(old.is_ok()) << old.status().message();
    EXPECT_EQ(dynamic_cast<const ViewAtlasPackage&>(**old).settings.depth_bits, 8);
    // 10-bit depth: an 8-bit depth file, one with a depth off the 10-bit grid, and a package whose
    // depth file is missing
    m = fresh("bc");
    Result<std::string> narrow = encode_png_grey_bytes(256, 256, 8, std::vector<std::uint16_t>(256 * 256, 0));
    ASSERT_TRUE(narrow);
    replace(m, "page_000_depth.png", *narrow);
    expect_refused("page_000_depth.png");
    m = fresh("bc");
    Result<std::string> off_grid = encode_png_grey_bytes(256, 256, 16, std::vector<std::uint16_t>(256 * 256, 1000));
    ASSERT_TRUE(off_grid);
    replace(m, "page_000_depth.png", *off_grid);
    expect_refused("not a multiple of 64");
    fs::remove_all(path);
    ASSERT_TRUE(write_package(small_package(), path).is_ok());
    m = nlohmann::json::parse(read_text(path + "/manifest.json"));
    m["pages"][0].erase("depth");
    std::ofstream(path + "/manifest.json") << m.dump(1);
    expect_refused("pages[0].depth");
}

TEST(ViewAtlasPackage, RoundTripAndDeterminism)
{
    std::string dir = test::fresh_directory("view_atlas_roundtrip");
    ViewAtlasPackage p = small_package();
    ASSERT_TRUE(write_package(p, dir + "/a.standin").is_ok());
    ASSERT_TRUE(write_package(p, dir + "/b.standin").is_ok());
    for (const char* name : {"manifest.json", "page_000_color.png", "page_000_normal_depth.png", "page_000_depth.png"})
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
    EXPECT_EQ(q.depth_pages, p.depth_pages); // exact 10-bit depth
    EXPECT_EQ(q.settings.depth_bits, 10);
    // 16 bits round trip as exactly
    ASSERT_TRUE(write_package(small_package(16), dir + "/e.standin").is_ok());
    Result<std::unique_ptr<Package>> sixteen = read_package(dir + "/e.standin");
    ASSERT_TRUE(sixteen.is_ok()) << sixteen.status().message();
    EXPECT_EQ(dynamic_cast<const ViewAtlasPackage&>(**sixteen).depth_pages, small_package(16).depth_pages);
    ViewAtlasPackage no_depth = small_package(); // depth_bits 10 without the pages: refused, nothing written
    no_depth.depth_pages.clear();
    EXPECT_FALSE(write_package(no_depth, dir + "/d.standin").is_ok());
    EXPECT_FALSE(fs::exists(dir + "/d.standin"));
    EXPECT_FLOAT_EQ(q.radius, p.radius);
    EXPECT_FLOAT_EQ(q.half_extent(), p.radius); // orthographic
    EXPECT_EQ(q.proxy_planes, p.proxy_planes);
    // alpha_tested is written only when true (other models' manifests stay as they were) and read back
    EXPECT_FALSE(q.alpha_tested);
    EXPECT_EQ(read_text(dir + "/a.standin/manifest.json").find("alpha_tested"), std::string::npos);
    ViewAtlasPackage masked = small_package();
    masked.alpha_tested = true;
    ASSERT_TRUE(write_package(masked, dir + "/c.standin").is_ok());
    Result<std::unique_ptr<Package>> masked_back = read_package(dir + "/c.standin");
    ASSERT_TRUE(masked_back.is_ok()) << masked_back.status().message();
    EXPECT_TRUE(dynamic_cast<const ViewAtlasPackage&>(**masked_back).alpha_tested);
    // packages from before the proxy hull have no planes: read as none (the renderer draws prisms)
    nlohmann::json manifest = nlohmann::json::parse(read_text(dir + "/a.standin/manifest.json"));
    manifest.erase("proxy_planes");
    std::ofstream(dir + "/a.standin/manifest.json") << manifest.dump(1);
    Result<std::unique_ptr<Package>> older = read_package(dir + "/a.standin");
    ASSERT_TRUE(older.is_ok()) << older.status().message();
    EXPECT_TRUE(dynamic_cast<const ViewAtlasPackage&>(**older).proxy_planes.empty());
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
        // proxy planes that are not planes
        {"proxy_planes[1]", [](nlohmann::json& m) { m["proxy_planes"][1] = {2.0, 0.0, 0.0, 1.0}; }},
        {"proxy_planes[0]", [](nlohmann::json& m) { m["proxy_planes"][0] = {0.0, 1.0, 0.0}; }},
        {"proxy_planes", [](nlohmann::json& m) { m["proxy_planes"] = "all of them"; }},
        {"alpha_tested", [](nlohmann::json& m) { m["alpha_tested"] = "yes"; }},
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
