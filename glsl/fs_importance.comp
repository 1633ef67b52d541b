#version 450 core
// Importance map of the Floyd-Steinberg sampler (Szirmay-Kalos et al. §1.3.2, light source sampling): the
// luminance of the radiance integrated over each texel's solid angle, I = lum(sum L dw), at the
// importance map's resolution, and the importance-weighted direction sum (for the texel's centroid). Each importance texel sums the environment texels whose centres it
// contains (an exact box of f x f texels when the sizes divide). One work group per importance row
// also reduces the row's sum, so that the sampler adds H row sums instead of W x H texels for S.
#include "fs_common.glsl"

layout(local_size_x = FS_WORK_GROUP) in;

layout(binding = UNIT_ENVIRONMENT) uniform sampler2D u_environment;  // lat-long RGB(A), texel (i, j) = map texel (i, j)
layout(binding = IMAGE_IMPORTANCE, r32f) uniform writeonly image2D u_importance;
layout(binding = IMAGE_RADIANCE, rgba32f) uniform writeonly image2D u_radiance;  // sum L dw over the texel (RGB), I (a)
layout(binding = IMAGE_MOMENTS, rgba32f) uniform writeonly image2D u_moments;    // sum of lum(L) dw w (xyz), sum dw (w)
layout(std430, binding = BINDING_FS_ROW_SUMS) writeonly buffer FsRowSums { double row_sum[]; };

// A ground hides the directions below the horizon: only the environment texels above it count (for an
// odd height, the upper half of the middle row's solid angle), so no sample falls below the ground.
layout(location = LOC_UPPER_HEMISPHERE) uniform bool u_upper_hemisphere;

shared double partial_sums[FS_WORK_GROUP];

// First fine index whose texel centre lies in coarse texel `coarse`: ceil(coarse * fine / coarse_size - 0.5).
int block_start(int coarse, int fine_size, int coarse_size) {
    return (2 * coarse * fine_size + coarse_size - 1) / (2 * coarse_size);
}

void main() {
    const ivec2 env_size = textureSize(u_environment, 0);
    const ivec2 size = imageSize(u_importance);
    const int row = int(gl_WorkGroupID.y);
    const int env_row_begin = block_start(row, env_size.y, size.y);
    const int env_row_end = block_start(row + 1, env_size.y, size.y);

    double row_importance = 0.0;
    for (int column = int(gl_LocalInvocationID.x); column < size.x; column += FS_WORK_GROUP) {
        const int env_column_begin = block_start(column, env_size.x, size.x);
        const int env_column_end = block_start(column + 1, env_size.x, size.x);
        vec3 radiance = vec3(0.0), importance_direction = vec3(0.0);
        float solid_angle = 0.0;
        for (int y = env_row_begin; y < env_row_end; ++y) {
            const float above = !u_upper_hemisphere || 2 * y + 2 <= env_size.y ? 1.0 : 2 * y + 1 == env_size.y ? 0.5 : 0.0;
            const float texel_solid_angle = above * fs_texel_solid_angle(y, env_size);
            vec3 row_radiance = vec3(0.0), row_direction = vec3(0.0);
            for (int x = env_column_begin; x < env_column_end; ++x) {
                const vec3 texel = max(texelFetch(u_environment, ivec2(x, y), 0).rgb, vec3(0.0));  // docs/DESIGN.md §2: clamp negatives
                row_radiance += texel;
                row_direction += fs_luminance(texel) * fs_texel_direction(ivec2(x, y), env_size);
            }
            radiance += row_radiance * texel_solid_angle;
            importance_direction += row_direction * texel_solid_angle;
            solid_angle += texel_solid_angle * float(env_column_end - env_column_begin);
        }
        const float importance = fs_luminance(radiance);
        imageStore(u_importance, ivec2(column, row), vec4(importance));
        imageStore(u_radiance, ivec2(column, row), vec4(radiance, importance));
        imageStore(u_moments, ivec2(column, row), vec4(importance_direction, solid_angle));
        row_importance += double(importance);
    }

    partial_sums[gl_LocalInvocationID.x] = row_importance;
    barrier();
    for (uint stride = FS_WORK_GROUP / 2; stride > 0; stride >>= 1) {
        if (gl_LocalInvocationID.x < stride)
            partial_sums[gl_LocalInvocationID.x] += partial_sums[gl_LocalInvocationID.x + stride];
        barrier();
    }
    if (gl_LocalInvocationID.x == 0) row_sum[row] = partial_sums[0];
}
