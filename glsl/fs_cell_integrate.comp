#version 450 core
// FsLightModel::cells, second pass: one work group per light integrates its cell of the importance map
// as the CPU methods integrate theirs (docs/DESIGN.md §3): radiance = sum L dw, solid angle = sum dw,
// centre = the normalised sum I w (the light's own direction where the cell has no importance),
// cos_radius = 1 - dw_i / (2 pi), cos_radius_weighted = 2 |sum I w| / sum I - 1. The lights' sum is then
// the integral over what was sampled, whatever the scan's rounding of S / K.
#include "fs_common.glsl"

layout(local_size_x = FS_WORK_GROUP) in;

layout(binding = UNIT_RADIANCE) uniform sampler2D u_radiance;  // sum L dw (rgb) and importance (a) per importance texel
layout(binding = UNIT_MOMENTS) uniform sampler2D u_moments;    // sum lum(L) dw w (xyz), sum dw (w) per importance texel
layout(std430, binding = BINDING_FS_COUNTS) readonly buffer FsCounts { FS_COUNTS_MEMBERS };
layout(std430, binding = BINDING_FS_LIGHTS) buffer FsLights { FsLight fs_lights[]; };
layout(std430, binding = BINDING_FS_SITES) readonly buffer FsSites { vec4 fs_sites[]; };
layout(std430, binding = BINDING_FS_NEAREST) readonly buffer FsNearest { uint fs_nearest_light[]; };

layout(location = LOC_WORLD_FROM_MAP) uniform mat3 u_world_from_map;
layout(location = LOC_RADIANCE_SCALE) uniform float u_radiance_scale;  // exposure
layout(location = LOC_SCAN_ROWS) uniform int u_scan_rows;

shared vec4 partial_radiance[FS_WORK_GROUP];
shared vec4 partial_moments[FS_WORK_GROUP];

void main() {
    const uint light = gl_WorkGroupID.x;
    if (light >= light_count) return;  // the whole work group
    const ivec2 size = textureSize(u_radiance, 0);
    const uint lane = gl_LocalInvocationID.x;
    vec4 radiance = vec4(0.0), moments = vec4(0.0);
    for (int t = int(lane); t < size.x * u_scan_rows; t += FS_WORK_GROUP) {
        if (fs_nearest_light[t] != light) continue;
        const ivec2 texel = ivec2(t % size.x, t / size.x);
        radiance += texelFetch(u_radiance, texel, 0);
        moments += texelFetch(u_moments, texel, 0);
    }
    partial_radiance[lane] = radiance;
    partial_moments[lane] = moments;
    barrier();
    for (uint stride = uint(FS_WORK_GROUP) / 2u; stride > 0u; stride >>= 1) {
        if (lane < stride) {
            partial_radiance[lane] += partial_radiance[lane + stride];
            partial_moments[lane] += partial_moments[lane + stride];
        }
        barrier();
    }
    if (lane != 0u) return;
    const vec4 cell_radiance = partial_radiance[0], cell_moments = partial_moments[0];
    const float importance = cell_radiance.a, solid_angle = cell_moments.w;
    const float mean_length = length(cell_moments.xyz);
    const bool weighted = importance > 0.0 && mean_length > 1e-9 * importance;
    const vec3 map_direction = weighted ? cell_moments.xyz / mean_length : fs_sites[light].xyz;
    FsLight cell = fs_lights[light];
    cell.direction = normalize(u_world_from_map * map_direction);
    cell.radiance = cell_radiance.rgb * u_radiance_scale;
    cell.solid_angle = solid_angle;
    cell.cos_radius = clamp(1.0 - solid_angle / (2.0 * PI), -1.0, 1.0);
    cell.cos_radius_weighted = weighted ? clamp(2.0 * mean_length / importance - 1.0, -1.0, 1.0) : cell.cos_radius;
    fs_lights[light] = cell;
}
