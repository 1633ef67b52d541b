// With a ground plane only the upper hemisphere is decomposed (docs/DESIGN.md §3.1). For
// every method and N of {1, 16, 64, 128, 256}: Σ L̃_i equals the integral over the upper hemisphere,
// every texel below the horizon is in no cell, every cell is non-empty, lies above the horizon and is
// integrated from its texels above it. Reference values are recomputed here from the map's texels with
// the solid angle of each texel's part above the horizon, (2π / W)(cos θ_top − max(0, cos θ_bottom)).
#include <cctype>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "contract_helpers.h"
#include "core/error.h"

namespace envshadow::contract {
namespace {

// Solid angle of one texel of row j above the horizon (θ < π/2): the whole texel, the upper half of
// the middle row of an odd-height map (cos θ_bottom = −cos θ_top there), or nothing.
double upper_solid_angle(int j, int width, int height) {
    if (2 * j >= height) return 0.0;  // the row starts at the horizon or below (cos(pi/2) rounds to 6e-17)
    const double top = std::cos(std::numbers::pi * j / height), bottom = std::cos(std::numbers::pi * (j + 1) / height);
    return (2.0 * std::numbers::pi / width) * std::max(0.0, top - std::max(0.0, bottom));
}

glm::dvec3 upper_integral(const EnvironmentMap& map) {
    glm::dvec3 total(0.0);
    for (int j = 0; j < map.height; ++j) {
        glm::dvec3 row(0.0);
        for (int i = 0; i < map.width; ++i) row += glm::dvec3(map.at(i, j));
        total += row * upper_solid_angle(j, map.width, map.height);
    }
    return total;
}

// A W x H map (H odd: the horizon halves the middle row) of random radiance, brighter near the horizon.
EnvironmentMap odd_height_map() {
    EnvironmentMap map;
    map.width = 62;
    map.height = 31;
    map.source = "odd 62x31";
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<float> value(0.0f, 1.0f);
    for (int j = 0; j < map.height; ++j)
        for (int i = 0; i < map.width; ++i)
            map.texels.push_back(glm::vec3(value(rng), value(rng), value(rng)) * (j == 15 ? 20.0f : 1.0f));
    return map;
}

const EnvironmentMap& test_map(const std::string& spec) {
    static const EnvironmentMap odd = odd_height_map();
    return spec == "odd" ? odd : cached_map(spec);
}

// Everything docs/DESIGN.md §3.1 promises about one upper-hemisphere decomposition.
void expect_upper_hemisphere_cells(const EnvironmentMap& map, const Decomposition& d, Method method, int lights,
                                   const std::string& context) {
    SCOPED_TRACE(context);
    EXPECT_EQ(d.hemisphere, Hemisphere::upper);
    EXPECT_TRUE(count_as_promised(method, lights, d.cells.size())) << d.cells.size() << " cells";
    ASSERT_EQ(d.texel_cell.size(), map.texels.size());
    const std::size_t count = d.cells.size();

    std::vector<glm::dvec3> radiance(count, glm::dvec3(0.0)), weighted(count, glm::dvec3(0.0));
    std::vector<double> solid_angle(count, 0.0), importance(count, 0.0);
    std::vector<long> texels(count, 0);
    long below_in_a_cell = 0, above_in_no_cell = 0;
    for (int j = 0; j < map.height; ++j) {
        const double dw = upper_solid_angle(j, map.width, map.height);
        for (int i = 0; i < map.width; ++i) {
            const std::uint16_t k = d.texel_cell[texel_index(i, j, map.width)];
            if (dw == 0.0) {  // wholly below the horizon
                below_in_a_cell += k != kNoCell;
                continue;
            }
            if (k >= count) {
                ++above_in_no_cell;
                continue;
            }
            const glm::dvec3 L(map.at(i, j));
            radiance[k] += L * dw;
            solid_angle[k] += dw;
            importance[k] += latlong::luminance(L) * dw;
            weighted[k] += latlong::luminance(L) * dw * latlong::texel_direction(i, j, map.width, map.height);
            ++texels[k];
        }
    }
    EXPECT_EQ(below_in_a_cell, 0) << "texels below the horizon in a cell";
    ASSERT_EQ(above_in_no_cell, 0) << "texels above the horizon in no cell";

    const glm::dvec3 integral = upper_integral(map);
    glm::dvec3 radiance_sum(0.0);
    double solid_angle_sum = 0.0;
    for (const Cell& cell : d.cells) {
        radiance_sum += glm::dvec3(cell.radiance);
        solid_angle_sum += cell.solid_angle;
    }
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(radiance_sum[c], integral[c], 1e-4 * integral[c]) << "Σ L̃ channel " << c;
        EXPECT_NEAR(d.integral[c], integral[c], 1e-6 * integral[c]) << "Decomposition::integral channel " << c;
    }
    EXPECT_NEAR(solid_angle_sum, 2.0 * std::numbers::pi, 1e-4) << "Σ Δω_i";

    long empty = 0, below = 0, wrong = 0;
    for (std::size_t k = 0; k < count; ++k) {
        const Cell& cell = d.cells[k];
        empty += texels[k] == 0;
        below += cell.direction.y < 0.0f;  // the middle row of an odd map lies on the horizon
        bool ok = std::abs(cell.solid_angle - solid_angle[k]) <= 1e-5 * solid_angle[k] + 1e-9 &&
                  std::abs(cell.cos_radius - (1.0 - solid_angle[k] / (2.0 * std::numbers::pi))) <= 1e-5;
        for (int c = 0; c < 3; ++c)
            ok = ok && std::abs(cell.radiance[c] - radiance[k][c]) <= 1e-5 * radiance[k][c] + 1e-9;
        if (importance[k] > 0.0 && glm::length(weighted[k]) > 1e-3 * importance[k]) {
            const glm::dvec3 centre = glm::normalize(weighted[k]);
            ok = ok && glm::length(centre - glm::dvec3(cell.direction)) <= 1e-4;
            const double weighted_cap = 2.0 * glm::dot(weighted[k], centre) / importance[k] - 1.0;
            ok = ok && std::abs(cell.cos_radius_weighted - weighted_cap) <= 2e-5;
        }
        if (!ok && ++wrong <= 3)
            ADD_FAILURE() << "cell " << k << ": solid angle " << cell.solid_angle << " vs " << solid_angle[k]
                          << ", radiance " << cell.radiance.g << " vs " << radiance[k].g << ", cos_radius_weighted "
                          << cell.cos_radius_weighted;
    }
    EXPECT_EQ(empty, 0) << "empty cells of " << count;
    EXPECT_EQ(below, 0) << "cell centres below the horizon";
    EXPECT_EQ(wrong, 0) << "cells not integrated from their texels above the horizon";
}

struct MapAndMethod {
    std::string spec;
    Method method;
};
void PrintTo(const MapAndMethod& c, std::ostream* out) {
    *out << c.spec.substr(c.spec.rfind('/') + 1) << " " << to_string(c.method);
}

std::vector<MapAndMethod> hemisphere_cases() {
    std::vector<MapAndMethod> cases;
    for (const std::string& spec :
         {blender_map("courtyard"), blender_map("city"), std::string("builtin:sky"), std::string("odd")})
        for (Method method : kAllMethods) cases.push_back({spec, method});
    return cases;
}

class EnvContractUpperHemisphere : public ::testing::TestWithParam<MapAndMethod> {};

TEST_P(EnvContractUpperHemisphere, EveryNConservesTheUpperHemisphereAndNoCellReachesBelow) {
    const auto& [spec, method] = GetParam();
    const EnvironmentMap& map = test_map(spec);
    for (int lights : kIssueCounts) {
        const Decomposition d =
            decompose(map, {.method = method, .lights = lights, .seed = 3, .hemisphere = Hemisphere::upper});
        expect_upper_hemisphere_cells(map, d, method, lights, describe(spec, method, lights));
    }
}

std::string case_name(const ::testing::TestParamInfo<MapAndMethod>& info) {
    std::string spec = info.param.spec;
    if (const auto slash = spec.rfind('/'); slash != std::string::npos) spec = spec.substr(slash + 1);
    std::string name;
    for (char c : spec) name += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
    return name + "_" + std::string(to_string(info.param.method));
}

INSTANTIATE_TEST_SUITE_P(MapsAndMethods, EnvContractUpperHemisphere, ::testing::ValuesIn(hemisphere_cases()),
                         case_name);

// Turning the map about +Y keeps the horizon a row border: the turned map's cells are as valid.
TEST(EnvContractUpperHemisphere, TurnedMapStaysAboveTheHorizon) {
    const EnvironmentMap turned = rolled_half_turn(cached_map(blender_map("courtyard")));
    for (Method method : kAllMethods) {
        const Decomposition d = decompose(turned, {.method = method, .lights = 64, .hemisphere = Hemisphere::upper});
        expect_upper_hemisphere_cells(turned, d, method, 64, describe(turned.source, method, 64));
    }
}

// The full sphere is still the default, and upper differs from it.
TEST(EnvContractUpperHemisphere, FullSphereIsTheDefault) {
    const EnvironmentMap& map = cached_map("builtin:sky");
    const Decomposition full = decompose(map, {.lights = 16});
    EXPECT_EQ(full.hemisphere, Hemisphere::full);
    for (std::uint16_t k : full.texel_cell) ASSERT_LT(k, full.cells.size());
    EXPECT_EQ(parse_enum<Hemisphere>("upper"), Hemisphere::upper);
    EXPECT_EQ(parse_enum<Hemisphere>("full"), Hemisphere::full);
    EXPECT_THROW(parse_enum<Hemisphere>("lower"), UsageError);
}

// A map with fewer texels above the horizon than lights is refused.
TEST(EnvContractUpperHemisphere, TooFewTexelsAboveTheHorizon) {
    EnvironmentMap map;
    map.width = 8;
    map.height = 4;
    map.source = "tiny";
    map.texels.assign(32, glm::vec3(1.0f));
    EXPECT_NO_THROW(decompose(map, {.lights = 16, .hemisphere = Hemisphere::upper}));
    EXPECT_THROW(decompose(map, {.lights = 17, .hemisphere = Hemisphere::upper}), InputError);
    EXPECT_NO_THROW(decompose(map, {.lights = 17}));
}

}  // namespace
}  // namespace envshadow::contract
