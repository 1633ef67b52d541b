// bench --variants (app/variants.h).
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "variants.h"

namespace envshadow::app {
namespace {

using render::AtlasMode;
using render::PcfKernel;
using render::RenderSettings;

TEST(Variants, ItemsApplyLeftToRight) {
    const RenderSettings base;
    EXPECT_EQ(apply_variant(base, "baseline").caster_lod, 0.0f);
    EXPECT_TRUE(apply_variant(base, "optimised").depth_prepass);
    const RenderSettings v =
        apply_variant(base, "baseline, caster-lod=0.25,depth-bits=32,tile=128,atlas=per-tile,pcf=wide");
    EXPECT_EQ(v.caster_lod, 0.25f);
    EXPECT_FALSE(v.depth_prepass);
    EXPECT_EQ(v.depth_bits, 32);
    EXPECT_EQ(v.tile_size, 128);
    EXPECT_EQ(v.atlas, AtlasMode::per_tile);
    EXPECT_EQ(v.pcf, PcfKernel::wide);
    EXPECT_EQ(apply_variant(base, "caster-lod=off").caster_lod, 0.0f);
    EXPECT_FALSE(apply_variant(base, "prepass=off").depth_prepass);
    EXPECT_TRUE(apply_variant(base, "baseline,prepass=on").depth_prepass);  // later items win
    const RenderSettings off = apply_variant(base, "ubo=off,cull=off,specialise=off,tiles=off,flat=off");
    EXPECT_FALSE(off.lights_uniform_block || off.cull_back_faces || off.specialise_shaders || off.shadow_tile_lists ||
                 off.flat_receivers);
    EXPECT_EQ(apply_variant(base, "").tile_size, base.tile_size);
    EXPECT_EQ(apply_variant(base, "tile-sizes=sqrt").tile_sizing, render::TileSizing::sqrt_share);
    EXPECT_EQ(apply_variant(base, "tile-sizes=uniform").tile_sizing, render::TileSizing::uniform);
    for (const char* bad : {"fast", "prepass=maybe", "tile-sizes=big", "caster-lod=x", "caster-lod=-1",
                            "caster-lod=nan", "tile=64", "depth-bits=24", "colour=red"})
        EXPECT_THROW(apply_variant(base, bad), UsageError) << bad;
}

// The shadow cache: on by default, off in the baseline, as bench --variants writes it.
TEST(Variants, ShadowCacheAndFit) {
    const RenderSettings base;
    EXPECT_TRUE(base.shadow_cache);
    EXPECT_EQ(base.shadow_fit, render::ShadowFit::frame);
    const std::vector<Variant> variants = parse_variants("shadow_cache=off;shadow_cache=on", base);
    ASSERT_EQ(variants.size(), 2u);
    EXPECT_FALSE(variants[0].settings.shadow_cache);
    EXPECT_TRUE(variants[1].settings.shadow_cache);
    EXPECT_FALSE(apply_variant(base, "shadow-cache=off").shadow_cache);
    EXPECT_EQ(apply_variant(base, "shadow-fit=animation").shadow_fit, render::ShadowFit::animation);
    EXPECT_EQ(apply_variant(base, "shadow_fit=animation,shadow-fit=frame").shadow_fit, render::ShadowFit::frame);
    const RenderSettings first = apply_variant(base, "baseline");
    EXPECT_FALSE(first.shadow_cache);
    EXPECT_EQ(first.shadow_fit, render::ShadowFit::frame);  // the first renderer's fits, frame by frame
    EXPECT_TRUE(apply_variant(base, "baseline,shadow_cache=on").shadow_cache);
    for (const char* bad : {"shadow_cache=yes", "shadow-fit=scene"})
        EXPECT_THROW(apply_variant(base, bad), UsageError) << bad;
}

TEST(Variants, SemicolonsSeparateVariantsAndErrorsNameTheFlag) {
    RenderSettings base;
    base.tile_size = 512;
    const std::vector<Variant> variants = parse_variants("baseline;optimised;tile=128", base);
    ASSERT_EQ(variants.size(), 3u);
    EXPECT_EQ(variants[0].label, "baseline");
    EXPECT_FALSE(variants[0].settings.depth_prepass);
    EXPECT_EQ(variants[0].settings.tile_size, 512);
    EXPECT_TRUE(variants[1].settings.depth_prepass);
    EXPECT_EQ(variants[2].settings.tile_size, 128);
    const std::vector<Variant> none = parse_variants("", base);
    ASSERT_EQ(none.size(), 1u);
    EXPECT_EQ(none[0].label, "");
    EXPECT_EQ(none[0].settings.tile_size, 512);
    try {
        parse_variants("baseline;tile=64", base);
        ADD_FAILURE() << "no error";
    } catch (const UsageError& e) {
        EXPECT_EQ(std::string(e.what()), "--variants: shadow tile size 64 is outside 128..2048");
    }
}

// Every setting of the table is a key, by the same name, taking the values its option takes.
TEST(Variants, EveryTableKeyTakesItsValuesAndRejectsOthers) {
    const RenderSettings base;
    for (const render::SettingInfo& setting : render::setting_table()) {
        const std::string key(setting.name);
        std::vector<std::string> values = setting.choices;
        if (values.empty()) values = {setting.format(render::baseline(base)), setting.format(base)};
        for (const std::string& value : values) {
            const RenderSettings v = apply_variant(base, key + "=" + value);
            EXPECT_EQ(setting.format(v), value) << key;
        }
        EXPECT_THROW(apply_variant(base, key + "=nonsense"), UsageError) << key;
    }
    try {
        apply_variant(base, "colour=red");
        ADD_FAILURE() << "no error";
    } catch (const UsageError& e) {
        const std::string message = e.what();
        for (const render::SettingInfo& setting : render::setting_table())
            EXPECT_NE(message.find(setting.name), std::string::npos) << setting.name << " missing from " << message;
    }
}

}  // namespace
}  // namespace envshadow::app
