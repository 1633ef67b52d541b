// The viewer's screenshot JSON (app/viewer/screenshot.h): the view, and every render setting by the
// name the command line gives it, so that the shot can be taken again with `envshadow render`.
#include <gtest/gtest.h>

#include "setting_options.h"
#include "viewer/screenshot.h"

namespace envshadow::app {
namespace {

TEST(Screenshot, JsonHasTheViewAndEverySettingByItsOptionName) {
    Scene scene;
    scene.file = "assets/scenes/spheres.json";
    ViewerControls controls;
    controls.settings = command_defaults();
    controls.settings.tile_sizing = render::TileSizing::sqrt_share;
    controls.lights = 64;
    Camera camera;
    camera.position = {1.0f, 2.0f, 3.0f};
    const nlohmann::json json = screenshot_json({scene, controls, camera, "builtin:sky", "lloyd"});
    EXPECT_EQ(json["scene"], "assets/scenes/spheres.json");
    EXPECT_EQ(json["environment"], "builtin:sky");
    EXPECT_EQ(json["lights"], 64);
    EXPECT_EQ(json["camera"]["position"][2], 3.0f);
    for (const render::SettingInfo& setting : render::setting_table())
        EXPECT_TRUE(json.contains(setting.name)) << setting.name;
    EXPECT_EQ(json["tile-sizes"], "sqrt");
    EXPECT_EQ(json["msaa"], 4);
}

}  // namespace
}  // namespace envshadow::app
