#pragma once
// The environment as the reference sees it: radiance constant over each texel of the lat-long map (the
// same piecewise-constant function whose texel sums the decomposition takes), turned into the world by
// the scene's rotation about +Y, and samplers for its light.
#include <cstddef>
#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>
#include <vector>

#include "env/environment.h"

namespace envshadow::reference {

// world direction = world_from_map * map direction: a rotation by `rotation_degrees` about +Y
// (right-handed: positive turns +X towards -Z), the scene's EnvironmentSettings::rotation_degrees.
glm::dmat3 world_from_map(double rotation_degrees);

struct EnvironmentSample {
    glm::dvec3 direction;  // world space, unit
    double pdf = 0.0;      // per steradian
};

class EnvironmentSampler {
public:
    EnvironmentSampler(const EnvironmentMap& map, double rotation_degrees);

    // Radiance of the texel containing `world_direction` (unit): the integrand of the reference.
    glm::dvec3 radiance(const glm::dvec3& world_direction) const;
    // Bilinear between texel centres, u wrapping and v clamped (as the renderer's GL_LINEAR background).
    glm::dvec3 radiance_filtered(const glm::dvec3& world_direction) const;

    // Light sampling with MIS compensation (Karlik et al. 2019, "MIS compensation: optimizing sampling
    // techniques in multiple importance sampling"): density proportional to max(0, lum(L) - mean lum(L))
    // over solid angle, the light above the map's mean (a sun, a lamp, the bright sky). What is darker is
    // left to the BRDF's strategies, which the reference always uses and which cover every direction:
    // with it, light samples land only where they beat them, and a sun in shadow stops no sky sample. A
    // black or uniform map has nothing above its mean (false).
    bool can_sample() const { return light_.total > 0.0; }
    // A direction with that density, from a point of the unit square: `xi1` picks the row by its share,
    // `xi2` the texel in the row by its share, and what is left of each places the direction uniformly in
    // solid angle inside the texel. Continuous and monotone in each coordinate, so stratified points give
    // stratified directions (a small bright sun gets its share).
    EnvironmentSample sample(double xi1, double xi2) const;
    double pdf(const glm::dvec3& world_direction) const;
    // One texel lookup for the integrand: the radiance, and the density in that direction.
    glm::dvec3 radiance_and_pdf(const glm::dvec3& world_direction, double& pdf) const;

    // Integral of luminance over the sphere (sum of lum * texel solid angle) and its mean over 4 pi.
    double luminance_integral() const { return total_; }
    double mean_luminance() const;

private:
    // The sampled density, piecewise constant in solid angle, by its cumulative sums in row-major order.
    struct Distribution {
        std::vector<double> cumulative;  // weight * solid angle of texels 0..k-1; size W*H + 1
        std::vector<double> row_start;   // cumulative[j * W]; size H + 1
        double total = 0.0;              // integral of the weight over the sphere
    };
    // What one lookup of the integrand needs, in one cache line.
    struct Texel {
        glm::vec3 radiance;
        double pdf;  // of the light sampling
    };

    std::size_t texel_index(const glm::dvec3& map_direction) const;

    const EnvironmentMap& map_;
    glm::dmat3 world_from_map_, map_from_world_;
    Distribution light_;
    std::vector<Texel> texels_;
    std::vector<double> cos_edge_;  // cos of the polar angle of the top edge of row j; size H + 1
    double total_ = 0.0;            // integral of lum over the sphere
};

}  // namespace envshadow::reference
