#include "variants.h"

#include <algorithm>

#include "core/error.h"
#include "options.h"

namespace envshadow::app {
namespace {

std::string_view trim(std::string_view text) {
    while (!text.empty() && text.front() == ' ') text.remove_prefix(1);
    while (!text.empty() && text.back() == ' ') text.remove_suffix(1);
    return text;
}

// The pieces of `text` between `separator`s, in order (empty pieces kept).
std::vector<std::string_view> split(std::string_view text, char separator) {
    std::vector<std::string_view> pieces;
    for (std::size_t start = 0; start <= text.size();) {
        const std::size_t end = std::min(text.find(separator, start), text.size());
        pieces.push_back(text.substr(start, end - start));
        start = end + 1;
    }
    return pieces;
}

}  // namespace

std::string variant_keys() {
    std::string keys;
    for (const render::SettingInfo& setting : render::setting_table())
        keys += (keys.empty() ? "" : ", ") + std::string(setting.name);
    return keys;
}

render::RenderSettings apply_variant(render::RenderSettings settings, std::string_view variant) {
    for (std::string_view piece : split(variant, ',')) {
        const std::string_view item = trim(piece);
        if (item.empty() || item == "optimised" || item == "default") continue;
        if (item == "baseline") {
            settings = render::baseline(settings);
            continue;
        }
        const std::size_t eq = item.find('=');
        if (eq == std::string_view::npos)
            throw UsageError("'" + std::string(item) + "' is neither baseline, optimised nor key=value");
        std::string key(trim(item.substr(0, eq)));
        std::replace(key.begin(), key.end(), '_', '-');
        const render::SettingInfo* setting = render::find_setting(key);
        if (!setting) throw UsageError("unknown key '" + key + "' (" + variant_keys() + ")");
        setting->parse(settings, trim(item.substr(eq + 1)));
    }
    render::validate(settings);
    return settings;
}

std::vector<Variant> parse_variants(std::string_view text, const render::RenderSettings& settings) {
    if (text.empty()) return {Variant{"", settings}};
    std::vector<Variant> variants;
    for (std::string_view label : split(text, ';'))
        variants.push_back(
            {std::string(label), naming_flag("--variants", [&] { return apply_variant(settings, label); })});
    return variants;
}

}  // namespace envshadow::app
