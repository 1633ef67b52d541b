#version 450 core
// The shadowed fraction's texels filtered over their surface (docs/DESIGN.md §5.14): the soft shadows' disc
// turns from texel to texel (shade_soft_shadows.glsl, disc_direction), so each texel holds one rotation's
// estimate, and a 3x3 binomial, (1 2 1) x (1 2 1), averages nine. Texels count in pairs opposite each other
// about the centre: a pair whose mean 1/w is the centre's lies on a plane through it (a pair that straddles
// an edge does not), and it must face the centre's way. Each texel of a pair is weighted further by how near
// its fraction is to the centre's (kNoiseScale). The mean is taken of the shadow 1 - f, so that where every
// texel is 1 the result is exactly 1.
#include "fraction_surface.glsl"

layout(binding = UNIT_FRACTION) uniform sampler2D u_fraction;                // the fraction, 1/w
layout(binding = UNIT_FRACTION_NORMAL) uniform sampler2D u_fraction_normal;  // the shading normal

layout(location = 0) out vec4 o_fraction;

// The fraction difference at which a neighbour's weight falls to 1/e: where many cells of small share light a
// penumbra (a room through its door, a uniform sky) their noise is a few hundredths; a sun's share moves f by
// more at its shadow's edge, and blurring that edge cost sphere_ground / city 1.53% -> 1.78%.
const float kNoiseScale = 0.1;

struct Sums {
    vec3 shadow;
    float weight;
};

// The pair at +-offset about `centre` (fraction f, 1/w w, shading normal n), of binomial weight `weight` each;
// `last` is the texture's last texel.
void add_pair(inout Sums sums, ivec2 centre, ivec2 offset, ivec2 last, float weight, vec3 f, float w, vec3 n) {
    ivec2 a = clamp(centre + offset, ivec2(0), last), b = clamp(centre - offset, ivec2(0), last);
    vec4 ta = texelFetch(u_fraction, a, 0), tb = texelFetch(u_fraction, b, 0);
    if (ta.a <= 0.0 || tb.a <= 0.0) return;
    float e = (0.5 * (ta.a + tb.a) - w) / (kPlaneToleranceOfDepth * w);
    vec4 na = texelFetch(u_fraction_normal, a, 0), nb = texelFetch(u_fraction_normal, b, 0);
    float facing = max(dot(n, na.xyz), 0.0) * max(dot(n, nb.xyz), 0.0);
    float match = weight * exp(-e * e) * pow(facing, kNormalPower);
    vec3 da = (ta.rgb - f) / kNoiseScale, db = (tb.rgb - f) / kNoiseScale;
    float wa = match * exp(-dot(da, da)), wb = match * exp(-dot(db, db));
    sums.shadow += wa * (1.0 - ta.rgb) + wb * (1.0 - tb.rgb);
    sums.weight += wa + wb;
}

void main() {
    ivec2 centre = ivec2(gl_FragCoord.xy);
    vec4 texel = texelFetch(u_fraction, centre, 0);
    if (texel.a <= 0.0) {  // no object
        o_fraction = texel;
        return;
    }
    vec3 normal = texelFetch(u_fraction_normal, centre, 0).xyz;
    Sums sums = Sums(4.0 * (1.0 - texel.rgb), 4.0);
    ivec2 last = textureSize(u_fraction, 0) - 1;
    add_pair(sums, centre, ivec2(1, 0), last, 2.0, texel.rgb, texel.a, normal);
    add_pair(sums, centre, ivec2(0, 1), last, 2.0, texel.rgb, texel.a, normal);
    add_pair(sums, centre, ivec2(1, 1), last, 1.0, texel.rgb, texel.a, normal);
    add_pair(sums, centre, ivec2(1, -1), last, 1.0, texel.rgb, texel.a, normal);
    o_fraction = vec4(1.0 - sums.shadow / sums.weight, texel.a);
}
