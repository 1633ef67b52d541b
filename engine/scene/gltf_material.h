#pragma once
// glTF 2.0 materials mapped onto the paper's modified Phong BRDF (docs/DESIGN.md §2; the mapping and its
// limits: docs/SCENES.md "Materials from glTF"). Factors, and which texture gives the base colour.
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>
#include <nlohmann/json_fwd.hpp>

#include "scene/scene.h"

namespace envshadow {

// The shininess range both shading modes and the reference agree on: the ratio mode's prefiltered
// levels span n = 1 … 10^4 (kPrefilterMinShininess/kPrefilterMaxShininess in engine/env/prefilter.h,
// a layer this one may not include; tests/scene/gltf_material_test.cpp holds the two equal).
inline constexpr float kGltfMinShininess = 1.0f;
inline constexpr float kGltfMaxShininess = 10000.0f;

// Reflectance of a dielectric at normal incidence (glTF 2.0, Appendix B: "dielectricSpecular").
inline constexpr float kDielectricF0 = 0.04f;

// Rec. 709 luminance (the renderer works in linear Rec. 709 / sRGB primaries): how an RGB F0 becomes
// the scalar rho_s.
float luminance(const glm::vec3& rgb);

// n = 2 / alpha^2 - 2 with alpha = roughness^2 (Walter et al. 2007: the Blinn-Phong exponent of a
// Beckmann width alpha; the paper's lobe is about the mirror direction, so its highlight comes out
// narrower than a glTF viewer's: docs/SCENES.md), clamped to [kGltfMinShininess, kGltfMaxShininess].
// roughness in [0, 1].
float shininess_from_roughness(float roughness);

// Metallic-roughness (glTF 2.0 core, Appendix B):
//   rho_d = baseColor (1 - 0.04) (1 - metallic),   F0 = mix(0.04, baseColor, metallic),
//   n from roughness,   rho_s = luminance(F0) (n + 1) / (n + 2),
// the last factor making the lobe's albedo at normal incidence, rho_s (n + 2) / (n + 1) (docs/DESIGN.md
// §2), equal to luminance(F0). Then rho_d + specular albedo <= 1 in every channel. The material keeps the
// parameters themselves too (Material::metallic_roughness).
Material material_from_metallic_roughness(const MetallicRoughness& parameters);
// `material` with its BRDF (rho_d, rho_s, shininess, metallic_roughness) from `parameters`; its textures,
// emission, occlusion and alpha kept: an edit of the factors (the scene file's keys, the viewer's sliders).
Material with_metallic_roughness(Material material, const MetallicRoughness& parameters);

// KHR_materials_pbrSpecularGlossiness: rho_d = diffuse (1 - max(specular)) (the extension's c_diff),
// roughness = 1 - glossiness, rho_s = luminance(specular) (n + 1) / (n + 2).
Material material_from_specular_glossiness(const glm::vec3& diffuse, const glm::vec3& specular, float glossiness);

// A material's textureInfo (baseColorTexture or the extension's diffuseTexture, metallicRoughnessTexture,
// emissiveTexture, occlusionTexture, normalTexture): the texture, its TEXCOORD set and KHR_texture_transform as the
// affine map uv' = (uv_transform * vec3(uv, 1)).xy.
struct GltfTextureRef {
    int texture = -1;  // index into the file's "textures" (checked by load_gltf)
    int texcoord = 0;  // TEXCOORD_<texcoord>
    glm::mat3 uv_transform{1.0f};
};

struct GltfMaterial {
    Material material;  // the textures unset (occlusion_strength set): load_gltf resolves the refs below
    std::string name;   // the glTF material's name, or "material <index>" without one
    std::optional<GltfTextureRef> base_color;
    std::optional<GltfTextureRef> metallic_roughness;  // metallicRoughnessTexture
    std::optional<GltfTextureRef> emission;            // emissiveTexture
    std::optional<GltfTextureRef> occlusion;           // occlusionTexture
    std::optional<GltfTextureRef> normal;              // normalTexture (its scale: Material::normal_scale)

    // Every reference above, the base colour's first (whose coordinates the mesh carries where it has one).
    std::array<const std::optional<GltfTextureRef>*, 5> texture_refs() const {
        return {&base_color, &metallic_roughness, &emission, &occlusion, &normal};
    }
};

struct GltfMaterials {
    std::vector<GltfMaterial> materials;  // one per entry of the file's "materials"
    // Material extensions present but not mapped (KHR_materials_clearcoat, ...), each named once in
    // order of appearance; load_gltf warns about them.
    std::vector<std::string> ignored_extensions;
};

// Maps document["materials"] (already type-checked by check_gltf_json), with emissiveFactor and
// KHR_materials_emissive_strength into Material::emission, occlusionTexture.strength into
// Material::occlusion_strength, normalTexture.scale into Material::normal_scale. Factors outside [0, 1], where the glTF
// schema bounds them, are an InputError "<file>: materials[i].<path>: <reason>", as are wrongly typed
// KHR_materials_pbrSpecularGlossiness properties.
GltfMaterials read_gltf_materials(const std::filesystem::path& file, const nlohmann::json& document);

}  // namespace envshadow
