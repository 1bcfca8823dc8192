// The viewer's script parser (apps/viewer/script.h): commands, their arguments, and the line named
// when one is wrong.
#include "viewer/script.h"

#include <standin/package.h>

#include <gtest/gtest.h>

namespace standin::viewer {
namespace {

// `set` takes any representation's run-time options, as the viewer passes them
Result<std::vector<ScriptCommand>> parse_script(const std::string& text, const std::string& name)
{
    static const std::vector<OptionSpec> options = [] {
        std::vector<OptionSpec> all;
        for (const Representation& r : representations()) all.insert(all.end(), r.render_options.begin(), r.render_options.end());
        return all;
    }();
    return viewer::parse_script(text, name, options);
}

std::vector<ScriptCommand> parse_ok(const std::string& text)
{
    Result<std::vector<ScriptCommand>> commands = parse_script(text, "s.txt");
    EXPECT_TRUE(commands.is_ok()) << commands.status().message();
    return commands ? *commands : std::vector<ScriptCommand>{};
}

std::string parse_error(const std::string& text)
{
    Result<std::vector<ScriptCommand>> commands = parse_script(text, "s.txt");
    EXPECT_FALSE(commands.is_ok());
    return commands ? std::string() : commands.status().message();
}

TEST(ViewerScript, ParsesEveryCommandOfTheIssue)
{
    std::vector<ScriptCommand> c = parse_ok("camera 30 -20 1.5\n"
                                            "show original\n"
                                            "show package 2\n"
                                            "split on\n"
                                            "debug fetches\n"
                                            "debug off\n"
                                            "resolution 400x300\n"
                                            "light 45 60\n"
                                            "screenshot out/a.png\n"
                                            "wait 3\n"
                                            "quit\n");
    ASSERT_EQ(c.size(), 11u);
    EXPECT_EQ(c[0].op, ScriptOp::camera);
    EXPECT_FLOAT_EQ(c[0].numbers[0], 30.0f);
    EXPECT_FLOAT_EQ(c[0].numbers[1], -20.0f);
    EXPECT_FLOAT_EQ(c[0].numbers[2], 1.5f);
    EXPECT_EQ(c[1].op, ScriptOp::show);
    EXPECT_EQ(c[1].word, "original");
    EXPECT_EQ(c[2].word, "package");
    EXPECT_EQ(c[2].count, 2);
    EXPECT_EQ(c[3].op, ScriptOp::split);
    EXPECT_EQ(c[3].word, "on");
    EXPECT_EQ(c[4].op, ScriptOp::debug);
    EXPECT_EQ(c[4].word, "fetches");
    EXPECT_EQ(c[5].word, ""); // off
    EXPECT_EQ(c[6].op, ScriptOp::resolution);
    EXPECT_EQ(c[6].size[0], 400);
    EXPECT_EQ(c[6].size[1], 300);
    EXPECT_EQ(c[7].op, ScriptOp::light);
    EXPECT_FLOAT_EQ(c[7].numbers[1], 60.0f);
    EXPECT_EQ(c[8].op, ScriptOp::screenshot);
    EXPECT_EQ(c[8].word, "out/a.png");
    EXPECT_EQ(c[9].op, ScriptOp::wait);
    EXPECT_EQ(c[9].count, 3);
    EXPECT_EQ(c[10].op, ScriptOp::quit);
    EXPECT_EQ(c[10].line, 11);
}

TEST(ViewerScript, CommentsAndBlankLinesKeepLineNumbers)
{
    std::vector<ScriptCommand> c = parse_ok("# a comment\n\n   \nwait 1   # trailing comment\r\nquit");
    ASSERT_EQ(c.size(), 2u);
    EXPECT_EQ(c[0].line, 4);
    EXPECT_EQ(c[0].count, 1);
    EXPECT_EQ(c[1].line, 5);
}

TEST(ViewerScript, ExtraCommands)
{
    std::vector<ScriptCommand> c = parse_ok("window 320x240\nresolution window\nsplit side\nsplit-position 0.25\n"
                                            "set march seed\nset steps 50\nset hit-range 0.02\nset coarse off\n"
                                            "projection orthographic\npan 0.1 -0.2\nlight camera\npanels off\n"
                                            "overlay on\nreload\nreset\ndebug holes\nshadows on\n");
    ASSERT_EQ(c.size(), 17u);
    EXPECT_EQ(c[0].op, ScriptOp::window);
    EXPECT_EQ(c[0].size[0], 320);
    EXPECT_EQ(c[1].word, "window");
    EXPECT_EQ(c[2].word, "side");
    EXPECT_FLOAT_EQ(c[3].numbers[0], 0.25f);
    EXPECT_EQ(c[4].word, "march");
    EXPECT_EQ(c[4].value, "seed");
    EXPECT_EQ(c[5].value, "50"); // `set` values stay text, checked against the declarations
    EXPECT_EQ(c[6].value, "0.02");
    EXPECT_EQ(c[7].value, "off");
    EXPECT_EQ(c[8].word, "orthographic");
    EXPECT_FLOAT_EQ(c[9].numbers[1], -0.2f);
    EXPECT_EQ(c[10].word, "camera");
    EXPECT_EQ(c[11].op, ScriptOp::panels);
    EXPECT_EQ(c[12].op, ScriptOp::overlay);
    EXPECT_EQ(c[13].op, ScriptOp::reload);
    EXPECT_EQ(c[14].op, ScriptOp::reset);
    EXPECT_EQ(c[15].word, "holes");
    EXPECT_EQ(c[16].op, ScriptOp::shadows);
    EXPECT_EQ(c[16].word, "on");
}

TEST(ViewerScript, UnknownCommandNamesTheLine)
{
    std::string message = parse_error("wait 1\n\nfly away\nquit\n");
    EXPECT_NE(message.find("s.txt line 3"), std::string::npos) << message;
    EXPECT_NE(message.find("unknown command 'fly'"), std::string::npos) << message;
}

TEST(ViewerScript, BadArgumentsAreRefusedWithTheirLine)
{
    const std::pair<const char*, const char*> cases[] = {
        {"camera 1 2", "camera AZIMUTH ELEVATION DISTANCE"},
        {"camera 0 95 1", "elevation"},
        {"camera 0 0 -1", "distance"},
        {"camera x 0 1", "'x'"},
        {"camera nan 0 1", "'nan'"},
        {"show package 0", "package number"},
        {"show package", "show package N"},
        {"show everything", "show original"},
        {"split maybe", "split on|off|side"},
        {"debug sparkles", "debug off|parts"},
        {"resolution 400", "WxH"},
        {"resolution 0x300", "WxH"},
        {"resolution 400x300x2", "WxH"},
        {"light 10", "light AZIMUTH ELEVATION"},
        {"shadows maybe", "shadows on|off"},
        {"screenshot out.jpg", ".png"},
        {"wait -1", "frames"},
        {"wait 1.5", "frames"},
        {"quit now", "'quit'"},
        {"set shininess 3", "unknown option"},
        {"set steps 0", "--steps: 0 is out of range"},
        {"set hit-range 2", "--hit-range: 2 is out of range"},
    };
    for (const auto& [line, expected] : cases) {
        std::string message = parse_error(std::string("wait 1\n") + line + "\n");
        EXPECT_NE(message.find("s.txt line 2: "), std::string::npos) << line << ": " << message;
        EXPECT_NE(message.find(expected), std::string::npos) << line << ": " << message;
    }
}

TEST(ViewerScript, EmptyScriptIsNoCommands)
{
    EXPECT_TRUE(parse_ok("").empty());
    EXPECT_TRUE(parse_ok("\n# only a comment\n").empty());
}

TEST(ViewerScript, Sizes)
{
    int w = 0, h = 0;
    EXPECT_TRUE(parse_size("800x600", w, h));
    EXPECT_EQ(w, 800);
    EXPECT_EQ(h, 600);
    EXPECT_TRUE(parse_size("200X150", w, h));
    EXPECT_FALSE(parse_size("800x", w, h));
    EXPECT_FALSE(parse_size("16385x10", w, h));
    EXPECT_FALSE(parse_size("", w, h));
}

} // namespace
} // namespace standin::viewer
