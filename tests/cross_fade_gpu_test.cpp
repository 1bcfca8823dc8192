// The screen-door cross-fade (issue #14: DrawParams::fade, CrossFade), over the mesh renderer and
// every registered representation baked from the bundled bunny with its defaults:
// - without a fade, or at amount 0 outgoing, a draw is byte-identical to what it draws alone; at
//   amount 1 incoming too; outgoing at 1 and incoming at 0 draw nothing (colour and depth);
// - an outgoing and an incoming draw of one renderer at the same amount split its picture: every
//   pixel it covers is drawn by exactly one of them, with the colour and depth of the plain draw;
//   the incoming share is the amount (8x8 ordered dither: within 2% over a bunny's silhouette);
// - CrossFade between the mesh and a stand-in, both ways, and between two stand-ins puts at every pixel the
//   colour and the true depth of exactly the one whose dither rank says so: no hole where one
//   covers and the other is dropped, no pixel drawn twice;
// - a shadow map drawn through CrossFade(mesh, mesh) is the mesh's own shadow (no dithered holes).
#include "test_support.h"

#include <standin/package.h>
#include <standin/render.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>
#include <stdexcept>

namespace standin {
namespace {

constexpr int k_fade_size = 128;

// The rank 0..63 of fade.glsl's 8x8 Bayer matrix at a GL pixel (x right, y up).
int bayer_rank(int x, int y)
{
    unsigned ux = unsigned(x) & 7u, uy = unsigned(y) & 7u, d = ux ^ uy;
    return int(((d & 1u) << 5) | ((uy & 1u) << 4) | ((d & 2u) << 2) | ((uy & 2u) << 1) | ((d & 4u) >> 1) | ((uy & 4u) >> 2));
}
// Whether the incoming renderer owns an image pixel (row 0 at the top) at `amount`.
bool incoming_owns(int x, int row, float amount)
{
    float t = (float(bayer_rank(x, k_fade_size - 1 - row)) + 0.5f) / 64.0f;
    return t < amount;
}

// A renderer drawn with a fixed fade, whatever the params say.
class Faded final : public Renderer {
public:
    Faded(Renderer& inner, float amount, bool incoming) : inner_(&inner), fade_{amount, incoming} {}
    DrawStats draw(const DrawParams& params) override
    {
        DrawParams p = params;
        p.fade = fade_;
        return inner_->draw(p);
    }

private:
    Renderer* inner_;
    DrawParams::Fade fade_;
};

Camera test_camera()
{
    OrbitView view;
    view.azimuth_degrees = 30.0f;
    view.elevation_degrees = 15.0f;
    return orbit_camera(test::bunny().bounding_sphere(), view, 1.0f);
}

RenderedImage render(Renderer& renderer)
{
    Camera camera = test_camera();
    Result<RenderedImage> image = render_offscreen(renderer, camera, default_light(camera), k_fade_size, k_fade_size);
    EXPECT_TRUE(image.is_ok()) << image.status().message();
    return image ? std::move(*image) : RenderedImage{};
}

bool covered(const RenderedImage& image, std::size_t i) { return image.depth[i] < 1.0f; }

bool same_pixel(const RenderedImage& a, const RenderedImage& b, std::size_t i)
{
    return std::memcmp(&a.color.pixels[4 * i], &b.color.pixels[4 * i], 4) == 0 && a.depth[i] == b.depth[i];
}

bool identical(const RenderedImage& a, const RenderedImage& b) { return a.color.pixels == b.color.pixels && a.depth == b.depth; }

bool empty(const RenderedImage& image)
{
    for (std::size_t i = 0; i < image.depth.size(); ++i)
        if (image.depth[i] != 1.0f || image.color.pixels[4 * i + 3] != 0) return false;
    return true;
}

// The mesh renderer ("mesh") or a registered representation's, baked from the bunny with its
// defaults; made on first use and kept for the process (ctest runs each test in its own).
Renderer& renderer(const std::string& name)
{
    // never destroyed: renderers free GL objects, and the context goes first at exit
    static auto& made = *new std::map<std::string, std::unique_ptr<Renderer>>;
    static auto& packages = *new std::vector<std::unique_ptr<Package>>; // renderers may refer to them
    std::unique_ptr<Renderer>& r = made[name];
    if (r) return *r;
    test::gpu_context();
    if (name == "mesh") {
        Result<std::unique_ptr<Renderer>> mesh = make_mesh_renderer(test::bunny());
        EXPECT_TRUE(mesh.is_ok());
        if (mesh) r = std::move(*mesh);
    } else {
        SourceInfo source;
        source.bounds = test::bunny().bounds();
        Result<std::unique_ptr<Package>> baked = bake_package(*find_representation(name), test::bunny(), source, {}, {}, 2);
        EXPECT_TRUE(baked.is_ok()) << name << ": " << baked.status().message();
        if (baked) {
            Result<std::unique_ptr<Renderer>> made_renderer = make_package_renderer(**baked, {});
            EXPECT_TRUE(made_renderer.is_ok()) << name << ": " << made_renderer.status().message();
            if (made_renderer) r = std::move(*made_renderer);
            packages.push_back(std::move(*baked));
        }
    }
    if (!r) throw std::runtime_error("no renderer for " + name);
    return *r;
}

void expect_ends_draw_everything_or_nothing(Renderer& r, const std::string& name)
{
    RenderedImage plain = render(r);
    Faded out0(r, 0.0f, false), in1(r, 1.0f, true), out1(r, 1.0f, false), in0(r, 0.0f, true);
    EXPECT_TRUE(identical(render(out0), plain)) << name;
    EXPECT_TRUE(identical(render(in1), plain)) << name;
    EXPECT_TRUE(empty(render(out1))) << name;
    EXPECT_TRUE(empty(render(in0))) << name;
    CrossFade at0(r, r), at1(r, r);
    at1.set_amount(1.0f);
    EXPECT_TRUE(identical(render(at0), plain)) << name;
    EXPECT_TRUE(identical(render(at1), plain)) << name;
}

void expect_complementary_draws_split_the_picture(Renderer& r, const std::string& name)
{
    RenderedImage plain = render(r);
    for (float amount : {0.1f, 0.5f, 0.8f}) {
        Faded out(r, amount, false), in(r, amount, true);
        RenderedImage a = render(out), b = render(in);
        std::size_t union_pixels = 0, drawn_by_in = 0, wrong = 0;
        for (std::size_t i = 0; i < plain.depth.size(); ++i) {
            bool ca = covered(a, i), cb = covered(b, i);
            if (ca && cb) ++wrong; // drawn twice
            if ((ca || cb) != covered(plain, i)) ++wrong; // a hole, or a pixel the plain draw lacks
            if (ca && !same_pixel(a, plain, i)) ++wrong;
            if (cb && !same_pixel(b, plain, i)) ++wrong;
            bool owner_in = incoming_owns(int(i) % k_fade_size, int(i) / k_fade_size, amount);
            if ((ca && owner_in) || (cb && !owner_in)) ++wrong; // not the dither's choice
            union_pixels += covered(plain, i) ? 1 : 0;
            drawn_by_in += cb ? 1 : 0;
        }
        EXPECT_EQ(wrong, 0u) << name << " at " << amount;
        ASSERT_GT(union_pixels, 1000u);
        EXPECT_NEAR(double(drawn_by_in) / double(union_pixels), amount, 0.02) << name;
    }
}

// CrossFade(from, to): each pixel is the plain picture of the one that owns it, colour and depth,
// where that one covers it; the incoming share of the union is the amount.
void expect_cross_fade_shows_one_per_pixel(Renderer& from, Renderer& to, const std::string& name)
{
    RenderedImage plain_from = render(from), plain_to = render(to);
    CrossFade fade(from, to);
    for (float amount : {0.3f, 0.7f}) {
        fade.set_amount(amount);
        RenderedImage mixed = render(fade);
        std::size_t wrong = 0, owned_by_to = 0, union_pixels = 0;
        for (std::size_t i = 0; i < mixed.depth.size(); ++i) {
            bool to_owns = incoming_owns(int(i) % k_fade_size, int(i) / k_fade_size, amount);
            const RenderedImage& owner = to_owns ? plain_to : plain_from;
            if (!same_pixel(mixed, owner, i)) ++wrong;
            if (covered(plain_from, i) || covered(plain_to, i)) {
                ++union_pixels;
                owned_by_to += to_owns ? 1 : 0;
            }
        }
        EXPECT_EQ(wrong, 0u) << name << " at " << amount;
        ASSERT_GT(union_pixels, 1000u);
        EXPECT_NEAR(double(owned_by_to) / double(union_pixels), amount, 0.02) << name;
    }
}

std::vector<std::string> subjects()
{
    std::vector<std::string> names = {"mesh"};
    for (const Representation& r : representations()) names.push_back(r.name);
    return names;
}

class CrossFadeOf : public ::testing::TestWithParam<std::string> {};

// one test per renderer, so that each bakes once
TEST_P(CrossFadeOf, EndsComplementaryDrawsAndCrossFadesWithTheMesh)
{
    Renderer& r = renderer(GetParam());
    expect_ends_draw_everything_or_nothing(r, GetParam());
    expect_complementary_draws_split_the_picture(r, GetParam());
    if (GetParam() == "mesh") return;
    Renderer& mesh = renderer("mesh");
    expect_cross_fade_shows_one_per_pixel(mesh, r, "mesh -> " + GetParam());
    expect_cross_fade_shows_one_per_pixel(r, mesh, GetParam() + " -> mesh");
}

INSTANTIATE_TEST_SUITE_P(Renderers, CrossFadeOf, ::testing::ValuesIn(subjects()),
                         [](const auto& info) {
                             std::string name = info.param;
                             for (char& c : name)
                                 if (c == '-') c = '_';
                             return name;
                         });

// Between two stand-ins: the first and the last registered (any two would do).
TEST(CrossFade, BetweenTwoStandInsShowsOnePerPixel)
{
    ASSERT_GE(representations().size(), 2u);
    const std::string a = representations().front().name, b = representations().back().name;
    expect_cross_fade_shows_one_per_pixel(renderer(a), renderer(b), a + " -> " + b);
}

TEST(CrossFade, ShadowMapDrawnThroughACrossFadeHasNoHoles)
{
    Renderer& mesh = renderer("mesh");
    Camera camera = test_camera();
    ShadowOptions shadows;
    shadows.enabled = true;
    shadows.scene = test::bunny().bounding_sphere();
    shadows.resolution = 512;
    Result<RenderedImage> plain = render_offscreen(mesh, camera, default_light(camera), k_fade_size, k_fade_size, {}, shadows);
    ASSERT_TRUE(plain.is_ok());
    CrossFade fade(mesh, mesh);
    fade.set_amount(0.5f);
    Result<RenderedImage> faded = render_offscreen(fade, camera, default_light(camera), k_fade_size, k_fade_size, {}, shadows);
    ASSERT_TRUE(faded.is_ok());
    EXPECT_TRUE(identical(*plain, *faded));
}

TEST(CrossFade, TransitionAmountOverADistanceBand)
{
    EXPECT_EQ(transition_amount(1.0f, 2.0f, 4.0f), 0.0f);
    EXPECT_EQ(transition_amount(2.0f, 2.0f, 4.0f), 0.0f);
    EXPECT_FLOAT_EQ(transition_amount(3.0f, 2.0f, 4.0f), 0.5f);
    EXPECT_EQ(transition_amount(4.0f, 2.0f, 4.0f), 1.0f);
    EXPECT_EQ(transition_amount(9.0f, 2.0f, 4.0f), 1.0f);
    EXPECT_EQ(transition_amount(2.9f, 3.0f, 3.0f), 0.0f); // a hard switch
    EXPECT_EQ(transition_amount(3.0f, 3.0f, 3.0f), 1.0f);
    EXPECT_EQ(transition_amount(std::nanf(""), 2.0f, 4.0f), 0.0f);
    CrossFade fade(renderer("mesh"), renderer("mesh"));
    fade.set_amount(std::nanf(""));
    EXPECT_EQ(fade.amount(), 0.0f);
    fade.set_amount(7.0f);
    EXPECT_EQ(fade.amount(), 1.0f);
}

TEST(CrossFade, BayerRanksArePermutationOfAllSixtyFour)
{
    std::vector<int> seen(64, 0);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) seen[std::size_t(bayer_rank(x, y))] += 1;
    for (int count : seen) EXPECT_EQ(count, 1);
    // ordered: any 2x2 block holds ranks from all four quarters of the range
    for (int y = 0; y < 8; y += 2)
        for (int x = 0; x < 8; x += 2) {
            int quarters = 0;
            for (int dy = 0; dy < 2; ++dy)
                for (int dx = 0; dx < 2; ++dx) quarters |= 1 << (bayer_rank(x + dx, y + dy) / 16);
            EXPECT_EQ(quarters, 15);
        }
}

} // namespace
} // namespace standin
