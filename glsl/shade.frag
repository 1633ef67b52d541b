#version 450 core
// Reflected radiance of the environment with shadows (Barsi et al. §2), times the material's occlusion
// texture, plus its emission:
//   L(x, w) ~ sum_i V(x, w_i) L~_i a(dw_i, w),  a = k_d (cos theta average) + k_s (a_s / k_s)
// One loop over the cells; engine/render/renderer.cpp sets the options as #defines, each handled in the
// include that owns its concept:
//   shade_surface.glsl       the shaded point: normals, mirror direction, material
//   shade_reflectivity.glsl  a(dw_i, w) (DIFFUSE_CAP, SPECULAR_SINGLE, DIFFUSE_ONLY)
//   shade_visibility.glsl    V(x, w_i) from the cell's tile in the shadow atlas (PCF_WIDE, SOFT_SHADOWS)
//   shade_cell_sums.glsl     the sums and the cells the loop visits (SHADOW_TILE_LISTS, FLAT_RECEIVER)
//   shade_ratio.glsl         the radiance from the sums (SHADING_RATIO: the ratio estimator; its clipping
//                            at the tangent plane is the reflectivity's and the visibility's)
//   shade_metallic_roughness.glsl  glTF's BRDF unshadowed, by the split sum (METALLIC_ROUGHNESS)
//   alpha_mask.glsl          ALPHA_TEST (no depth pre-pass): masked surfaces cut out here; ALPHA_BLEND: the
//                            radiance premultiplied by the alpha, laid over what is behind (draw_blended)
//   shade_shadowed_fraction.glsl  the ratio split in two passes (docs/DESIGN.md §5.14): SHADOWED_FRACTION_OUT
//                            writes the fraction, SHADOWED_FRACTION_IN shades with it instead of the loop;
//                            SHADOWED_FRACTION_REFINE (with both) writes it per pixel, looked up where the
//                            per-2x2 fractions agree and from the loop where they do not
//   shade_sun_per_pixel.glsl the sun's shadow looked up again at each pixel (SUN_PER_PIXEL)
#include "shade_cell_sums.glsl"
#include "shade_ratio.glsl"
#include "shade_shadowed_fraction.glsl"
#include "shade_surface.glsl"
#if defined(SUN_PER_PIXEL)
#include "shade_sun_per_pixel.glsl"
#endif

// centroid: with MSAA, interpolated inside the triangle (at a covered sample) rather than at the pixel
// centre, which may lie beyond a silhouette edge; the same as the centre at one sample per pixel.
layout(location = 0) centroid in vec3 v_world_position;
layout(location = 1) centroid in vec3 v_world_normal;
layout(location = 2) centroid in vec2 v_texcoord;
// Not centroid: at the pixel centre, for the triangle's plane (shade_surface.glsl).
layout(location = 3) in vec3 v_world_position_at_centre;
layout(location = 4) centroid in vec4 v_world_tangent;

layout(location = 0) out vec4 o_color;

void main() {
    Surface s = surface(v_world_position, v_world_position_at_centre, v_world_normal,
                        interpolateAtOffset(v_world_normal, vec2(0.0)), v_world_tangent, v_texcoord);
#if defined(ALPHA_TEST)
    if (cut_out(mask_alpha(u_base_color, v_texcoord))) discard;  // without a depth pre-pass, which keeps them out
#endif
#if defined(SHADOWED_FRACTION_REFINE)
    UpsampledFraction upsampled = fraction_at_fragment(s.normal);
    vec3 fraction = upsampled.fraction;
    if (upsampled.spread > kRefinedSpread) {
        CellSums sums = cell_sums(s);
        fraction = shadowed_fraction(shadowed_sum(sums), sums.whole_lobe);
    }
    o_color = fraction_texel(fraction, s.normal);
#elif defined(SHADOWED_FRACTION_IN)
    UpsampledFraction upsampled = fraction_at_fragment(s.normal);
    vec3 fraction = upsampled.fraction;
#if defined(SUN_PER_PIXEL)
    if (sun_looked_up(s))
        fraction = clamp(fraction + upsampled.sun_share * sun_visibility(s) - upsampled.sun_lit, 0.0, 1.0);
#endif
    vec3 reflected = unshadowed_radiance(s) * fraction;
    o_color = vec4(reflected * occlusion(s) + emitted_radiance(s), 1.0);
#else
    CellSums sums = cell_sums(s);
#if defined(SHADOWED_FRACTION_OUT)
    o_color = fraction_texel(shadowed_fraction(shadowed_sum(sums), sums.whole_lobe), s.normal);
#if defined(SUN_PER_PIXEL)
    write_sun_texel(s, sums.whole_lobe);
#endif
#else
    vec3 reflected = reflected_radiance(s, shadowed_sum(sums), sums.whole_lobe);
    vec3 radiance = reflected * occlusion(s) + emitted_radiance(s);
#if defined(ALPHA_BLEND)
    o_color = vec4(radiance * s.alpha, s.alpha);  // glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA)
#else
    o_color = vec4(radiance, 1.0);  // alpha 1 marks object pixels (the accuracy comparison masks by it)
#endif
#endif
#endif
}
