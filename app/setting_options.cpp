#include "setting_options.h"

#include <algorithm>
#include <string>

#include "core/error.h"

namespace envshadow::app {
namespace {

// The row's own parse and check, in the engine's words: "" when `text` is a value of it.
std::string rejection(const render::SettingInfo& setting, const std::string& text) {
    try {
        render::RenderSettings scratch;
        setting.parse(scratch, text);
        setting.check(scratch);
        return "";
    } catch (const UsageError& e) {
        return e.what();
    }
}

}  // namespace

render::RenderSettings command_defaults() {
    render::RenderSettings settings;
    settings.msaa = 4;
    settings.shading = render::ShadingMode::ratio;
    settings.shadows = render::ShadowMode::soft;
    settings.shadow_rate = render::ShadowRate::half;
    return settings;
}

void add_setting_options(CLI::App* app, SettingOptions* options, const render::RenderSettings& defaults,
                         std::span<const ExtraValue> extra) {
    app->add_flag("--baseline", options->baseline,
                  "The first working renderer: every optimisation off (the options below apply after it)");
    for (const render::SettingInfo& setting : render::setting_table()) {
        std::string values = setting.values(), help(setting.help);
        for (const ExtraValue& e : extra)
            if (e.setting == setting.name) {
                values += "|" + std::string(e.value);
                help += "; " + std::string(e.value) + ": " + std::string(e.help);
            }
        const std::string name(setting.name);
        app->add_option_function<std::string>(
               "--" + name, [options, name](const std::string& text) { options->given[name] = text; },
               help + " (default " + setting.format(defaults) + ")")
            ->type_name(values)
            ->check(CLI::Validator(
                [&setting, extra](std::string& text) {
                    for (const ExtraValue& e : extra)
                        if (e.setting == setting.name && e.value == text) return std::string();
                    return rejection(setting, text);
                },
                ""));
    }
}

render::RenderSettings settings_from(const SettingOptions& options, render::RenderSettings settings) {
    if (options.baseline) settings = render::baseline(settings);
    for (const auto& [name, text] : options.given) {
        const render::SettingInfo* setting = render::find_setting(name);
        if (!setting) throw UsageError("--" + name + ": no such setting");
        try {
            setting->parse(settings, text);
            setting->check(settings);
        } catch (const UsageError& e) {
            throw UsageError("--" + name + ": " + e.what());
        }
    }
    render::validate(settings);
    return settings;
}

nlohmann::json settings_json(const render::RenderSettings& settings) {
    nlohmann::json json = nlohmann::json::object();
    for (const render::SettingInfo& setting : render::setting_table()) {
        const std::string text = setting.format(settings);
        std::string name(setting.name);
        if (setting.kind == render::SettingKind::integer)
            json[name] = std::stoi(text);
        else if (setting.kind == render::SettingKind::number)
            json[name] = std::stod(text);
        else
            json[name] = text;
    }
    return json;
}

}  // namespace envshadow::app
