// The split sum's DFG table (docs/DESIGN.md §11).
#include "env/dfg_table.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "env/gltf_brdf.h"

namespace envshadow {

glm::dvec4 dfg_texel(double n_dot_v, double roughness, int samples_per_axis) {
    const double alpha = gltf_brdf::alpha_from_roughness(roughness);
    const glm::dvec3 n(0.0, 0.0, 1.0);
    const glm::dvec3 v(std::sqrt(std::max(0.0, 1.0 - n_dot_v * n_dot_v)), 0.0, n_dot_v);
    const double view_masking = gltf_brdf::smith_masking(n_dot_v, alpha);
    double scale = 0.0, bias = 0.0, diffuse = 0.0;
    glm::dvec3 moment(0.0);  // of D V n.l dl: the lobe's centroid
    // u1 = 1 - (1 - w)^2 with w at the strata's midpoints, weighted by du1/dw = 2 (1 - w): the visible normals'
    // map has sqrt(1 - u1) in it, so plain midpoints in u1 leave the last ring of strata at the horizon (1.6% off
    // at n.v = 1, roughness 0.3, 64 samples per axis).
    double total_weight = 0.0;
    for (int a = 0; a < samples_per_axis; ++a)
        for (int b = 0; b < samples_per_axis; ++b) {
            const double w = (a + 0.5) / samples_per_axis, u2 = (b + 0.5) / samples_per_axis;
            const double u1 = 1.0 - (1.0 - w) * (1.0 - w), stratum = 2.0 * (1.0 - w);
            total_weight += stratum;
            // D V n.l / pdf with pdf = G1(v) D / (4 n.v): 4 V n.l n.v / G1(v) = G2 / G1(v).
            const glm::dvec3 l = gltf_brdf::sample_ggx_reflection(n, v, alpha, u1, u2).direction;
            if (l.z > 0.0) {
                const double s = gltf_brdf::schlick_weight(glm::dot(v, glm::normalize(v + l)));
                const double weight =
                    4.0 * gltf_brdf::smith_visibility(l.z, n_dot_v, alpha) * l.z * n_dot_v / view_masking;
                scale += stratum * (1.0 - s) * weight;
                bias += stratum * s * weight;
                moment += stratum * weight * l;
            }
            // (1 - s) n.l / pi over the cosine's density n.l / pi.
            const double radius = std::sqrt(u1), phi = 2.0 * std::numbers::pi * u2;
            const glm::dvec3 c(radius * std::cos(phi), radius * std::sin(phi), std::sqrt(std::max(0.0, 1.0 - u1)));
            diffuse += stratum * (1.0 - gltf_brdf::schlick_weight(glm::dot(v, glm::normalize(v + c))));
        }
    const double to_mirror = std::acos(std::clamp(n_dot_v, -1.0, 1.0));  // r is v mirrored about n
    const double axis = to_mirror > 0.0 && glm::length(moment) > 0.0
                            ? std::acos(std::clamp(glm::normalize(moment).z, -1.0, 1.0)) / to_mirror
                            : 1.0;
    return glm::dvec4(glm::dvec3(scale, bias, diffuse) / total_weight, axis);
}

glm::dvec3 dfg_integrals(double n_dot_v, double roughness, int samples_per_axis) {
    return glm::dvec3(dfg_texel(n_dot_v, roughness, samples_per_axis));
}

glm::vec4 DfgTable::lookup(double n_dot_v, double roughness) const {
    const double x = std::clamp(n_dot_v * size - 0.5, 0.0, double(size - 1));
    const double y = std::clamp(roughness * size - 0.5, 0.0, double(size - 1));
    const int i0 = std::min(int(x), size - 1), j0 = std::min(int(y), size - 1);
    const int i1 = std::min(i0 + 1, size - 1), j1 = std::min(j0 + 1, size - 1);
    const double ax = x - i0, ay = y - j0;
    auto at = [&](int i, int j) { return glm::dvec4(texels[std::size_t(j) * std::size_t(size) + std::size_t(i)]); };
    const glm::dvec4 low = at(i0, j0) * (1.0 - ax) + at(i1, j0) * ax;
    const glm::dvec4 high = at(i0, j1) * (1.0 - ax) + at(i1, j1) * ax;
    return glm::vec4(low * (1.0 - ay) + high * ay);
}

DfgTable compute_dfg_table(int size, int samples_per_axis) {
    DfgTable table;
    table.size = size;
    table.texels.resize(std::size_t(size) * std::size_t(size));
    tbb::parallel_for(0, size, [&](int j) {
        for (int i = 0; i < size; ++i)
            table.texels[std::size_t(j) * std::size_t(size) + std::size_t(i)] =
                glm::vec4(dfg_texel((i + 0.5) / size, (j + 0.5) / size, samples_per_axis));
    });
    return table;
}

}  // namespace envshadow
