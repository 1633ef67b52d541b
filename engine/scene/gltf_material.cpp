#include "scene/gltf_material.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <nlohmann/json.hpp>

#include "core/error.h"

namespace envshadow {
namespace {

using nlohmann::json;

constexpr const char* kSpecularGlossiness = "KHR_materials_pbrSpecularGlossiness";

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
            if (const auto ext = m.find("extensions"); ext != m.end())
                for (const auto& [name, value] : ext->items()) {
                    if (name == kSpecularGlossiness)
                        spec_gloss = &value;
                    else if (std::find(out.ignored_extensions.begin(), out.ignored_extensions.end(), name) ==
                             out.ignored_extensions.end())
                        out.ignored_extensions.push_back(name);
                }
            // The extension, where present, takes the place of the core model (pbrMetallicRoughness is
            // then only a fallback for viewers without it).
            if (spec_gloss) {
                const std::string at = where + ".extensions." + kSpecularGlossiness;
                const json& sg = *spec_gloss;
                const glm::vec3 diffuse = unit_rgb(sg, "diffuseFactor", 4, at);
                const glm::vec3 specular = unit_rgb(sg, "specularFactor", 3, at);
                const float glossiness = unit(sg, "glossinessFactor", at);
                g.material = material_from_specular_glossiness(diffuse, specular, glossiness);
            } else {
                static const json kEmpty = json::object();
                const auto pbr_it = m.find("pbrMetallicRoughness");
                const json& pbr = pbr_it != m.end() ? *pbr_it : kEmpty;
                const std::string at = where + ".pbrMetallicRoughness";
                const glm::vec3 base = unit_rgb(pbr, "baseColorFactor", 4, at);
                g.material = material_from_metallic_roughness(base, unit(pbr, "metallicFactor", at),
                                                              unit(pbr, "roughnessFactor", at));
            }
            out.materials.push_back(std::move(g));
        }
        return out;
    }

private:
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
    // The RGB of an RGB or RGBA factor (alpha checked, then unused: no blending here).
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

Material material_from_metallic_roughness(const glm::vec3& base_color, float metallic, float roughness) {
    Material m;
    m.shininess = shininess_from_roughness(roughness);
    m.rho_d = base_color * ((1.0f - kDielectricF0) * (1.0f - metallic));
    const glm::vec3 f0 = glm::mix(glm::vec3(kDielectricF0), base_color, metallic);
    m.rho_s = lobe_rho_s(luminance(f0), m.shininess);
    return m;
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
