#pragma once
// The numbers C++ and the shaders of glsl/ share, written once: uniform locations, texture and image
// units, buffer bindings, vertex attributes, work-group and array sizes. embedded_shaders() injects
// every entry into every stage as a #define (LOC_EYE, UNIT_ATLAS, BINDING_LIGHTS, ATTRIB_POSITION,
// MAX_LIGHTS, ...); the GLSL writes `layout(location = LOC_EYE) uniform vec3 u_eye;` and C++ passes
// shader::loc::eye, so neither side holds a copy. tests/render/shader_interface_test.cpp checks every
// active uniform of every program against this table.
#include <span>
#include <string>
#include <vector>

#include "env/cells.h"
#include "env/compact_sources.h"
#include "env/ggx_prefilter.h"

namespace envshadow::render::shader {

// X(kind, name, value). Kinds and their #define:
//   loc      LOC_<NAME>, the explicit location of uniform u_<name> (per program: programs that use
//            the same name agree on it, different names may share a number);
//   unit     UNIT_<NAME>, the texture unit of sampler u_<name>;
//   image    IMAGE_<NAME>, the image unit of image u_<name>;
//   binding  BINDING_<NAME>, a shader storage or uniform block's binding point;
//   attrib   ATTRIB_<NAME>, a vertex attribute (render/gpu_mesh.h);
//   size     <NAME>, a count the shaders size arrays or work groups by.
#define ENVSHADOW_SHADER_INTERFACE(X)                                                                  \
    /* shadow_atlas.vert */                                                                            \
    X(loc, world_from_object, 0) /* also shade.vert */                                                 \
    X(loc, first_tile, 4)                                                                              \
    /* shade.vert, shade.frag */                                                                       \
    X(loc, world_normal_from_object, 4)                                                                \
    X(loc, clip_from_world, 8)                                                                         \
    X(loc, eye, 12)                                                                                    \
    X(loc, light_count, 13) /* also shadow_tiles.comp */                                               \
    X(loc, atlas_texel, 14)                                                                            \
    X(loc, k_d, 15)                                                                                    \
    X(loc, k_s, 16)                                                                                    \
    X(loc, shininess, 17)                                                                              \
    X(loc, tiles_x, 18)                                                                                \
    X(loc, unshadowed, 19)                                                                             \
    X(loc, env_from_world, 20)  /* SHADING_RATIO: world to map directions (mat3: 20-22) */             \
    X(loc, specular_weight, 23) /* SHADING_RATIO: weight of u_specular_upper, linear in log n */       \
    X(loc, slope_bias, 24)      /* RenderSettings::slope_bias, of the receiver-plane depth bias */     \
    X(loc, fraction_scale, 25)  /* SHADOWED_FRACTION_IN: fraction texels per pixel */                  \
    /* METALLIC_ROUGHNESS: glTF's BRDF (glsl/shade_metallic_roughness.glsl) */                         \
    X(loc, pixel_footprint, 26) /* widen mirror-like lobes by the pixel (with MSAA) */                 \
    X(loc, base_color_factor, 27)                                                                      \
    X(loc, metallic, 28)                                                                               \
    X(loc, roughness, 29)                                                                              \
    X(loc, sample_quarters, 30) /* each quarter of the pixel: its MSAA samples (bits) */               \
    X(loc, upper_only, 31)      /* the levels' hemisphere is the upper one */                          \
    X(loc, emission, 32)        /* shade.frag: Material::emission (times u_emission_texture) */        \
    /* alpha_mask.glsl: shade.frag ALPHA_TEST, depth_prepass.frag, shadow_atlas_mask.frag */           \
    X(loc, base_alpha, 33)                                                                             \
    X(loc, alpha_cutoff, 34)        /* 0: nothing cut out */                                           \
    X(loc, alpha_to_coverage, 35)   /* depth_prepass.frag ALPHA_MASK at MSAA */                        \
    X(loc, occlusion_strength, 36)  /* shade.frag: Material::occlusion_strength */                     \
    X(loc, compact_light_count, 37) /* METALLIC_ROUGHNESS: env/compact_sources.h, their count */       \
    X(loc, ggx_levels, 39)          /* METALLIC_ROUGHNESS: each GGX level's rows (ivec3, 39-54) */     \
    X(loc, normal_scale, 55)        /* shade.frag: Material::normal_scale, 0 without a normal map */   \
    X(loc, compact_directions, 56)  /* world direction, cos radius (vec4[4]: 56-59) */                 \
    X(loc, compact_radiances, 60)   /* integral of L dw (vec4[4]: 60-63) */                            \
    X(loc, sun_cell, 64)            /* SUN_PER_PIXEL: the sun's cell (sun_light), -1: none */          \
    X(loc, footprint_shift, 65)     /* pixel_footprint.glsl: the frame's CameraView::jitter */         \
    /* background.frag */                                                                              \
    X(loc, direction_from_clip, 0)                                                                     \
    X(loc, map_from_world, 4)                                                                          \
    /* shadow_tiles.comp */                                                                            \
    X(loc, world_from_clip, 0)                                                                         \
    X(loc, pad, 5)                                                                                     \
    X(loc, caster_count, 6)                                                                            \
    /* fs_sampler.geom, fs_lights.comp, fs_cell_assign.comp, fs_cell_integrate.comp */                 \
    X(loc, expected_samples, 0)                                                                        \
    X(loc, capacity, 1)                                                                                \
    X(loc, weights, 2)                                                                                 \
    X(loc, world_from_map, 0)                                                                          \
    X(loc, radiance_scale, 1)                                                                          \
    X(loc, scan_rows, 3)           /* fs_sampler.geom, fs_cell_*: all, or those above the horizon */   \
    X(loc, sampled_solid_angle, 2) /* fs_lights.comp: 4 pi, or 2 pi for the upper hemisphere */        \
    X(loc, upper_hemisphere, 0)    /* fs_importance.comp */                                            \
    /* present.frag */                                                                                 \
    X(loc, exposure_scale, 0)                                                                          \
    /* texture units */                                                                                \
    X(unit, atlas, 0)          /* shade.frag (depth compare), atlas_preview.frag */                    \
    X(unit, environment, 1)    /* background.frag, fs_importance.comp */                               \
    X(unit, depth, 2)          /* shadow_tiles.comp: the image's depth after the pre-pass */           \
    X(unit, importance, 0)     /* fs_sampler.geom */                                                   \
    X(unit, radiance, 0)       /* fs_lights.comp, fs_cell_assign.comp, fs_cell_integrate.comp */       \
    X(unit, moments, 1)        /* fs_lights.comp, fs_cell_integrate.comp */                            \
    X(unit, linear, 0)         /* present.frag */                                                      \
    X(unit, irradiance, 3)     /* shade.frag SHADING_RATIO: env/prefilter.h level 0 (n = 1) */         \
    X(unit, specular_lower, 4) /* shade.frag SHADING_RATIO: the two levels about n */                  \
    X(unit, specular_upper, 5)                                                                         \
    X(unit, atlas_depth, 6) /* shade.frag SOFT_SHADOWS: the atlas as depths (blocker search) */        \
    X(unit, base_color, 7)  /* shade.frag, masked casters: base-colour texture (white without one) */  \
    /* shade.frag SHADOWED_FRACTION_IN, fraction_filter.frag: the fraction and 1/w, normals */         \
    X(unit, fraction, 8)                                                                               \
    X(unit, fraction_normal, 9)                                                                        \
    X(unit, fraction_sun, 1)       /* SUN_PER_PIXEL: the sun's share and visibility */                 \
    X(unit, dfg, 10)               /* shade.frag METALLIC_ROUGHNESS: env/dfg_table.h's table */        \
    X(unit, emission_texture, 11)  /* shade.frag: the material's emission (white without one) */       \
    X(unit, occlusion_texture, 12) /* shade.frag: the material's occlusion (R, linear; white) */       \
    /* shade.frag METALLIC_ROUGHNESS: the GGX levels in one texture, the map itself, and the */        \
    /* material's metallic (B) and roughness (G), linear, white without one */                         \
    X(unit, ggx_level_texels, 13)                                                                      \
    X(unit, ggx_mirror, 4)                                                                             \
    X(unit, metallic_roughness_texture, 14)                                                            \
    X(unit, normal_texture, 15) /* shade.frag: the material's normal map (linear) */                   \
    /* shade.frag TRANSLUCENT_SHADOWS: the atlas's translucent layer, on units free in shade.frag */   \
    X(unit, atlas_transmittance, 0)                                                                    \
    X(unit, atlas_translucent_depth, 2)                                                                \
    /* image units (fs_importance.comp) */                                                             \
    X(image, importance, 0)                                                                            \
    X(image, radiance, 1)                                                                              \
    X(image, moments, 2)                                                                               \
    /* buffer bindings */                                                                              \
    X(binding, lights, 0)       /* cells.glsl: uniform or storage block of LightRecord */              \
    X(binding, tile_lists, 1)   /* shadow_tiles.comp writes, shade.frag reads */                       \
    X(binding, caster_rects, 3) /* shadow_tiles.comp */                                                \
    X(binding, atlas_tiles, 5)  /* shadow_atlas.vert ATLAS_CLIP_DISTANCES: instance to tile */         \
    X(binding, fs_row_sums, 0)  /* fs_importance.comp writes, fs_sampler.geom reads */                 \
    X(binding, fs_counts, 1)    /* fs_sampler.geom writes, fs_lights.comp reads */                     \
    X(binding, fs_samples, 0)   /* fs_lights.comp (transform feedback of fs_sampler.geom) */           \
    X(binding, fs_lights, 2)    /* fs_lights.comp writes, fs_cell_integrate.comp rewrites */           \
    X(binding, fs_sites, 3)     /* fs_lights.comp writes the map directions, fs_cell_*.comp read */    \
    X(binding, fs_nearest, 4)   /* fs_cell_assign.comp: each importance texel's nearest light */       \
    /* vertex attributes */                                                                            \
    X(attrib, position, 0)                                                                             \
    X(attrib, normal, 1)                                                                               \
    X(attrib, texcoord, 2) /* unset (0, 0) on meshes without texture coordinates */                    \
    X(attrib, tangent, 3)  /* unset (0, 0, 0, 1) on meshes without tangents */                         \
    /* sizes */                                                                                        \
    X(size, max_lights, kMaxLights) /* light records the uniform block and the tile lists hold */      \
    X(size, screen_tile, 16)        /* pixels: shadow_tiles.comp's work group, shade.frag's tile */    \
    X(size, fs_work_group, 64)      /* fs_importance, fs_lights, fs_cell_* (a power of two) */         \
    X(size, fs_scan_run, 16)        /* fs_sampler.geom's unrolled run: the width must be a multiple */ \
    X(size, fs_texel_bits, 21)      /* a packed sample: texel index bits, multiplicity above them */   \
    /* the GGX levels (env/ggx_prefilter.h) */                                                         \
    X(size, ggx_prefilter_levels, kGgxPrefilterLevels)                                                 \
    X(size, max_compact_sources, kMaxCompactSources)

#define ENVSHADOW_SHADER_CONSTANT(kind, name, value) \
    namespace kind {                                 \
    inline constexpr int name = value;               \
    }
ENVSHADOW_SHADER_INTERFACE(ENVSHADOW_SHADER_CONSTANT)
#undef ENVSHADOW_SHADER_CONSTANT

// A captured Floyd-Steinberg sample is one uint: the texel index in the low fs_texel_bits, the
// multiplicity above (glsl/fs_common.glsl fs_pack_sample).
inline constexpr int kFsMaxTexels = 1 << size::fs_texel_bits;
inline constexpr int kFsMaxMultiplicity = (1 << (32 - size::fs_texel_bits)) - 1;

struct Constant {
    const char* kind;  // "loc", "unit", "image", "binding", "attrib" or "size"
    const char* name;  // as in C++: "world_from_object"
    int value;
    std::string define_name() const;  // "LOC_WORLD_FROM_OBJECT"; a size: "MAX_LIGHTS"
};

// The table, in its order.
std::span<const Constant> constants();

// "NAME VALUE" for every entry: gl::ShaderLibrary::define takes them.
std::vector<std::string> defines();

}  // namespace envshadow::render::shader
