// Shared by every stage that shades or draws the environment: the lat-long convention (the GLSL
// mirror of engine/env/latlong.h; tests/render/latlong_glsl_test.cpp keeps the two equal) and the
// per-light record of the shadow atlas (engine/render/lights.h's LightRecord is its C++ twin).
#include "constants.glsl"

// Lat-long map: u = (i + 0.5) / W, v = (j + 0.5) / H, row 0 the zenith (+Y);
// theta = pi v from +Y, phi = 2 pi u, direction = (sin theta cos phi, cos theta, sin theta sin phi).
vec3 latlong_direction(vec2 uv) {
    float theta = PI * uv.y, phi = 2.0 * PI * uv.x;
    float s = sin(theta);
    return vec3(s * cos(phi), cos(theta), s * sin(phi));
}

// u in [0, 1), v in [0, 1]; `d` unit length. theta = atan(|d.xz|, d.y) equals latlong.h's
// acos(d.y) but keeps float precision near the poles; u = 0 at the poles themselves.
vec2 latlong_uv(vec3 d) {
    float horizontal = length(d.xz);
    float u = horizontal > 0.0 ? atan(d.z, d.x) / (2.0 * PI) : 0.0;
    if (u < 0.0) u += 1.0;
    if (u >= 1.0) u -= 1.0;
    return vec2(u, atan(horizontal, d.y) / PI);
}

// One directional cell of the environment (Barsi et al. §2): the sum over cells of
// V(x, w_i) L~_i a(dw_i, w) approximates the reflected radiance.
struct Light {
    vec4 direction;        // xyz: w_i in world space (towards the light); w: cos r_i of the chosen cap
    vec4 radiance;         // rgb: L~_i = integral of L_env over the cell; w: unused
    mat4 clip_from_world;  // orthographic along -w_i, fitted to the casters: the tile's [-1, 1]^3
    vec4 tile;             // xy: the tile's lower-left corner in atlas uv, zw: its size in atlas uv
    vec4 bias;             // x: receiver depth bias (depth units), y: normal offset (world units)
};

#ifndef LIGHTS_BINDING
#define LIGHTS_BINDING 0
#endif
#if defined(LIGHTS_UNIFORM_BLOCK)
// A uniform block (std140 lays this struct out as std430 does): llvmpipe loads it once per loop
// iteration for all lanes; the storage block below it gathers per lane (docs/PERFORMANCE.md).
layout(std140, binding = LIGHTS_BINDING) uniform LightBlock { Light lights[MAX_LIGHTS]; };
#else
layout(std430, binding = LIGHTS_BINDING) readonly buffer LightBlock { Light lights[]; };
#endif
