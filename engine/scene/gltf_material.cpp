#include "scene/gltf_material.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <nlohmann/json.hpp>

#include "core/error.h"

namespace envshadow {
namespace {

using nlohmann::json;

constexpr const char* kSpecularGlossiness = "KHR_materials_pbrSpecularGlossiness";
constexpr const char* kEmissiveStrength = "KHR_materials_emissive_strength";

// rho_s that makes the paper's lobe reflect `albedo` at normal incidence (its albedo there is
// rho_s (n + 2) / (n + 1), docs/DESIGN.md §2).
float lobe_rho_s(float albedo, float shininess) {
    return float(double(albedo) * (double(shininess) + 1.0) / (double(shininess) + 2.0));
}

class MaterialReader {
public:
    explicit MaterialReader(const std::filesystem::path& file) : file_(file) {}

    GltfMaterials read(const json& document) {
        GltfMaterials out;
        const auto materials = document.find("materials");
        if (materials == document.end()) return out;
        for (std::size_t i = 0; i < materials->size(); ++i) {
            const json& m = (*materials)[i];
            const std::string where = "materials[" + std::to_string(i) + "]";
            GltfMaterial g;
            g.name = m.contains("name") ? m["name"].get<std::string>() : "material " + std::to_string(i);
            const json* spec_gloss = nullptr;
            const json* emissive_strength = nullptr;
            if (const auto ext = m.find("extensions"); ext != m.end())
                for (const auto& [name, value] : ext->items()) {
                    if (name == kSpecularGlossiness)
                        spec_gloss = &value;
                    else if (name == kEmissiveStrength)
                        emissive_strength = &value;
                    else if (std::find(out.ignored_extensions.begin(), out.ignored_extensions.end(), name) ==
                             out.ignored_extensions.end())
                        out.ignored_extensions.push_back(name);
                }
            float base_alpha = 1.0f;
            // The extension, where present, takes the place of the core model (pbrMetallicRoughness is
            // then only a fallback for viewers without it).
            if (spec_gloss) {
                const std::string at = where + ".extensions." + kSpecularGlossiness;
                const json& sg = *spec_gloss;
                const glm::vec3 diffuse = unit_rgb(sg, "diffuseFactor", 4, at);
                base_alpha = unit_alpha(sg, "diffuseFactor", at);
                const glm::vec3 specular = unit_rgb(sg, "specularFactor", 3, at);
                const float glossiness = unit(sg, "glossinessFactor", at);
                g.material = material_from_specular_glossiness(diffuse, specular, glossiness);
                g.base_color = texture_ref(sg, "diffuseTexture", at);
            } else {
                static const json kEmpty = json::object();
                const auto pbr_it = m.find("pbrMetallicRoughness");
                const json& pbr = pbr_it != m.end() ? *pbr_it : kEmpty;
                const std::string at = where + ".pbrMetallicRoughness";
                const glm::vec3 base = unit_rgb(pbr, "baseColorFactor", 4, at);
                base_alpha = unit_alpha(pbr, "baseColorFactor", at);
                g.material = material_from_metallic_roughness(
                    MetallicRoughness{base, unit(pbr, "metallicFactor", at), unit(pbr, "roughnessFactor", at)});
                g.base_color = texture_ref(pbr, "baseColorTexture", at);
                g.metallic_roughness = texture_ref(pbr, "metallicRoughnessTexture", at);
            }
            // Emission: emissiveFactor (default black) times the extension's emissiveStrength (default 1).
            if (m.contains("emissiveFactor")) {
                float strength = 1.0f;
                if (emissive_strength) {
                    const std::string at = where + ".extensions." + kEmissiveStrength;
                    if (!emissive_strength->is_object()) fail(at, "expected an object");
                    strength = number(*emissive_strength, "emissiveStrength", at, 1.0f);
                    if (strength < 0.0f) fail(at + ".emissiveStrength", "must not be negative");
                }
                g.material.emission = unit_rgb(m, "emissiveFactor", 3, where) * strength;
            }
            g.emission = texture_ref(m, "emissiveTexture", where);
            g.occlusion = texture_ref(m, "occlusionTexture", where);
            if (g.occlusion)
                g.material.occlusion_strength = unit(m.at("occlusionTexture"), "strength", where + ".occlusionTexture");
            g.normal = texture_ref(m, "normalTexture", where);
            if (g.normal)
                g.material.normal_scale = number(m.at("normalTexture"), "scale", where + ".normalTexture", 1.0f);
            read_alpha(m, where, base_alpha, g.material);
            g.material.double_sided = m.value("doubleSided", false);  // type-checked by check_gltf_json
            out.materials.push_back(std::move(g));
        }
        return out;
    }

private:
    // alphaMode and alphaCutoff (docs/SCENES.md "Alpha"); BLEND ignores the cutoff, as the specification says.
    void read_alpha(const json& m, const std::string& where, float base_alpha, Material& material) const {
        material.base_alpha = base_alpha;
        const std::string mode = m.value("alphaMode", std::string("OPAQUE"));
        if (mode == "OPAQUE") return;
        if (mode != "MASK" && mode != "BLEND")
            fail(where + ".alphaMode", "\"" + mode + "\" is not OPAQUE, MASK or BLEND");
        if (mode == "BLEND") {
            material.alpha_mode = AlphaMode::blend;
            return;
        }
        material.alpha_mode = AlphaMode::mask;
        material.alpha_cutoff = number(m, "alphaCutoff", where, 0.5f);
        if (material.alpha_cutoff < 0.0f) fail(where + ".alphaCutoff", "must not be negative");
    }

    [[noreturn]] void fail(const std::string& where, const std::string& reason) const {
        throw InputError(file_.string() + ": " + where + ": " + reason);
    }

    // A number in [0, 1] as the schema bounds it (JSON has no NaN, so only the range can be wrong);
    // 1 where absent, the default of every factor read here.
    float unit_value(const json& value, const std::string& where) const {
        if (!value.is_number()) fail(where, "expected a number");
        const double x = value.get<double>();
        if (!(x >= 0.0 && x <= 1.0)) fail(where, value.dump() + " is outside 0 … 1 (the glTF range of this factor)");
        return float(x);
    }
    float unit(const json& object, const char* key, const std::string& where) const {
        const auto it = object.find(key);
        return it == object.end() ? 1.0f : unit_value(*it, where + "." + key);
    }
    // The alpha of an RGBA factor (checked by unit_rgb), 1 where absent.
    float unit_alpha(const json& object, const char* key, const std::string& where) const {
        const auto it = object.find(key);
        return it == object.end() || !it->is_array() || it->size() != 4
                   ? 1.0f
                   : unit_value((*it)[3], where + "." + key + "[3]");
    }
    // The RGB of an RGB or RGBA factor (alpha checked; unit_alpha reads it).
    glm::vec3 unit_rgb(const json& object, const char* key, std::size_t length, const std::string& where) const {
        const auto it = object.find(key);
        if (it == object.end()) return glm::vec3(1.0f);
        const std::string at = where + "." + key;
        if (!it->is_array() || it->size() != length) fail(at, "expected " + std::to_string(length) + " numbers");
        glm::vec3 rgb;
        for (std::size_t k = 0; k < length; ++k) {
            const float x = unit_value((*it)[k], at + "[" + std::to_string(k) + "]");
            if (k < 3) rgb[int(k)] = x;
        }
        return rgb;
    }

    // A textureInfo: its index and texCoord (type-checked here: the extension's objects are not in the
    // core schema check) and KHR_texture_transform, whose texCoord overrides the core one.
    std::optional<GltfTextureRef> texture_ref(const json& object, const char* key, const std::string& where) const {
        const auto it = object.find(key);
        if (it == object.end()) return std::nullopt;
        const std::string at = where + "." + key;
        if (!it->is_object()) fail(at, "expected an object");
        GltfTextureRef ref;
        ref.texture = index(*it, "index", at, true);
        ref.texcoord = index(*it, "texCoord", at, false);
        if (const auto ext = it->find("extensions"); ext != it->end() && ext->is_object())
            if (const auto t = ext->find("KHR_texture_transform"); t != ext->end()) {
                const std::string tat = at + ".extensions.KHR_texture_transform";
                if (!t->is_object()) fail(tat, "expected an object");
                const glm::vec2 offset = pair(*t, "offset", tat, glm::vec2(0.0f));
                const glm::vec2 scale = pair(*t, "scale", tat, glm::vec2(1.0f));
                const float rotation = number(*t, "rotation", tat, 0.0f);
                if (t->contains("texCoord")) ref.texcoord = index(*t, "texCoord", tat, false);
                // The extension's T * R * S (column-major): a counter-clockwise turn of the uvs, whose v
                // axis points down the image.
                const float c = std::cos(rotation), s = std::sin(rotation);
                const glm::mat3 translation(1, 0, 0, 0, 1, 0, offset.x, offset.y, 1);
                const glm::mat3 turn(c, -s, 0, s, c, 0, 0, 0, 1);
                const glm::mat3 scaling(scale.x, 0, 0, 0, scale.y, 0, 0, 0, 1);
                ref.uv_transform = translation * turn * scaling;
            }
        return ref;
    }
    int index(const json& object, const char* key, const std::string& where, bool required) const {
        const auto it = object.find(key);
        if (it == object.end()) {
            if (required) fail(where, std::string("has no \"") + key + "\"");
            return 0;
        }
        if (!it->is_number_integer() || it->get<long long>() < 0 || it->get<long long>() > 1'000'000)
            fail(where + "." + key, "expected a non-negative integer");
        return int(it->get<long long>());
    }
    float number(const json& object, const char* key, const std::string& where, float fallback) const {
        const auto it = object.find(key);
        if (it == object.end()) return fallback;
        if (!it->is_number() || !std::isfinite(it->get<double>()) || std::abs(it->get<double>()) > 1e6)
            fail(where + "." + key, "expected a number of magnitude at most 1e6");
        return float(it->get<double>());
    }
    glm::vec2 pair(const json& object, const char* key, const std::string& where, glm::vec2 fallback) const {
        const auto it = object.find(key);
        if (it == object.end()) return fallback;
        const std::string at = where + "." + key;
        if (!it->is_array() || it->size() != 2) fail(at, "expected 2 numbers");
        glm::vec2 v;
        for (int k = 0; k < 2; ++k) {
            const json& x = (*it)[std::size_t(k)];
            if (!x.is_number() || std::abs(x.get<double>()) > 1e6)
                fail(at + "[" + std::to_string(k) + "]", "expected a number of magnitude at most 1e6");
            v[k] = float(x.get<double>());
        }
        return v;
    }

    const std::filesystem::path& file_;
};

}  // namespace

float luminance(const glm::vec3& rgb) {
    return 0.2126f * rgb.r + 0.7152f * rgb.g + 0.0722f * rgb.b;
}

float shininess_from_roughness(float roughness) {
    const double alpha = double(roughness) * double(roughness);
    const double alpha2 = alpha * alpha;
    // 2 / alpha^2 - 2 >= max exactly when alpha^2 <= 2 / (max + 2): also covers roughness 0.
    if (!(alpha2 > 2.0 / (double(kGltfMaxShininess) + 2.0))) return kGltfMaxShininess;
    return float(std::clamp(2.0 / alpha2 - 2.0, double(kGltfMinShininess), double(kGltfMaxShininess)));
}

Material material_from_metallic_roughness(const MetallicRoughness& parameters) {
    const auto& [base_color, metallic, roughness] = parameters;
    Material m;
    m.metallic_roughness = parameters;
    m.shininess = shininess_from_roughness(roughness);
    m.rho_d = base_color * ((1.0f - kDielectricF0) * (1.0f - metallic));
    const glm::vec3 f0 = glm::mix(glm::vec3(kDielectricF0), base_color, metallic);
    m.rho_s = lobe_rho_s(luminance(f0), m.shininess);
    return m;
}

Material with_metallic_roughness(Material material, const MetallicRoughness& parameters) {
    const Material brdf = material_from_metallic_roughness(parameters);
    material.rho_d = brdf.rho_d;
    material.rho_s = brdf.rho_s;
    material.shininess = brdf.shininess;
    material.metallic_roughness = brdf.metallic_roughness;
    return material;
}

Material material_from_specular_glossiness(const glm::vec3& diffuse, const glm::vec3& specular, float glossiness) {
    Material m;
    m.shininess = shininess_from_roughness(1.0f - glossiness);
    m.rho_d = diffuse * (1.0f - std::max({specular.r, specular.g, specular.b}));
    m.rho_s = lobe_rho_s(luminance(specular), m.shininess);
    return m;
}

GltfMaterials read_gltf_materials(const std::filesystem::path& file, const nlohmann::json& document) {
    return MaterialReader(file).read(document);
}

}  // namespace envshadow
