// The lat-long convention in GLSL: the mirror of engine/env/latlong.h (tests/render/latlong_glsl_test.cpp
// keeps the two equal). Included by every stage that looks up or samples the environment map.
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
