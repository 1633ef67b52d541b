#version 450 core
// FsLightModel::cells, first pass: every importance texel the scan covered goes to its nearest light by
// angle (docs/DESIGN.md §3: the cells every CPU method ends with), lowest index on ties, so that
// fs_cell_integrate.comp can integrate each light over its cell.
#include "fs_common.glsl"

layout(local_size_x = FS_WORK_GROUP) in;

layout(binding = UNIT_RADIANCE) uniform sampler2D u_radiance;  // the importance map's size
layout(std430, binding = BINDING_FS_COUNTS) readonly buffer FsCounts { FS_COUNTS_MEMBERS };
layout(std430, binding = BINDING_FS_SITES) readonly buffer FsSites { vec4 fs_sites[]; };  // map-space light directions
layout(std430, binding = BINDING_FS_NEAREST) writeonly buffer FsNearest { uint fs_nearest_light[]; };

layout(location = LOC_SCAN_ROWS) uniform int u_scan_rows;

void main() {
    const ivec2 size = textureSize(u_radiance, 0);
    const int texel_index = int(gl_GlobalInvocationID.x);
    if (texel_index >= size.x * u_scan_rows) return;
    const vec3 p = fs_texel_direction(ivec2(texel_index % size.x, texel_index / size.x), size);
    uint best = 0u;
    float best_cos = -2.0;
    for (uint k = 0u; k < light_count; ++k) {
        const float c = dot(p, fs_sites[k].xyz);
        if (c > best_cos) {
            best_cos = c;
            best = k;
        }
    }
    fs_nearest_light[texel_index] = best;
}
