#include "viewer/screenshot.h"

#include <ctime>
#include <filesystem>

#include "core/atomic_file.h"
#include "setting_options.h"

namespace envshadow::app {
namespace {

std::string timestamp() {
    const std::time_t now = std::time(nullptr);
    char text[32];
    std::strftime(text, sizeof text, "%Y%m%d-%H%M%S", std::localtime(&now));
    return text;
}

}  // namespace

nlohmann::json screenshot_json(const ScreenshotContext& context) {
    const ViewerControls& controls = context.controls;
    const Camera& camera = context.camera;
    nlohmann::json json = {
        {"scene", context.scene.file.string()},
        {"environment", context.environment},
        {"method", context.method},
        {"lights", controls.lights},
        {"seed", controls.seed},
        {"time", controls.time},
        {"exposure", controls.exposure},
        {"tonemap", to_string(controls.tone_map)},
        {"rotation_degrees", controls.rotation},
        {"camera",
         {{"position", {camera.position.x, camera.position.y, camera.position.z}},
          {"target", {camera.target.x, camera.target.y, camera.target.z}},
          {"fov_y_degrees", camera.fov_y_degrees}}},
    };
    json.update(settings_json(controls.settings));
    return json;
}

std::string write_screenshot(const Image& linear, const ScreenshotContext& context) {
    std::filesystem::create_directories("screenshots");
    const std::string stem = "screenshots/view_" + context.scene.file.stem().string() + "_" + context.method + "_N" +
                             std::to_string(context.controls.lights) + "_" + timestamp();
    write_exr(stem + ".exr", linear);
    write_png(stem + ".png", tonemap_to_srgb8(linear, context.controls.exposure, context.controls.tone_map));
    write_file_atomically(stem + ".json", screenshot_json(context).dump(2) + "\n");
    return stem;
}

}  // namespace envshadow::app
