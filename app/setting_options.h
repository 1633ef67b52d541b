#pragma once
// The render settings as command-line options: one option per row of render::setting_table(), the same
// name, values and help for render, bench and view, and --baseline. The commands start from
// command_defaults().
#include <map>
#include <span>
#include <string>
#include <string_view>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "render/render_settings.h"

namespace envshadow::app {

// What the commands start from: the best picture (docs/DESIGN.md §4.1, §5.9, §5.14): 4 samples per pixel,
// the ratio estimator and soft shadows, the shadowed fraction once per 2x2 pixels. RenderSettings' own defaults (one
// sample, the paper's sum over the cells with hard shadows) are what the engine's tests compare; `--shading cells
// --shadows hard` gives the paper's method.
render::RenderSettings command_defaults();

// The settings options as given.
struct SettingOptions {
    bool baseline = false;                                  // --baseline
    std::map<std::string, std::string, std::less<>> given;  // by setting name: the text after --NAME
};

// A value that one command's option takes besides the table's, and handles itself (render's --atlas all).
struct ExtraValue {
    std::string_view setting, value, help;
};

// --NAME for every setting, checked by its row (its help ends with `defaults`' value), and --baseline.
void add_setting_options(CLI::App* app, SettingOptions* options, const render::RenderSettings& defaults,
                         std::span<const ExtraValue> extra = {});

// `defaults`, then render::baseline() with --baseline, then each given option; validated. UsageError
// naming the flag.
render::RenderSettings settings_from(const SettingOptions& options, render::RenderSettings defaults);

// Every setting by its name, numbers as numbers: the viewer's screenshot JSON.
nlohmann::json settings_json(const render::RenderSettings& settings);

}  // namespace envshadow::app
