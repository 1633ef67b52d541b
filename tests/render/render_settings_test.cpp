// Option names and range checks of the renderer's settings.
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
    EXPECT_NO_THROW(validate(s));
}

TEST(RenderSettings, NamesRoundTrip) {
    for (auto m : {AtlasMode::clip_distances, AtlasMode::viewport_array, AtlasMode::per_tile})
        EXPECT_EQ(parse_atlas_mode(to_string(m), "--atlas"), m);
    for (auto k : {PcfKernel::hardware_2x2, PcfKernel::wide}) EXPECT_EQ(parse_pcf_kernel(to_string(k), "--pcf"), k);
    for (auto m : {SpecularMode::blended, SpecularMode::single})
        EXPECT_EQ(parse_specular_mode(to_string(m), "--specular"), m);
    for (auto c : {CapKind::solid_angle, CapKind::weighted}) EXPECT_EQ(parse_cap_kind(to_string(c), "--cap"), c);
    for (auto d : {DiffuseMode::center, DiffuseMode::cap}) EXPECT_EQ(parse_diffuse_mode(to_string(d), "--diffuse"), d);
    EXPECT_EQ(parse_pcf_kernel("2x2", "--pcf"), PcfKernel::hardware_2x2);
    EXPECT_EQ(parse_cap_kind("solid-angle", "--cap"), CapKind::solid_angle);
}

TEST(RenderSettings, BadValuesAreUsageErrorsNamingTheOption) {
    try {
        parse_pcf_kernel("3x3", "--pcf");
        FAIL();
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find("--pcf"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("wide"), std::string::npos);
    }
    RenderSettings s;
    s.tile_size = 64;
    EXPECT_THROW(validate(s), UsageError);
    s.tile_size = 4096;
    EXPECT_THROW(validate(s), UsageError);
    s = RenderSettings{};
    s.depth_bits = 24;
    EXPECT_THROW(validate(s), UsageError);
    s = RenderSettings{};
    s.normal_offset = -1.0f;
    EXPECT_THROW(validate(s), UsageError);
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
}

TEST(RenderSettings, VariantsApplyLeftToRight) {
    const RenderSettings base;
    EXPECT_EQ(apply_variant(base, "baseline", "--variants").caster_lod, 0.0f);
    EXPECT_TRUE(apply_variant(base, "optimised", "--variants").depth_prepass);
    const RenderSettings v =
        apply_variant(base, "baseline, caster-lod=0.25,depth-bits=32,tile=128,atlas=per-tile,pcf=wide", "--variants");
    EXPECT_EQ(v.caster_lod, 0.25f);
    EXPECT_FALSE(v.depth_prepass);
    EXPECT_EQ(v.depth_bits, 32);
    EXPECT_EQ(v.tile_size, 128);
    EXPECT_EQ(v.atlas, AtlasMode::per_tile);
    EXPECT_EQ(v.pcf, PcfKernel::wide);
    EXPECT_EQ(apply_variant(base, "caster-lod=off", "--variants").caster_lod, 0.0f);
    EXPECT_FALSE(apply_variant(base, "prepass=off", "--variants").depth_prepass);
    const RenderSettings off = apply_variant(base, "ubo=off,cull=off,specialise=off,tiles=off,flat=off", "--variants");
    EXPECT_FALSE(off.lights_uniform_block || off.cull_back_faces || off.specialise_shaders || off.shadow_tile_lists ||
                 off.flat_receivers);
    const RenderSettings none = baseline(base);
    EXPECT_FALSE(none.lights_uniform_block || none.cull_back_faces || none.specialise_shaders ||
                 none.shadow_tile_lists || none.flat_receivers);
    EXPECT_EQ(apply_variant(base, "", "--variants").tile_size, base.tile_size);
    for (const char* bad : {"fast", "prepass=maybe", "caster-lod=x", "caster-lod=-1", "caster-lod=nan", "tile=64",
                            "depth-bits=24", "colour=red"})
        EXPECT_THROW(apply_variant(base, bad, "--variants"), UsageError) << bad;
}

}  // namespace
}  // namespace envshadow::render
