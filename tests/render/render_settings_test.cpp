// Option names and range checks of the renderer's settings.
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

TEST(RenderSettings, NamesRoundTrip) {
    for (auto m : {AtlasMode::clip_distances, AtlasMode::viewport_array, AtlasMode::per_tile})
        EXPECT_EQ(parse_atlas_mode(to_string(m)), m);
    for (auto k : {PcfKernel::hardware_2x2, PcfKernel::wide}) EXPECT_EQ(parse_pcf_kernel(to_string(k)), k);
    for (auto m : {SpecularMode::blended, SpecularMode::single}) EXPECT_EQ(parse_specular_mode(to_string(m)), m);
    for (auto c : {CapKind::solid_angle, CapKind::weighted}) EXPECT_EQ(parse_cap_kind(to_string(c)), c);
    for (auto d : {DiffuseMode::center, DiffuseMode::cap}) EXPECT_EQ(parse_diffuse_mode(to_string(d)), d);
    for (auto m : {ShadowMode::hard, ShadowMode::soft}) EXPECT_EQ(parse_shadow_mode(to_string(m)), m);
    for (auto f : {ShadowFit::animation, ShadowFit::frame}) EXPECT_EQ(parse_shadow_fit(to_string(f)), f);
    EXPECT_EQ(parse_shadow_fit("frame"), ShadowFit::frame);
    EXPECT_EQ(names<ShadowFit>(), (std::vector<std::string>{"frame", "animation"}));
    EXPECT_EQ(parse_shadow_mode("soft"), ShadowMode::soft);
    EXPECT_EQ(parse_pcf_kernel("2x2"), PcfKernel::hardware_2x2);
    EXPECT_EQ(parse_cap_kind("solid-angle"), CapKind::solid_angle);
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
    EXPECT_EQ(usage_error_of([] { parse_pcf_kernel("3x3"); }), "'3x3' is not one of 2x2, wide");
    EXPECT_EQ(usage_error_of([] { parse_shadow_mode("pcss"); }), "'pcss' is not one of hard, soft");
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
    for (const OptimisationSwitch& each : optimisation_switches()) {
        EXPECT_TRUE(optimised.*each.member) << each.name;
        EXPECT_FALSE(first.*each.member) << each.name;
    }
}

}  // namespace
}  // namespace envshadow::render
