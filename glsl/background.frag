#version 450 core
// The environment behind the objects: each sample's direction from the inverse view-projection,
// rotated into map space, looked up in the lat-long map. Computed per sample (v_ndc is interpolated
// there), so that with MSAA a pixel is the map's mean over it, as the box-filtered reference takes
// it, and a pixel an object covers in part shows the map beside the object; no pinch
// at the poles; the map repeats in u (no seam at the wrap) and is clamped in v; no mipmaps, so the
// jump of u at the wrap cannot select a blurry level.
#include "latlong.glsl"

layout(location = 0) sample in vec2 v_ndc;

layout(location = LOC_DIRECTION_FROM_CLIP) uniform mat4 u_direction_from_clip;  // world_from_view (rotation) * view_from_clip
layout(location = LOC_MAP_FROM_WORLD) uniform mat3 u_map_from_world;

layout(binding = UNIT_ENVIRONMENT) uniform sampler2D u_environment;

layout(location = 0) out vec4 o_color;

void main() {
    vec4 d = u_direction_from_clip * vec4(v_ndc, 1.0, 1.0);
    vec3 world = normalize(d.xyz / d.w);
    vec3 radiance = texture(u_environment, latlong_uv(normalize(u_map_from_world * world))).rgb;
    o_color = vec4(radiance, 0.0);  // alpha 0: background
}
