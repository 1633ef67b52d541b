// The render settings' options (app/setting_options.h): every command that renders takes every setting of
// render::setting_table() by its name, with its default, and reads it as the table does.
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "commands.h"
#include "core/error.h"
#include "core/tonemap.h"
#include "env/cells.h"
#include "gl/context.h"
#include "gl/timer.h"
#include "options.h"
#include "setting_options.h"

namespace envshadow::app {
namespace {

struct Cli {
    CLI::App app{"envshadow"};
    std::vector<Command> commands = {add_render_command(app), add_bench_command(app), add_view_command(app)};
};

TEST(SettingOptions, EveryCommandListsEverySettingByItsName) {
    Cli cli;
    for (const char* command : {"render", "bench", "view"}) {
        const std::string help = cli.app.get_subcommand(command)->help();
        for (const render::SettingInfo& setting : render::setting_table()) {
            const std::string option = "--" + std::string(setting.name) + " ";
            EXPECT_NE(help.find(option), std::string::npos) << command << " --help lacks " << option;
            const std::string with_default = "(default " + setting.format(command_defaults()) + ")";
            EXPECT_NE(help.find(with_default), std::string::npos) << command << ": " << setting.name;
        }
        EXPECT_NE(help.find("--baseline"), std::string::npos) << command;
    }
}

TEST(SettingOptions, CommandsDefaultToTheBestPictureAndOtherwiseTheEngine) {
    render::RenderSettings engine;
    render::RenderSettings commands = command_defaults();
    EXPECT_EQ(commands.msaa, 4);
    EXPECT_EQ(commands.shading, render::ShadingMode::ratio);
    EXPECT_EQ(commands.shadows, render::ShadowMode::soft);
    EXPECT_EQ(commands.shadow_rate, render::ShadowRate::half);
    commands.msaa = engine.msaa;
    commands.shading = engine.shading;
    commands.shadows = engine.shadows;
    commands.shadow_rate = engine.shadow_rate;
    for (const render::SettingInfo& setting : render::setting_table())
        EXPECT_EQ(setting.format(commands), setting.format(engine)) << setting.name;
}

TEST(SettingOptions, GivenOptionsApplyAfterTheBaselineAndNameTheFlag) {
    SettingOptions options;
    options.baseline = true;
    options.given = {{"prepass", "on"}, {"tile", "512"}, {"pcf", "wide"}};
    const render::RenderSettings s = settings_from(options, command_defaults());
    EXPECT_TRUE(s.depth_prepass);
    EXPECT_FALSE(s.cull_back_faces);  // the baseline's
    EXPECT_EQ(s.tile_size, 512);
    EXPECT_EQ(s.pcf, render::PcfKernel::wide);
    EXPECT_EQ(s.msaa, 4);
    options.given = {{"tile", "64"}};
    try {
        settings_from(options, command_defaults());
        ADD_FAILURE() << "no error";
    } catch (const UsageError& e) {
        EXPECT_EQ(std::string(e.what()), "--tile: shadow tile size 64 is outside 128..2048");
    }
}

TEST(SettingOptions, TheCommandLineTakesEveryValueOfEverySetting) {
    for (const render::SettingInfo& setting : render::setting_table()) {
        std::vector<std::string> values = setting.choices;
        if (values.empty()) values = {setting.format(render::RenderSettings{})};
        for (const std::string& value : values) {
            Cli cli;
            cli.app.parse(std::vector<std::string>{value, "--" + std::string(setting.name), "view"});  // reversed
            EXPECT_TRUE(cli.commands[2].app->parsed()) << setting.name;
        }
        Cli cli;
        EXPECT_THROW(cli.app.parse(std::vector<std::string>{"nonsense", "--" + std::string(setting.name), "view"}),
                     CLI::ValidationError)
            << setting.name;
    }
}

TEST(SettingOptions, ScreenshotJsonNamesEverySettingAsTheCommandLineDoes) {
    const nlohmann::json json = settings_json(command_defaults());
    for (const render::SettingInfo& setting : render::setting_table()) ASSERT_TRUE(json.contains(setting.name));
    EXPECT_EQ(json["tile-sizes"], "share");
    EXPECT_EQ(json["msaa"], 4);
    EXPECT_EQ(json["depth-bias"], 0.5);
    EXPECT_FALSE(json.contains("tile_sizes"));
}

std::string readme() {
    std::ifstream file(ENVSHADOW_SOURCE_DIR "/README.md");
    std::stringstream text;
    text << file.rdbuf();
    return text.str();
}

std::string joined(const std::vector<std::string>& names) {
    std::string text;
    for (const std::string& name : names) text += (text.empty() ? "" : "|") + name;
    return text;
}

// README's command-line reference names every setting with its values, as --help does, and the other
// named choices as their tables spell them.
TEST(SettingOptions, ReadmeListsEverySettingAndEveryNamedChoice) {
    const std::string text = readme();
    ASSERT_FALSE(text.empty());
    for (const render::SettingInfo& setting : render::setting_table()) {
        const std::string entry = "`--" + std::string(setting.name) + " " + setting.values() + "`";
        EXPECT_NE(text.find(entry), std::string::npos) << "README lacks " << entry;
    }
    EXPECT_NE(text.find("[--baseline]"), std::string::npos);
    std::vector<std::string> hemispheres = enum_value_names<Hemisphere>();
    const std::vector<std::string> choices[] = {enum_value_names<ToneMap>(), gl::headless_backend_names(),
                                                gl::pass_timing_choices(), enum_value_names<Method>(), hemispheres};
    const char* flags[] = {"--tonemap ", "--backend ", "--pass-timing ", "--method ", "--hemisphere "};
    for (std::size_t i = 0; i < std::size(flags); ++i) {
        const std::string entry = flags[i] + joined(choices[i]);
        EXPECT_NE(text.find(entry), std::string::npos) << "README lacks " << entry;
    }
    hemispheres.emplace_back(kAutoHemisphere);
    EXPECT_NE(text.find("--hemisphere " + joined(hemispheres)), std::string::npos);
}

}  // namespace
}  // namespace envshadow::app
