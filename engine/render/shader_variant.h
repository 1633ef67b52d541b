#pragma once
// Which programs the renderer draws with (as Filament's Variant): everything a program's source depends
// on, computed from the settings and what the context supports by one function. Two settings with the
// same key draw with the same programs, so the renderer builds the programs of a key once and keeps them
// (Renderer::set_settings). GL-free.
#include <compare>
#include <string>
#include <vector>

#include "render/render_settings.h"

namespace envshadow::render {

// What the context offers that a variant may need.
struct ShaderSupport {
    bool viewport_layer_array = false;  // GL_ARB_shader_viewport_layer_array: AtlasMode::viewport_array
    bool uniform_block_fits = false;    // GL_MAX_UNIFORM_BLOCK_SIZE holds shader::size::max_lights records
};

struct ShaderVariant {
    AtlasMode atlas = AtlasMode::clip_distances;  // as drawn: viewport_array needs the extension
    bool lights_uniform_block = false;            // LIGHTS_UNIFORM_BLOCK, in every program that reads lights
    bool diffuse_cap = false;                     // DIFFUSE_CAP
    bool specular_single = false;                 // SPECULAR_SINGLE
    bool pcf_wide = false;                        // PCF_WIDE
    bool tile_lists = false;                      // SHADOW_TILE_LISTS (uses_tile_lists)
    bool ratio = false;                           // SHADING_RATIO
    bool soft_shadows = false;                    // SOFT_SHADOWS
    bool fraction_pass = false;                   // SHADOWED_FRACTION_OUT: ratio at a reduced shadow rate
    bool sun_per_pixel = false;                   // SUN_PER_PIXEL: with the fraction at ShadowRate::half
    bool alpha_test = false;  // ALPHA_TEST: no depth pre-pass, so shade.frag cuts masked surfaces out itself
    // TRANSLUCENT_SHADOWS: the scene has blended casters, in the atlas's translucent layer (the renderer sets it
    // from the frame, not from the settings).
    bool translucent_shadows = false;

    auto operator<=>(const ShaderVariant&) const = default;
};

// The one place that turns settings into a variant.
ShaderVariant shader_variant(const RenderSettings& settings, const ShaderSupport& support);

// The defines of glsl/shadow_atlas.vert, and of glsl/shade.frag (whose diffuse-only and flat-receiver
// programs add DIFFUSE_ONLY and FLAT_RECEIVER), for `variant`. With fraction_pass these are the programs
// of the shadowed-fraction pass; the shading then draws with one program for every variant
// (SHADOWED_FRACTION_IN, Renderer's fraction_shading_program()), or with sun_per_pixel one per variant.
std::vector<std::string> atlas_defines(const ShaderVariant& variant);
std::vector<std::string> shade_defines(const ShaderVariant& variant);

}  // namespace envshadow::render
