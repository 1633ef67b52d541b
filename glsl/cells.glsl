// The per-light record of the shadow atlas, shared by every stage that draws or shades with the
// lights (engine/render/lights.h's LightRecord is its C++ twin). Binding and MAX_LIGHTS come from
// engine/render/shader_interface.h.

// One directional cell of the environment (Barsi et al. §2): the sum over cells of
// V(x, w_i) L~_i a(dw_i, w) approximates the reflected radiance.
struct Light {
    vec4 direction;        // xyz: w_i in world space (towards the light); w: cos r_i of the chosen cap
    vec4 radiance;         // rgb: L~_i = integral of L_env over the cell; w: 1 where the neighbourhood
                           // surrounds the cell (the soft shadows' bound applies, docs/DESIGN.md §5.9)
    mat4 clip_from_world;  // orthographic along -w_i, fitted to the casters: the tile's [-1, 1]^3
    vec4 tile;             // xy: the tile's lower-left corner in atlas uv, zw: its size in atlas uv
    vec4 bias;             // x: receiver depth bias (depth units), y: normal offset (world units),
                           // zw: the cap's penumbra in tile texels (x, y) per unit of depth (docs/DESIGN.md §5.9)
    uvec4 neighbourhood[MAX_LIGHTS / 128];  // bit j % 32 of word j / 32: light j is this one or a neighbour
};

#if defined(LIGHTS_UNIFORM_BLOCK)
// A uniform block (std140 lays this struct out as std430 does): llvmpipe loads it once per loop
// iteration for all lanes; the storage block below it gathers per lane (docs/PERFORMANCE.md).
layout(std140, binding = BINDING_LIGHTS) uniform Lights { Light lights[MAX_LIGHTS]; };
#else
layout(std430, binding = BINDING_LIGHTS) readonly buffer Lights { Light lights[]; };
#endif

layout(location = LOC_LIGHT_COUNT) uniform int u_light_count;  // the records in use, lights[0 .. count)
