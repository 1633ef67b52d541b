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
    EXPECT_EQ(s.cap, CapKind::weighted);  // the better cap (DESIGN.md §3)
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

}  // namespace
}  // namespace envshadow::render
