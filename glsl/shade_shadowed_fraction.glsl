// The ratio estimator split in two passes (docs/DESIGN.md §5.14). The fraction pass
// (SHADOWED_FRACTION_OUT, one sample per pixel or per 2x2 pixels) writes the cells' shadowed fraction and
// its surface's 1/w (gl_FragCoord.w: 1 / view depth, affine in window coordinates over a plane), and its
// shading normal; texels without an object keep the clear's alpha 0. The shading (SHADOWED_FRACTION_IN,
// at the image's own samples) takes the fraction from the texels about the fragment whose surface is the
// fragment's own: its plane's 1/w carried to each texel's centre must meet the texel's, and the normals
// must agree (where two surfaces meet, as an object standing on the ground, the depths do). With both
// (SHADOWED_FRACTION_REFINE, one sample per pixel) the per-2x2 texels are looked up so, and the fraction
// computed again where they disagree.

#if defined(SHADOWED_FRACTION_OUT)
layout(location = 1) out vec4 o_fraction_normal;

// What the fraction pass writes: the fraction and 1/w to location 0, the normal to location 1.
vec4 fraction_texel(vec3 fraction, vec3 normal) {
    o_fraction_normal = vec4(normal, 0.0);
    return vec4(fraction, gl_FragCoord.w);
}
#endif

#if defined(SHADOWED_FRACTION_IN)
// The fraction pass's two targets, read with texelFetch.
layout(binding = UNIT_FRACTION) uniform sampler2D u_fraction;                // the fraction, 1/w
layout(binding = UNIT_FRACTION_NORMAL) uniform sampler2D u_fraction_normal;  // the shading normal
layout(location = LOC_FRACTION_SCALE) uniform vec2 u_fraction_scale;         // texels per pixel, x and y
#if defined(SUN_PER_PIXEL)
layout(binding = UNIT_FRACTION_SUN) uniform sampler2D u_fraction_sun;  // the sun's share, its V (shade_sun_per_pixel.glsl)
#endif

#include "fraction_surface.glsl"

// The fragment's plane: 1/w at the fragment and its change per pixel; its shading normal.
struct FragmentPlane {
    float w;
    vec2 slope;
    float tolerance;
    vec3 normal;
};

// How well texel t lies on the plane and faces its way: 1 on it, falling off over the tolerance; 0 for a
// texel without an object.
float plane_match(FragmentPlane plane, ivec2 t, float texel_w) {
    vec2 centre = (vec2(t) + 0.5) / u_fraction_scale;  // the texel's centre in window coordinates
    float expected = plane.w + dot(plane.slope, centre - gl_FragCoord.xy);
    float e = (texel_w - expected) / plane.tolerance;
    float facing = max(dot(plane.normal, texelFetch(u_fraction_normal, t, 0).xyz), 0.0);
    return texel_w > 0.0 ? exp(-e * e) * pow(facing, kNormalPower) : 0.0;
}

// SHADOWED_FRACTION_REFINE: the fraction is computed again where the texels looked up on the fragment's
// surface (plane_match over kSameSurfaceMatch) differ by more than kRefinedSpread (docs/DESIGN.md §5.14).
const float kRefinedSpread = 0.1;
const float kSameSurfaceMatch = 0.5;

// The texels looked up: a tent of kTentRadius texels over the kTexelsAcross^2 about the fragment. The
// shading's is the bilinear 2x2; the refinement's, wider, also averages the soft shadows' per-texel disc
// rotations (their noise).
#if defined(SHADOWED_FRACTION_REFINE)
const int kTexelsAcross = 4;
const float kTentRadius = 1.6;
#else
const int kTexelsAcross = 2;
const float kTentRadius = 1.0;
#endif

struct UpsampledFraction {
    vec3 fraction;
    // How far apart the fractions (their largest channel) of the texels on the fragment's surface lie; 1
    // where none of them is on it.
    float spread;
    // SUN_PER_PIXEL, from the same texels with the same weights: the sun's share (RGB) and its share of the
    // fraction, share x V (the products averaged: where the texels straddle its terminator, those under the
    // plane have share 0 and V 1).
    vec3 sun_share, sun_lit;
};

// The sun's texel t (SUN_PER_PIXEL): its share and V; or nothing of a sun.
vec4 sun_texel(ivec2 t) {
#if defined(SUN_PER_PIXEL)
    return texelFetch(u_fraction_sun, t, 0);
#else
    return vec4(0.0, 0.0, 0.0, 1.0);
#endif
}

// A sun texel's share and share x V, to be averaged.
mat2x3 sun_terms(vec4 texel) {
    return mat2x3(texel.rgb, texel.rgb * texel.a);
}

// The shadowed fraction at this fragment: the fraction texels about it weighted by the tent and by how well
// they lie on its plane (a joint bilateral upsampling); where none does (a silhouette the fraction's samples
// missed), the 3x3 texels about the nearest by the plane alone, and failing that the one nearest in depth.
// The mean is taken of the shadow 1 - f, so that fractions of exactly 1 (nothing in the way) give exactly 1.
UpsampledFraction fraction_at_fragment(vec3 normal) {
    FragmentPlane plane;
    plane.normal = normal;
    plane.w = gl_FragCoord.w;
    plane.slope = vec2(dFdx(gl_FragCoord.w), dFdy(gl_FragCoord.w));
    plane.tolerance = kPlaneToleranceOfDepth * plane.w + abs(plane.slope.x) + abs(plane.slope.y);
    ivec2 last = textureSize(u_fraction, 0) - 1;
    vec2 q = gl_FragCoord.xy * u_fraction_scale - 0.5;  // texel centres at integers
    ivec2 base = ivec2(floor(q)) - (kTexelsAcross / 2 - 1);
    vec3 shadow = vec3(0.0);
    mat2x3 sun = mat2x3(0.0);
    float total = 0.0;
    float lowest = 1.0, highest = 0.0;  // of the texels on the fragment's surface
    for (int k = 0; k < kTexelsAcross * kTexelsAcross; ++k) {
        ivec2 t = base + ivec2(k % kTexelsAcross, k / kTexelsAcross);
        vec2 d = abs(vec2(t) - q) / kTentRadius;
        float tent = max(1.0 - d.x, 0.0) * max(1.0 - d.y, 0.0);
        t = clamp(t, ivec2(0), last);
        vec4 texel = texelFetch(u_fraction, t, 0);
        float match = plane_match(plane, t, texel.a);
        shadow += tent * match * (1.0 - texel.rgb);
        sun += tent * match * sun_terms(sun_texel(t));
        total += tent * match;
        if (tent > 0.0 && match > kSameSurfaceMatch) {
            float largest = max(max(texel.r, texel.g), texel.b);
            lowest = min(lowest, largest);
            highest = max(highest, largest);
        }
    }
    float spread = highest >= lowest ? highest - lowest : 1.0;
    if (total > 1e-3) return UpsampledFraction(1.0 - shadow / total, spread, sun[0] / total, sun[1] / total);

    ivec2 nearest = ivec2(floor(q + 0.5));
    vec3 best = vec3(1.0);  // lit where no texel has an object
    mat2x3 best_sun = mat2x3(0.0);
    float best_distance = 1e30;
    shadow = vec3(0.0);
    sun = mat2x3(0.0);
    total = 0.0;
    for (int y = -1; y <= 1; ++y)
        for (int x = -1; x <= 1; ++x) {
            ivec2 t = clamp(nearest + ivec2(x, y), ivec2(0), last);
            vec4 texel = texelFetch(u_fraction, t, 0);
            float weight = plane_match(plane, t, texel.a);
            shadow += weight * (1.0 - texel.rgb);
            sun += weight * sun_terms(sun_texel(t));
            total += weight;
            float distance = abs(texel.a - plane.w);
            if (texel.a > 0.0 && distance < best_distance) {
                best_distance = distance;
                best = texel.rgb;
                best_sun = sun_terms(sun_texel(t));
            }
        }
    if (total > 1e-3) return UpsampledFraction(1.0 - shadow / total, 1.0, sun[0] / total, sun[1] / total);
    return UpsampledFraction(best, 1.0, best_sun[0], best_sun[1]);
}
#endif
