#pragma once
// The viewer's screenshot (F12 or P): the frame without the UI as linear EXR and tone-mapped PNG, and
// beside them the JSON of what it was taken with, every render setting by its command-line name.
#include <string>

#include <nlohmann/json.hpp>

#include "core/image.h"
#include "scene/scene.h"
#include "viewer/panels.h"

namespace envshadow::app {

struct ScreenshotContext {
    const Scene& scene;
    const ViewerControls& controls;
    Camera camera;            // the orbit camera's, not the scene's
    std::string environment;  // the map's source ("" while the first loads)
    std::string method;       // the light method's name
};

nlohmann::json screenshot_json(const ScreenshotContext& context);

// Writes screenshots/view_SCENE_METHOD_NLIGHTS_TIMESTAMP.{exr,png,json}; returns that stem.
std::string write_screenshot(const Image& linear, const ScreenshotContext& context);

}  // namespace envshadow::app
