// The glTF metallic-roughness BRDF (engine/env/gltf_brdf.h) and its DFG table (engine/env/dfg_table.h) against
// the specification written another way and against quadratures of their own (tests/brdf/ggx_quadrature.h),
// docs/DESIGN.md §11.
#include "env/gltf_brdf.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include <glm/geometric.hpp>

#include "brdf/ggx_quadrature.h"
#include "env/dfg_table.h"

namespace envshadow::testing {
namespace {

using gltf_brdf::MetallicRoughness;
constexpr double kPi = std::numbers::pi;

glm::dvec3 random_unit(std::mt19937_64& rng) {
    std::normal_distribution<double> normal;
    return glm::normalize(glm::dvec3(normal(rng), normal(rng), normal(rng)));
}

// A direction in the hemisphere about n, not closer than ~3 degrees to the tangent plane.
glm::dvec3 random_above(std::mt19937_64& rng, const glm::dvec3& n) {
    for (;;) {
        const glm::dvec3 d = random_unit(rng);
        const double c = glm::dot(d, n);
        if (std::abs(c) > 0.05) return c > 0.0 ? d : -d;
    }
}

// The specification's normative mix, from its pieces: mix(dielectric_brdf, metal_brdf, metallic) with
// dielectric_brdf = mix(diffuse, specular, fresnel(0.04)) and metal_brdf = specular * fresnel(baseColor).
glm::dvec3 specification_brdf(const MetallicRoughness& m, const glm::dvec3& n, const glm::dvec3& v,
                              const glm::dvec3& l) {
    const double alpha = std::max(m.roughness * m.roughness, gltf_brdf::kMinAlpha);
    const glm::dvec3 h = glm::normalize(v + l);
    const double cos_l = glm::dot(n, l), cos_v = glm::dot(n, v);
    const double specular = walter_ggx_distribution(glm::dot(n, h), alpha) * height_correlated_g2(cos_l, cos_v, alpha) /
                            (4.0 * cos_l * cos_v);
    const double schlick = std::pow(1.0 - std::abs(glm::dot(v, h)), 5.0);
    const double dielectric_fresnel = 0.04 + 0.96 * schlick;
    const glm::dvec3 dielectric =
        m.base_color / kPi * (1.0 - dielectric_fresnel) + glm::dvec3(specular * dielectric_fresnel);
    const glm::dvec3 metal = specular * (m.base_color + (glm::dvec3(1.0) - m.base_color) * schlick);
    return dielectric * (1.0 - m.metallic) + metal * m.metallic;
}

std::vector<MetallicRoughness> test_materials() {
    return {{glm::dvec3(1.0), 1.0, 1.0},
            {glm::dvec3(1.0, 0.766, 0.336), 1.0, 0.3},  // gold
            {glm::dvec3(0.8, 0.1, 0.1), 0.0, 0.5},
            {glm::dvec3(0.5, 0.6, 0.7), 0.4, 0.08},
            {glm::dvec3(0.2), 0.7, 0.9}};
}

TEST(GltfBrdf, EqualsTheSpecificationsMixWrittenAnotherWay) {
    std::mt19937_64 rng(7);
    for (const MetallicRoughness& m : test_materials())
        for (int trial = 0; trial < 200; ++trial) {
            const glm::dvec3 n = random_unit(rng), v = random_above(rng, n), l = random_above(rng, n);
            const glm::dvec3 got = gltf_brdf::evaluate(m, n, v, l), want = specification_brdf(m, n, v, l);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1e-9 * std::max(1.0, want[c])) << trial;
        }
}

TEST(GltfBrdf, ReciprocalNonNegativeAndZeroUnderTheSurface) {
    std::mt19937_64 rng(11);
    for (const MetallicRoughness& m : test_materials())
        for (int trial = 0; trial < 500; ++trial) {
            const glm::dvec3 n = random_unit(rng), v = random_above(rng, n), l = random_above(rng, n);
            const glm::dvec3 forward = gltf_brdf::evaluate(m, n, v, l), backward = gltf_brdf::evaluate(m, n, l, v);
            for (int c = 0; c < 3; ++c) {
                EXPECT_GE(forward[c], 0.0);
                EXPECT_NEAR(forward[c], backward[c], 1e-12 * std::max(1.0, forward[c]));
            }
            EXPECT_EQ(gltf_brdf::evaluate(m, n, v, -l), glm::dvec3(0.0));
            EXPECT_EQ(gltf_brdf::evaluate(m, n, -v, l), glm::dvec3(0.0));
        }
}

// Directional albedo integral of f_r n.l dl of white base colour at n.v: the specular lobe over half vectors
// distributed as D (n.h) (dl = 4 v.h dh), the diffuse one over the hemisphere.
struct Albedo {
    double diffuse, specular;
};
Albedo white_albedo(double metallic, double roughness, double n_dot_v) {
    const MetallicRoughness m{glm::dvec3(1.0), metallic, roughness};
    const glm::dvec3 n(0.0, 0.0, 1.0), v = view_at(n_dot_v);
    const double alpha = gltf_brdf::alpha_from_roughness(roughness);
    const double specular = mean_over_ggx_half_vectors(alpha, 800, [&](const glm::dvec3& h) {
        const glm::dvec3 l = reflected(v, h);
        if (l.z <= 0.0 || glm::dot(v, h) <= 0.0) return 0.0;
        return gltf_brdf::evaluate_lobes(m, n, v, l).specular.g * l.z * 4.0 * glm::dot(v, h) /
               (walter_ggx_distribution(h.z, alpha) * h.z);
    });
    const double diffuse = integral_over_hemisphere(
        400, [&](const glm::dvec3& l) { return gltf_brdf::evaluate_lobes(m, n, v, l).diffuse.g * l.z; });
    return {diffuse, specular};
}

// The glTF BRDF is not energy conserving by construction: its specular lobe loses what single-scattering GGX
// loses (the light reflected more than once among the microfacets, most at roughness 1), and its diffuse lobe,
// weighted by 1 - F at the half vector of l and v rather than by what the specular lobe leaves, gains at grazing
// views of smooth dielectrics (KhronosGroup/glTF#1853 discusses the weighting).
TEST(GltfBrdf, WhiteFurnaceLosesOnlyWhatSingleScatteringGgxLoses) {
    for (double n_dot_v : {0.2, 0.5, 1.0}) {
        double previous_metal = 1.0;
        for (double roughness : {0.1, 0.5, 1.0}) {
            const Albedo metal = white_albedo(1.0, roughness, n_dot_v);
            const Albedo dielectric = white_albedo(0.0, roughness, n_dot_v);
            std::printf("n.v %.1f roughness %.1f: metal %.4f, dielectric %.4f (diffuse %.4f + specular %.4f)\n",
                        n_dot_v, roughness, metal.specular, dielectric.diffuse + dielectric.specular,
                        dielectric.diffuse, dielectric.specular);
            EXPECT_EQ(metal.diffuse, 0.0);
            EXPECT_LE(metal.specular, 1.0 + 1e-3);
            EXPECT_LT(metal.specular, previous_metal + 1e-3) << "the loss grows with roughness";
            previous_metal = metal.specular;
            if (roughness == 0.1) {
                EXPECT_GT(metal.specular, 0.995) << "nearly a mirror: nearly no loss";
            }
            // The diffuse lobe is at most (1 - 0.04) of Lambert's; the dielectric's specular at most the metal's.
            EXPECT_LE(dielectric.diffuse, 0.96 + 1e-3);
            EXPECT_GT(dielectric.diffuse, 0.9);
            EXPECT_LE(dielectric.specular, metal.specular + 1e-9);
            // Normal incidence, and rough surfaces at every angle, stay within 1.
            if (n_dot_v == 1.0 || roughness == 1.0) {
                EXPECT_LE(dielectric.diffuse + dielectric.specular, 1.0 + 1e-3);
            }
        }
    }
    // Roughness 1 (alpha 1) seen from the normal: h is cosine-distributed and only the half of it within 45
    // degrees of the normal reflects above the surface, so with G2 < 1 the metal keeps under 1/2.
    const double rough_metal_at_normal = white_albedo(1.0, 1.0, 1.0).specular;
    EXPECT_LT(rough_metal_at_normal, 0.5);
    EXPECT_GT(rough_metal_at_normal, 0.25);
    // Roughness 1 at n.v = 0.5 loses 40-60% (Kulla and Conty 2017's single-scattering loss at this roughness).
    const double rough_metal = white_albedo(1.0, 1.0, 0.5).specular;
    EXPECT_GT(1.0 - rough_metal, 0.4);
    EXPECT_LT(1.0 - rough_metal, 0.6);
}

// A frame about the unit vector r: the direction at angle theta from r and azimuth phi.
glm::dvec3 about(const glm::dvec3& r, double theta, double phi) {
    const glm::dvec3 t = glm::normalize(std::abs(r.x) < 0.9 ? glm::cross(r, glm::dvec3(1.0, 0.0, 0.0))
                                                            : glm::cross(r, glm::dvec3(0.0, 1.0, 0.0)));
    const glm::dvec3 b = glm::cross(r, t);
    return std::cos(theta) * r + std::sin(theta) * (std::cos(phi) * t + std::sin(phi) * b);
}

// integral over the sphere of g(l) dl in polar coordinates about r, theta = pi s^2 (dense near r, where the lobe is).
template <class G>
double integral_over_sphere_about(const glm::dvec3& r, int steps, G g) {
    double sum = 0.0;
    const int azimuths = 360;
    for (int a = 0; a < steps; ++a) {
        const double s = (a + 0.5) / steps, theta = kPi * s * s, d_theta = 2.0 * kPi * s / steps;
        for (int b = 0; b < azimuths; ++b)
            sum += g(about(r, theta, 2.0 * kPi * (b + 0.5) / azimuths)) * std::sin(theta) * d_theta;
    }
    return sum * 2.0 * kPi / azimuths;
}

TEST(GltfBrdf, ReflectionSamplerDensityIntegratesToOne) {
    const glm::dvec3 n(0.0, 0.0, 1.0);
    for (double roughness : {0.3, 0.6, 1.0})
        for (double n_dot_v : {0.15, 0.6, 1.0}) {
            const double alpha = gltf_brdf::alpha_from_roughness(roughness);
            const glm::dvec3 v = view_at(n_dot_v), r = reflected(v, n);
            const double total = integral_over_sphere_about(
                r, 3000, [&](const glm::dvec3& l) { return gltf_brdf::ggx_reflection_pdf(n, v, l, alpha); });
            EXPECT_NEAR(total, 1.0, 2e-3) << "roughness " << roughness << " n.v " << n_dot_v;
        }
}

// integral of f_spec n.l dl per channel over half vectors (as white_albedo), the quadrature the sampler must match.
glm::dvec3 specular_albedo(const MetallicRoughness& m, double n_dot_v) {
    const glm::dvec3 n(0.0, 0.0, 1.0), v = view_at(n_dot_v);
    const double alpha = gltf_brdf::alpha_from_roughness(m.roughness);
    glm::dvec3 result;
    for (int c = 0; c < 3; ++c)
        result[c] = mean_over_ggx_half_vectors(alpha, 800, [&](const glm::dvec3& h) {
            const glm::dvec3 l = reflected(v, h);
            if (l.z <= 0.0 || glm::dot(v, h) <= 0.0) return 0.0;
            return gltf_brdf::evaluate_lobes(m, n, v, l).specular[c] * l.z * 4.0 * glm::dot(v, h) /
                   (walter_ggx_distribution(h.z, alpha) * h.z);
        });
    return result;
}

TEST(GltfBrdf, ReflectionSamplerEstimatesMatchQuadrature) {
    const glm::dvec3 n(0.0, 0.0, 1.0);
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    for (const MetallicRoughness& m :
         {MetallicRoughness{glm::dvec3(1.0, 0.766, 0.336), 1.0, 0.3}, MetallicRoughness{glm::dvec3(0.9), 1.0, 0.8}})
        for (double n_dot_v : {0.3, 0.9}) {
            const glm::dvec3 v = view_at(n_dot_v);
            const double alpha = gltf_brdf::alpha_from_roughness(m.roughness);
            // The albedo, and the probability of a cap of 0.3 rad about a direction off the mirror direction.
            const glm::dvec3 cap_axis = glm::normalize(reflected(v, n) + glm::dvec3(0.0, 0.25, 0.1));
            const double cap_cos = std::cos(0.3);
            const int count = 1 << 16;
            glm::dvec3 sum(0.0), sum2(0.0);
            int in_cap = 0;
            for (int k = 0; k < count; ++k) {
                const gltf_brdf::DirectionSample sample =
                    gltf_brdf::sample_ggx_reflection(n, v, alpha, uniform(rng), uniform(rng));
                ASSERT_GT(sample.pdf, 0.0);
                if (glm::dot(sample.direction, cap_axis) > cap_cos) ++in_cap;
                const glm::dvec3 x = gltf_brdf::evaluate_lobes(m, n, v, sample.direction).specular *
                                     std::max(sample.direction.z, 0.0) / sample.pdf;
                sum += x;
                sum2 += x * x;
            }
            const glm::dvec3 mean = sum / double(count);
            const glm::dvec3 error = glm::sqrt((sum2 / double(count) - mean * mean) / double(count));
            const glm::dvec3 want = specular_albedo(m, n_dot_v);
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(mean[c], want[c], 4.0 * error[c] + 1e-4)
                    << "roughness " << m.roughness << " n.v " << n_dot_v;
                EXPECT_LT(error[c], 0.01 * want[c]);  // the visible normals' weights vary little
            }
            const double cap_probability = integral_over_sphere_about(cap_axis, 1500, [&](const glm::dvec3& l) {
                return glm::dot(l, cap_axis) > cap_cos ? gltf_brdf::ggx_reflection_pdf(n, v, l, alpha) : 0.0;
            });
            const double fraction = double(in_cap) / count;
            EXPECT_NEAR(fraction, cap_probability,
                        4.0 * std::sqrt(cap_probability * (1.0 - cap_probability) / count) + 2e-3);
        }
}

// The DFG integrals at one point by the test's own quadrature: the specular ones over GGX half vectors with the
// height-correlated G2 written through Lambda, the diffuse one over the hemisphere.
glm::dvec3 dfg_by_quadrature(double n_dot_v, double roughness) {
    const glm::dvec3 v = view_at(n_dot_v);
    const double alpha = std::max(roughness * roughness, gltf_brdf::kMinAlpha);
    auto specular = [&](bool bias) {
        return mean_over_ggx_half_vectors(alpha, 1000, [&](const glm::dvec3& h) {
            const glm::dvec3 l = reflected(v, h);
            const double v_dot_h = glm::dot(v, h);
            if (l.z <= 0.0 || v_dot_h <= 0.0) return 0.0;
            const double s = std::pow(1.0 - v_dot_h, 5.0);
            // D V n.l 4 v.h / (D n.h), V = G2 / (4 n.l n.v)
            return (bias ? s : 1.0 - s) * height_correlated_g2(l.z, n_dot_v, alpha) * v_dot_h / (n_dot_v * h.z);
        });
    };
    const double diffuse = integral_over_hemisphere(400, [&](const glm::dvec3& l) {
        return (1.0 - std::pow(1.0 - glm::dot(v, glm::normalize(v + l)), 5.0)) * l.z / kPi;
    });
    return {specular(false), specular(true), diffuse};
}

TEST(DfgTable, MatchesQuadratureAtTexelCentresAndBetween) {
    const DfgTable table = compute_dfg_table(32, 64);
    ASSERT_EQ(table.texels.size(), 32u * 32u);
    double worst_centre = 0.0, worst_between = 0.0;
    // Texel centres ((i + 0.5) / 32), and points between them where the bilinear lookup adds its error.
    for (const auto& [i, j] : std::vector<std::pair<int, int>>{{3, 9}, {15, 15}, {28, 25}, {9, 31}, {22, 6}, {0, 20}}) {
        const double n_dot_v = (i + 0.5) / 32.0, roughness = (j + 0.5) / 32.0;
        const glm::dvec3 want = dfg_by_quadrature(n_dot_v, roughness);
        const glm::dvec3 got(table.lookup(n_dot_v, roughness));
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(got[c], want[c], 1e-3) << "n.v " << n_dot_v << " roughness " << roughness << " channel " << c;
            worst_centre = std::max(worst_centre, std::abs(got[c] - want[c]));
        }
    }
    for (const auto& [n_dot_v, roughness] :
         std::vector<std::pair<double, double>>{{0.2, 0.35}, {0.55, 0.62}, {0.8, 0.9}}) {
        const glm::dvec3 want = dfg_by_quadrature(n_dot_v, roughness);
        const glm::dvec3 got(table.lookup(n_dot_v, roughness));
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(got[c], want[c], 5e-3) << "n.v " << n_dot_v << " roughness " << roughness << " channel " << c;
            worst_between = std::max(worst_between, std::abs(got[c] - want[c]));
        }
    }
    std::printf("DFG 32 x 32, 64^2 samples: worst error %.2e at texel centres, %.2e between\n", worst_centre,
                worst_between);
}

TEST(DfgTable, WhiteMetalAlbedoIsScalePlusBias) {
    // F0 = 1: scale + bias is the white metal's directional albedo, integrated by white_albedo another way.
    for (const auto& [n_dot_v, roughness] :
         std::vector<std::pair<double, double>>{{0.2, 0.5}, {0.5, 1.0}, {1.0, 0.3}}) {
        const glm::dvec3 dfg = dfg_integrals(n_dot_v, roughness, 64);
        EXPECT_NEAR(dfg.x + dfg.y, white_albedo(1.0, roughness, n_dot_v).specular, 1e-3);
    }
}

// The lobe's axis (the fourth channel): the angle from the normal to the centroid of D V n.l dl, over the angle
// to the mirror direction, by the test's own quadrature over GGX half vectors (dl = 4 v.h dh), at texel centres.
// The centroid leans from r towards the normal as the lobe widens and the view grazes (the cosine and the masking
// cut its far side), and not at all for a sharp lobe seen head on.
TEST(DfgTable, AxisIsTheAngleToTheLobesCentroid) {
    const DfgTable table = compute_dfg_table(32, 64);
    for (const auto& [i, j] : std::vector<std::pair<int, int>>{{3, 9}, {15, 15}, {28, 25}, {9, 31}, {22, 6}, {1, 20}}) {
        const double n_dot_v = (i + 0.5) / 32.0, roughness = (j + 0.5) / 32.0;
        const glm::dvec3 v = view_at(n_dot_v);
        const double alpha = std::max(roughness * roughness, gltf_brdf::kMinAlpha);
        auto moment = [&](int axis) {
            return mean_over_ggx_half_vectors(alpha, 1000, [&](const glm::dvec3& h) {
                const glm::dvec3 l = reflected(v, h);
                if (l.z <= 0.0 || glm::dot(v, h) <= 0.0) return 0.0;
                return l[axis] * height_correlated_g2(l.z, n_dot_v, alpha) * glm::dot(v, h) / h.z;
            });
        };
        const double centroid = std::atan2(std::abs(moment(0)), moment(2));
        const double want = centroid / std::acos(n_dot_v);
        EXPECT_NEAR(table.lookup(n_dot_v, roughness).w, want, 2e-3) << "n.v " << n_dot_v << " roughness " << roughness;
    }
    EXPECT_GT(table.lookup(0.9, 0.1).w, 0.99);
    EXPECT_LT(table.lookup(0.1, 0.8).w, 0.6);
    EXPECT_LT(table.lookup(0.1, 0.5).w, table.lookup(0.7, 0.5).w);
}

}  // namespace
}  // namespace envshadow::testing
