// Option names and range checks of the renderer's settings.
#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "render/render_settings.h"

namespace envshadow::render {
namespace {

TEST(RenderSettings, DefaultsAreTheDocumentedOnes) {
    const RenderSettings s;
    EXPECT_EQ(s.tile_size, 256);
    EXPECT_EQ(s.depth_bits, 16);
    EXPECT_EQ(s.cap, CapKind::weighted);  // the better cap (docs/DESIGN.md §3)
    EXPECT_EQ(s.specular, SpecularMode::blended);
    EXPECT_EQ(s.diffuse, DiffuseMode::center);
    EXPECT_EQ(s.atlas, AtlasMode::clip_distances);
    EXPECT_EQ(s.msaa, 1);                       // the engine's; the commands ask for 4
    EXPECT_EQ(s.shadows, ShadowMode::hard);     // soft costs 2-4x the shading on flyover (docs/PERFORMANCE.md)
    EXPECT_TRUE(s.shadow_cache);                // issue 18: the same image, less work (docs/DESIGN.md §5.11)
    EXPECT_EQ(s.shadow_fit, ShadowFit::frame);  // the goldens' fits; animation asked for (changes their shadows)
    EXPECT_NO_THROW(validate(s));
}

template <typename Enum>
void expect_names_round_trip() {
    for (const auto& [value, name] : enum_names(Enum{})) {
        EXPECT_EQ(to_string(value), name);
        EXPECT_EQ(parse_enum<Enum>(name), value);
    }
}

TEST(RenderSettings, NamesRoundTrip) {
    expect_names_round_trip<AtlasMode>();
    expect_names_round_trip<PcfKernel>();
    expect_names_round_trip<SpecularMode>();
    expect_names_round_trip<CapKind>();
    expect_names_round_trip<DiffuseMode>();
    expect_names_round_trip<ShadingMode>();
    expect_names_round_trip<ShadowMode>();
    expect_names_round_trip<ShadowFit>();
    expect_names_round_trip<TileSizing>();
    EXPECT_EQ(enum_value_names<ShadowFit>(), (std::vector<std::string>{"frame", "animation"}));
    EXPECT_EQ(parse_enum<PcfKernel>("2x2"), PcfKernel::hardware_2x2);
    EXPECT_EQ(parse_enum<CapKind>("solid-angle"), CapKind::solid_angle);
    EXPECT_EQ(to_string(TileSizing::sqrt_share), "sqrt");
}

// Values a row accepts: its choices, or its range's ends.
std::vector<std::string> valid_values(const SettingInfo& setting) {
    if (!setting.choices.empty()) return setting.choices;
    RenderSettings s;
    std::vector<std::string> values;
    for (double bound : {setting.min, setting.max}) {
        if (!std::isfinite(bound)) continue;
        setting.parse(s, setting.kind == SettingKind::integer ? std::to_string(int(bound)) : std::to_string(bound));
        values.push_back(setting.format(s));
    }
    return values;
}

// The engine's messages say what is wrong in its own words; app/ adds the flag's name.
std::string usage_error_of(const auto& throwing) {
    try {
        throwing();
    } catch (const UsageError& e) {
        return e.what();
    }
    return "no UsageError";
}

TEST(RenderSettings, BadValuesAreUsageErrorsSayingWhatIsAllowed) {
    EXPECT_EQ(usage_error_of([] { parse_enum<PcfKernel>("3x3"); }), "'3x3' is not one of 2x2, wide");
    EXPECT_EQ(usage_error_of([] { parse_enum<ShadowMode>("pcss"); }), "'pcss' is not one of hard, soft");
    RenderSettings s;
    s.tile_size = 64;
    EXPECT_EQ(usage_error_of([&] { validate(s); }), "shadow tile size 64 is outside 128..2048");
    s.tile_size = 4096;
    EXPECT_THROW(validate(s), UsageError);
    s = RenderSettings{};
    s.depth_bits = 24;
    EXPECT_EQ(usage_error_of([&] { validate(s); }), "shadow depth bits 24 is not 16 or 32");
    s = RenderSettings{};
    s.caster_lod = 5.0f;
    EXPECT_EQ(usage_error_of([&] { validate(s); }), "caster LOD error 5 is outside 0..4 shadow texels");
    for (int samples : msaa_sample_counts()) {
        s = RenderSettings{};
        s.msaa = samples;
        EXPECT_NO_THROW(validate(s)) << samples;
    }
    s.msaa = 3;
    EXPECT_EQ(usage_error_of([&] { validate(s); }), "MSAA samples 3 is not 1, 2, 4 or 8");
    s = RenderSettings{};
    s.normal_offset = -1.0f;
    EXPECT_EQ(usage_error_of([&] { validate(s); }), "normal offset -1 is below 0");
    s.normal_offset = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(usage_error_of([&] { validate(s); }), "normal offset nan is not finite");
}

// The table: one row per member, each name once, every value it lists reads back as itself, its
// default within range; what it rejects.
TEST(SettingTable, RowsRoundTripTheirValues) {
    std::set<std::string_view> names;
    for (const SettingInfo& setting : setting_table()) {
        SCOPED_TRACE(std::string(setting.name));
        EXPECT_TRUE(names.insert(setting.name).second) << "named twice";
        EXPECT_EQ(find_setting(setting.name), &setting);
        EXPECT_FALSE(setting.help.empty());
        RenderSettings s;
        const std::string default_text = setting.format(s);
        setting.parse(s, default_text);
        EXPECT_EQ(setting.format(s), default_text);
        EXPECT_NO_THROW(setting.check(s));
        for (const std::string& value : valid_values(setting)) {
            setting.parse(s, value);
            EXPECT_NO_THROW(setting.check(s)) << value;
            EXPECT_EQ(setting.format(s), value);
        }
        EXPECT_THROW(setting.parse(s, "nonsense"), UsageError);
    }
    EXPECT_EQ(find_setting("no-such-setting"), nullptr);
    EXPECT_EQ(names.size(), 34u);  // RenderSettings' members
}

TEST(SettingTable, ValuesAndRangesSayWhatIsAllowed) {
    EXPECT_EQ(find_setting("pcf")->values(), "2x2|wide");
    EXPECT_EQ(find_setting("prepass")->values(), "on|off");
    EXPECT_EQ(find_setting("msaa")->values(), "1|2|4|8");
    EXPECT_EQ(find_setting("tile")->values(), "128..2048");
    EXPECT_EQ(find_setting("slope-bias")->values(), ">= 0");
    RenderSettings s;
    find_setting("caster-lod")->parse(s, "off");
    EXPECT_EQ(s.caster_lod, 0.0f);
    find_setting("caster-lod")->parse(s, "1.5");
    EXPECT_EQ(s.caster_lod, 1.5f);
    EXPECT_THROW(find_setting("caster-lod")->parse(s, "1.5x"), UsageError);
    EXPECT_THROW(find_setting("tile")->parse(s, "128.5"), UsageError);
    find_setting("tile")->parse(s, "64");  // a number, out of range: check() says so
    EXPECT_EQ(usage_error_of([&] { find_setting("tile")->check(s); }), "shadow tile size 64 is outside 128..2048");
}

TEST(RenderSettings, BaselineTurnsEveryOptimisationOff) {
    const RenderSettings optimised;
    EXPECT_GT(optimised.caster_lod, 0.0f);
    EXPECT_TRUE(optimised.depth_prepass);
    const RenderSettings first = baseline(optimised);
    EXPECT_EQ(first.caster_lod, 0.0f);
    EXPECT_FALSE(first.depth_prepass);
    EXPECT_EQ(first.tile_size, optimised.tile_size);  // everything else stays
    EXPECT_EQ(first.atlas, optimised.atlas);
    for (bool RenderSettings::*each :
         {&RenderSettings::depth_prepass, &RenderSettings::lights_uniform_block, &RenderSettings::cull_back_faces,
          &RenderSettings::specialise_shaders, &RenderSettings::shadow_tile_lists, &RenderSettings::flat_receivers,
          &RenderSettings::shadow_cache}) {
        EXPECT_TRUE(optimised.*each);
        EXPECT_FALSE(first.*each);
    }
}

}  // namespace
}  // namespace envshadow::render
