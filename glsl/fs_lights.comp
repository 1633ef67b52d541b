#version 450 core
// Turns the Floyd-Steinberg samples (fs_sampler.geom) into lights once their number K is known
// (docs/DESIGN.md §5). A light of multiplicity m (m of the K samples on one texel) gets the texel's
// importance-weighted mean direction (its centre where it has no importance: as the CPU's
// centroid_direction does, falling back on the centre rather than the solid-angle mean); radiance of
// luminance m S / K in the texel's colour (the estimator L / p of Szirmay-Kalos et al.'s §1.2 for a texel chosen with
// p = I / S, over K samples); a cap of solid angle m 4 pi / K (cos_radius; m 2 pi / K when only the
// upper hemisphere is sampled); and, as its radiance-weighted cap, the solid angle over which the
// texel's own radiance integrates to that luminance, m (S / K) dw / I, at most that cap's: a
// texel-sized cap for a sun, 4 pi / K where importance is uniform.
#include "fs_common.glsl"

layout(local_size_x = FS_WORK_GROUP) in;

layout(binding = UNIT_RADIANCE) uniform sampler2D u_radiance;  // sum L dw (rgb) and importance (a) per importance texel
layout(binding = UNIT_MOMENTS) uniform sampler2D u_moments;    // sum lum(L) dw w (xyz) per importance texel
layout(std430, binding = BINDING_FS_SAMPLES) readonly buffer FsSamples { uint captured_sample[]; };
layout(std430, binding = BINDING_FS_COUNTS) readonly buffer FsCounts { FS_COUNTS_MEMBERS };
layout(std430, binding = BINDING_FS_LIGHTS) writeonly buffer FsLights { FsLight fs_lights[]; };
layout(std430, binding = BINDING_FS_SITES) writeonly buffer FsSites { vec4 fs_sites[]; };  // map-space directions (cells)

layout(location = LOC_WORLD_FROM_MAP) uniform mat3 u_world_from_map;
layout(location = LOC_RADIANCE_SCALE) uniform float u_radiance_scale;  // exposure
layout(location = LOC_SAMPLED_SOLID_ANGLE) uniform float u_sampled_solid_angle;  // 4 pi, or 2 pi for the upper hemisphere

void main() {
    const uint index = gl_GlobalInvocationID.x;
    if (index >= light_count) return;
    const ivec2 size = textureSize(u_radiance, 0);
    const int texel_index = int(fs_sample_texel(captured_sample[index]));
    const ivec2 texel = ivec2(texel_index % size.x, texel_index / size.x);
    const float share = float(fs_sample_multiplicity(captured_sample[index])) / float(samples);  // m / K
    const vec4 texel_radiance = texelFetch(u_radiance, texel, 0);
    const float texel_importance = texel_radiance.a;  // lum(rgb)
    // A texel may be chosen by carried error alone while itself black: give it a neutral colour.
    const vec3 chromaticity = texel_importance > 0.0 ? texel_radiance.rgb / texel_importance : vec3(1.0);
    const float solid_angle = u_sampled_solid_angle * share;
    const float light_importance = importance_sum * share;
    const float local_solid_angle = texel_importance > 0.0
        ? min(solid_angle, light_importance * fs_texel_solid_angle(texel.y, size) / texel_importance)
        : solid_angle;

    FsLight light;
    const vec3 importance_direction = texelFetch(u_moments, texel, 0).xyz;
    const vec3 map_direction = length(importance_direction) > 1e-9 * texel_importance && texel_importance > 0.0
        ? normalize(importance_direction)
        : fs_texel_direction(texel, size);
    light.direction = normalize(u_world_from_map * map_direction);
    fs_sites[index] = vec4(map_direction, 0.0);
    light.solid_angle = solid_angle;
    light.radiance = chromaticity * (u_radiance_scale * light_importance);
    light.cos_radius = 1.0 - solid_angle / (2.0 * PI);
    light.cos_radius_weighted = 1.0 - local_solid_angle / (2.0 * PI);
    light.unused0 = light.unused1 = light.unused2 = 0.0;
    fs_lights[index] = light;
}
