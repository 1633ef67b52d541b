// The shader variant key (render/shader_variant.h) against the settings table: a setting whose change the
// table says rebuilds programs changes the key, no other does.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "render/render_settings.h"
#include "render/shader_variant.h"

namespace envshadow::render {
namespace {

constexpr ShaderSupport kEverything{.viewport_layer_array = true, .uniform_block_fits = true};

// The values of a row: its choices, or its range's ends.
std::vector<std::string> values_of(const SettingInfo& setting) {
    if (!setting.choices.empty()) return setting.choices;
    return {setting.kind == SettingKind::integer ? std::to_string(int(setting.min)) : std::to_string(setting.min)};
}

// From the defaults, from ratio shading (where --shadow-rate picks the programs) and from its half rate
// (where --sun-per-pixel does).
TEST(ShaderVariant, OnlyTheProgramSettingsChangeTheKey) {
    RenderSettings ratio;
    ratio.shading = ShadingMode::ratio;
    RenderSettings half = ratio;
    half.shadow_rate = ShadowRate::half;
    for (const SettingInfo& setting : setting_table()) {
        bool key_changed = false;
        for (const RenderSettings& start : {RenderSettings{}, ratio, half}) {
            const ShaderVariant base = shader_variant(start, kEverything);
            for (const std::string& value : values_of(setting)) {
                RenderSettings s = start;
                setting.parse(s, value);
                key_changed |= shader_variant(s, kEverything) != base;
            }
        }
        EXPECT_EQ(key_changed, setting.effect == SettingEffect::programs) << setting.name;
    }
}

TEST(ShaderVariant, ShadowRateSplitsRatioShadingOnly) {
    RenderSettings s;
    s.shadow_rate = ShadowRate::half;
    EXPECT_FALSE(shader_variant(s, kEverything).fraction_pass);  // cells: the sum does not split
    s.shading = ShadingMode::ratio;
    EXPECT_TRUE(shader_variant(s, kEverything).fraction_pass);
    s.shadow_rate = ShadowRate::fragment;
    EXPECT_FALSE(shader_variant(s, kEverything).fraction_pass);
}

TEST(ShaderVariant, WhatTheContextLacksFallsBack) {
    RenderSettings s;
    s.atlas = AtlasMode::viewport_array;
    EXPECT_EQ(shader_variant(s, kEverything).atlas, AtlasMode::viewport_array);
    EXPECT_EQ(shader_variant(s, ShaderSupport{}).atlas, AtlasMode::clip_distances);
    EXPECT_FALSE(shader_variant(s, ShaderSupport{}).lights_uniform_block);
    s.depth_prepass = false;  // the tile lists need the pre-pass's depths
    EXPECT_FALSE(shader_variant(s, kEverything).tile_lists);
}

TEST(ShaderVariant, DefinesFollowTheKey) {
    ShaderVariant v;
    v.ratio = v.soft_shadows = v.lights_uniform_block = true;
    EXPECT_EQ(shade_defines(v), (std::vector<std::string>{"LIGHTS_UNIFORM_BLOCK", "SHADING_RATIO", "SOFT_SHADOWS"}));
    v.atlas = AtlasMode::per_tile;
    EXPECT_EQ(atlas_defines(v), (std::vector<std::string>{"LIGHTS_UNIFORM_BLOCK"}));
}

}  // namespace
}  // namespace envshadow::render
