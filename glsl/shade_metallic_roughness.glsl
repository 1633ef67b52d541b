// The glTF 2.0 metallic-roughness BRDF without shadows, by the split sum (docs/DESIGN.md §11), in the programs
// of such materials (METALLIC_ROUGHNESS, with SHADING_RATIO):
//   L_spec = P(r, alpha) (F0 scale(n.v, roughness) + bias(n.v, roughness))
//   L_diff = (1 - metallic) (1 - 0.04) baseColor diffuse(n.v) E(n) / pi
// P from env/ggx_prefilter.h's levels (all of them in one texture, looked up at each pixel's roughness), scale,
// bias and diffuse from env/dfg_table.h's table (tests/render/metallic_roughness_test.cpp holds the result to the
// BRDF's albedo by quadrature, and to the reference). metallic and roughness are the factors times the
// metallic-roughness texture's B and G (linear; white without one).
#include "constants.glsl"
#include "ggx.glsl"
#include "pixel_footprint.glsl"

layout(location = LOC_BASE_COLOR_FACTOR) uniform vec3 u_base_color_factor;  // times the base-colour texture
layout(location = LOC_METALLIC) uniform float u_metallic;
layout(location = LOC_ROUGHNESS) uniform float u_roughness;
layout(binding = UNIT_METALLIC_ROUGHNESS_TEXTURE) uniform sampler2D u_metallic_roughness_texture;
// Texel (i, j) at n.v = (i + 0.5) / size, roughness = (j + 0.5) / size: (n.v, roughness) is its coordinate.
layout(binding = UNIT_DFG) uniform sampler2D u_dfg;

// Below the sharpest GGX level the lower level is the map itself (shade_ratio.glsl's ggx_lobe_mean); u_upper_only:
// the levels' hemisphere is the upper one.
layout(location = LOC_UPPER_ONLY) uniform bool u_upper_only;

// The sharpest level's weight against the map itself (env/ggx_prefilter.h ggx_sharpest_level_weight: alpha over
// the level's), alpha^2 widened by Kaplanyan et al. 2016's specular anti-aliasing with Filament's constants
// (2 x 0.15 |dn|^2, on r = 2 |dn|) up to the sharpest level's.
const float kSharpestRoughness = 0.125;  // kGgxPrefilterMinRoughness
const float kSharpestAlpha = kSharpestRoughness * kSharpestRoughness;
float mirror_level_weight(float roughness, float spread) {
    float alpha = roughness * roughness;
    float widened = sqrt(alpha * alpha + min(0.075 * spread, kSharpestAlpha * kSharpestAlpha));
    return clamp(widened / kSharpestAlpha, 0.0, 1.0);
}

const float kDielectricF0 = 0.04;  // glTF's dielectric reflectance at normal incidence (ior 1.5)
const float kMinAlpha = 1e-3;      // env/gltf_brdf.h's floor on alpha = roughness^2

// glTF's material at one pixel: what the split sum and the cells' weights share.
struct GltfPixel {
    float metallic, roughness;  // the factors times the texture's
    float n_dot_v;
    float alpha2;          // alpha^2, alpha = roughness^2
    vec3 f0;               // mix(0.04, baseColor, metallic)
    vec3 diffuse_albedo;   // (1 - metallic)(1 - 0.04) baseColor diffuse(n.v): L_diff = it E(n) / pi
    vec3 specular_albedo;  // F0 scale(n.v, roughness) + bias(n.v, roughness): L_spec = it P(r, alpha)
    float mirror_spread;   // |dr/dx|^2 + |dr/dy|^2 of the pixel's footprint (0 without multisampling)
    float lobe_axis;       // the lobe's centroid at this share of the angle from the normal to the mirror
};

// The direction the split sum looks its round lobe up in: the BRDF lobe's centroid, turned from the normal
// towards the mirror direction r by the table's share of their angle (docs/DESIGN.md §11, "The lobe's axis").
vec3 lobe_axis(GltfPixel p, vec3 n, vec3 r) {
    vec3 across = r - n * dot(n, r);
    float length_across = length(across);
    if (length_across < 1e-6) return r;
    float angle = p.lobe_axis * atan(length_across, dot(n, r));
    return n * cos(angle) + across * (sin(angle) / length_across);
}

// Whether the pixel's lobe is sharper than the sharpest level: its lookup is the map itself and that level.
bool below_levels(GltfPixel p) {
    return p.roughness < kSharpestRoughness;
}

// base_color: the texture's at this pixel; n_dot_v of the shading normal; pixel the pixel's footprint.
GltfPixel gltf_pixel(vec3 base_color, vec2 texcoord, float n_dot_v, PixelFootprint pixel) {
    GltfPixel p;
    vec2 metallic_roughness = texture(u_metallic_roughness_texture, texcoord).bg;
    p.metallic = u_metallic * metallic_roughness.x;
    p.roughness = u_roughness * metallic_roughness.y;
    p.mirror_spread = dot(pixel.mirror_dx, pixel.mirror_dx) + dot(pixel.mirror_dy, pixel.mirror_dy);
    p.n_dot_v = clamp(n_dot_v, 0.0, 1.0);
    float alpha = max(p.roughness * p.roughness, kMinAlpha);
    p.alpha2 = alpha * alpha;
    vec3 base = u_base_color_factor * base_color;
    vec4 dfg = texture(u_dfg, vec2(p.n_dot_v, p.roughness));
    p.lobe_axis = dfg.w;
    p.f0 = mix(vec3(kDielectricF0), base, p.metallic);
    p.diffuse_albedo = base * ((1.0 - p.metallic) * (1.0 - kDielectricF0) * dfg.z);
    p.specular_albedo = p.f0 * dfg.x + dfg.y;
    return p;
}
