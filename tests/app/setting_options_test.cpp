// The render settings' options (app/setting_options.h): every command that renders takes every setting of
// render::setting_table() by its name, with its default, and reads it as the table does.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "commands.h"
#include "core/error.h"
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

TEST(SettingOptions, CommandsDefaultToFourSamplesAndOtherwiseTheEngine) {
    render::RenderSettings engine;
    render::RenderSettings commands = command_defaults();
    EXPECT_EQ(commands.msaa, 4);
    commands.msaa = engine.msaa;
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

}  // namespace
}  // namespace envshadow::app
