#pragma once
// The split sum's second factor (docs/DESIGN.md §11; Karis 2013, Filament's libs/ibl): for the glTF BRDF
// (env/gltf_brdf.h) under light of constant radiance, per n.v and perceptual roughness,
//   scale    = integral of (1 - s) D V n.l dl,  bias = integral of s D V n.l dl,  s = (1 - v.h)^5
//   diffuse  = (1 / pi) integral of (1 - s) n.l dl                       (the same for every roughness)
// so that the specular albedo is F0 scale + bias (with F90 = 1) and the diffuse albedo
// (1 - metallic) (1 - 0.04) baseColor diffuse, both exact for a constant environment; and
//   axis     = angle(n, m) / angle(n, r),  m the mean direction of D V n.l dl (the lobe's centroid)
// where the split sum looks its round lobe up, between the normal and the mirror direction r (docs/DESIGN.md §11,
// "The lobe's axis").
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace envshadow {

// (scale, bias, diffuse) at one point, n_dot_v in (0, 1]: the specular integrals by the visible normals
// (gltf_brdf::sample_ggx_reflection), the diffuse one by the cosine, each on a samples_per_axis^2 grid of
// stratum midpoints.
glm::dvec3 dfg_integrals(double n_dot_v, double roughness, int samples_per_axis);

// (scale, bias, diffuse, axis) at one point, n_dot_v in (0, 1): the integrals above and the lobe's centroid from
// the same strata, in one pass.
glm::dvec4 dfg_texel(double n_dot_v, double roughness, int samples_per_axis);

struct DfgTable {
    int size = 0;
    // (scale, bias, diffuse, axis) of texel (i, j) at j * size + i: n.v = (i + 0.5) / size,
    // roughness = (j + 0.5) / size.
    std::vector<glm::vec4> texels;

    // Bilinear between texel centres, clamped at the edges (GL_LINEAR with GL_CLAMP_TO_EDGE).
    glm::vec4 lookup(double n_dot_v, double roughness) const;
};

// Parallel (TBB). 64 samples per axis keep every entry within 1e-3 of the integral (tests/brdf/gltf_brdf_test.cpp).
DfgTable compute_dfg_table(int size, int samples_per_axis = 64);

}  // namespace envshadow
