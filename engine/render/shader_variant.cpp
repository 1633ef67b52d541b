#include "render/shader_variant.h"

#include "render/frame_plan.h"

namespace envshadow::render {

ShaderVariant shader_variant(const RenderSettings& settings, const ShaderSupport& support) {
    ShaderVariant variant;
    variant.atlas = settings.atlas == AtlasMode::viewport_array && !support.viewport_layer_array
                        ? AtlasMode::clip_distances
                        : settings.atlas;
    variant.lights_uniform_block = settings.lights_uniform_block && support.uniform_block_fits;
    variant.diffuse_cap = settings.diffuse == DiffuseMode::cap;
    variant.specular_single = settings.specular == SpecularMode::single;
    variant.pcf_wide = settings.pcf == PcfKernel::wide;
    variant.tile_lists = uses_tile_lists(settings);
    variant.ratio = settings.shading == ShadingMode::ratio;
    variant.soft_shadows = settings.shadows == ShadowMode::soft;
    variant.fraction_pass = variant.ratio && settings.shadow_rate != ShadowRate::fragment;
    variant.sun_per_pixel = variant.fraction_pass && settings.shadow_rate == ShadowRate::half && settings.sun_per_pixel;
    variant.alpha_test = !settings.depth_prepass;
    return variant;
}

std::vector<std::string> atlas_defines(const ShaderVariant& variant) {
    std::vector<std::string> defines;
    if (variant.lights_uniform_block) defines.push_back("LIGHTS_UNIFORM_BLOCK");
    if (variant.atlas == AtlasMode::clip_distances) defines.push_back("ATLAS_CLIP_DISTANCES");
    if (variant.atlas == AtlasMode::viewport_array) defines.push_back("ATLAS_VIEWPORT_ARRAY");
    return defines;
}

std::vector<std::string> shade_defines(const ShaderVariant& variant) {
    std::vector<std::string> defines;
    if (variant.lights_uniform_block) defines.push_back("LIGHTS_UNIFORM_BLOCK");
    if (variant.diffuse_cap) defines.push_back("DIFFUSE_CAP");
    if (variant.specular_single) defines.push_back("SPECULAR_SINGLE");
    if (variant.pcf_wide) defines.push_back("PCF_WIDE");
    if (variant.tile_lists) defines.push_back("SHADOW_TILE_LISTS");
    if (variant.ratio) defines.push_back("SHADING_RATIO");
    if (variant.soft_shadows) defines.push_back("SOFT_SHADOWS");
    if (variant.fraction_pass) defines.push_back("SHADOWED_FRACTION_OUT");
    if (variant.sun_per_pixel) defines.push_back("SUN_PER_PIXEL");
    if (variant.alpha_test) defines.push_back("ALPHA_TEST");
    if (variant.translucent_shadows) defines.push_back("TRANSLUCENT_SHADOWS");
    return defines;
}

}  // namespace envshadow::render
