#version 450 core
// Depth of the shadow casters into the shadow atlas: instance k draws the mesh into tile
// u_first_tile + k (ATLAS_CLIP_DISTANCES: tile atlas_tiles[u_first_tile + k]), orthographically along
// -w_i (Barsi et al. §2.2: one depth map per cell).
// One of three ways keeps a tile's triangles inside its rectangle (engine/render/render_settings.h
// AtlasMode; engine/render/renderer.cpp draw_atlas):
//   ATLAS_CLIP_DISTANCES  the tiles that take one level of the mesh in one instanced draw over the
//                         whole atlas; four clip distances cut each instance to the tile's [-1, 1]^2
//   ATLAS_VIEWPORT_ARRAY  batches of GL_MAX_VIEWPORTS instances, instance k to viewport k
//   (neither)             the baseline: one draw per tile, the viewport set to the tile
#if defined(ATLAS_VIEWPORT_ARRAY)
#extension GL_ARB_shader_viewport_layer_array : require
#endif
#include "cells.glsl"

layout(location = ATTRIB_POSITION) in vec3 a_position;
#if defined(ALPHA_MASK)
// Alpha-masked casters: the texture coordinates for shadow_atlas_mask.frag.
layout(location = ATTRIB_TEXCOORD) in vec2 a_texcoord;
layout(location = 0) out vec2 v_texcoord;
#endif

layout(location = LOC_WORLD_FROM_OBJECT) uniform mat4 u_world_from_object;
layout(location = LOC_FIRST_TILE) uniform int u_first_tile;

#if defined(ATLAS_CLIP_DISTANCES)
layout(std430, binding = BINDING_ATLAS_TILES) readonly buffer AtlasTiles { int atlas_tiles[]; };

out gl_PerVertex {
    vec4 gl_Position;
    float gl_ClipDistance[4];
};
#endif

void main() {
#if defined(ALPHA_MASK)
    v_texcoord = a_texcoord;
#endif
#if defined(ATLAS_CLIP_DISTANCES)
    int tile = atlas_tiles[u_first_tile + gl_InstanceID];
#else
    int tile = u_first_tile + gl_InstanceID;
#endif
    vec4 clip = lights[tile].clip_from_world * (u_world_from_object * vec4(a_position, 1.0));  // w = 1
#if defined(ATLAS_CLIP_DISTANCES)
    gl_ClipDistance[0] = 1.0 + clip.x;
    gl_ClipDistance[1] = 1.0 - clip.x;
    gl_ClipDistance[2] = 1.0 + clip.y;
    gl_ClipDistance[3] = 1.0 - clip.y;
    vec4 rect = lights[tile].tile;  // corner and size in atlas uv
    gl_Position = vec4((rect.xy + (0.5 * clip.xy + 0.5) * rect.zw) * 2.0 - 1.0, clip.z, 1.0);
#elif defined(ATLAS_VIEWPORT_ARRAY)
    gl_ViewportIndex = gl_InstanceID;
    gl_Position = clip;
#else
    gl_Position = clip;
#endif
}
