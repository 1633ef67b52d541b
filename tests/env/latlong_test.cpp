#include "env/latlong.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "env/importance.h"

namespace envshadow {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(LatLong, DirectionToUvToDirectionRoundTrips) {
    std::mt19937_64 rng(7);
    std::normal_distribution<double> gauss;
    for (int k = 0; k < 10000; ++k) {
        const glm::dvec3 d = glm::normalize(glm::dvec3(gauss(rng), gauss(rng), gauss(rng)));
        const glm::dvec2 uv = latlong::uv(d);
        ASSERT_GE(uv.x, 0.0);
        ASSERT_LT(uv.x, 1.0);
        ASSERT_GE(uv.y, 0.0);
        ASSERT_LE(uv.y, 1.0);
        const glm::dvec3 back = latlong::direction(uv.x, uv.y);
        ASSERT_NEAR(glm::length(back - d), 0.0, 1e-12) << d.x << " " << d.y << " " << d.z;
    }
}

TEST(LatLong, TexelCentreToUvIsTheTexelCentre) {
    const int width = 64, height = 32;
    for (int j = 0; j < height; ++j)
        for (int i = 0; i < width; ++i) {
            const glm::dvec2 uv = latlong::uv(latlong::texel_direction(i, j, width, height));
            ASSERT_NEAR(uv.x, (i + 0.5) / width, 1e-12);
            ASSERT_NEAR(uv.y, (j + 0.5) / height, 1e-12);
        }
}

TEST(LatLong, RowZeroIsTheZenithAndUGrowsFromXTowardsZ) {
    EXPECT_NEAR(latlong::direction(0.3, 0.0).y, 1.0, 1e-15);
    EXPECT_NEAR(latlong::direction(0.3, 1.0).y, -1.0, 1e-15);
    EXPECT_NEAR(glm::length(latlong::direction(0.0, 0.5) - glm::dvec3(1, 0, 0)), 0.0, 1e-15);
    EXPECT_NEAR(glm::length(latlong::direction(0.25, 0.5) - glm::dvec3(0, 0, 1)), 0.0, 1e-15);
}

TEST(LatLong, TexelSolidAnglesSumTo4Pi) {
    for (const auto& [width, height] :
         {std::pair{2, 1}, std::pair{8, 4}, std::pair{1000, 500}, std::pair{1024, 512}, std::pair{16384, 8192}}) {
        double sum = 0.0;
        for (int j = 0; j < height; ++j) sum += width * latlong::texel_solid_angle(j, width, height);
        EXPECT_NEAR(sum, 4.0 * kPi, 1e-9) << width << "x" << height;
    }
}

TEST(LatLong, RowsAboveALatitudeMakeASphericalCap) {
    // Independent of the texel formula: the cap above polar angle theta has area 2 pi (1 - cos theta).
    const int width = 360, height = 180;
    double sum = 0.0;
    for (int j = 0; j < height; ++j) {
        sum += width * latlong::texel_solid_angle(j, width, height);
        const double theta = kPi * (j + 1) / height;
        ASSERT_NEAR(sum, 2.0 * kPi * (1.0 - std::cos(theta)), 1e-10) << j;
    }
}

TEST(LatLong, TexelDirectionTablesEqualTheFormulaExactly) {
    for (const auto& [width, height] : {std::pair{2, 1}, std::pair{10, 5}, std::pair{1024, 512}}) {
        const TexelDirections directions(width, height);
        for (int j = 0; j < height; j += std::max(1, height / 37))
            for (int i = 0; i < width; i += std::max(1, width / 53)) {
                const glm::dvec3 a = directions(i, j), b = latlong::texel_direction(i, j, width, height);
                ASSERT_EQ(a.x, b.x);
                ASSERT_EQ(a.y, b.y);
                ASSERT_EQ(a.z, b.z);
            }
    }
}

}  // namespace
}  // namespace envshadow
