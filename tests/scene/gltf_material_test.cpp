// glTF materials mapped onto the paper's BRDF, one part per material (scene/gltf_material.h). The
// expected values are worked out by hand in the comments from the formulas of docs/SCENES.md.
#include "scene/gltf_material.h"

#include <cmath>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "env/prefilter.h"
#include "gltf_writer.h"
#include "scene/gltf.h"

namespace envshadow {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::GltfWriter;
using test::test_folder;

const fs::path& kModels = test::kAssimpModels;

static_assert(kGltfMinShininess == kPrefilterMinShininess && kGltfMaxShininess == kPrefilterMaxShininess,
              "the glTF mapping clamps n to the ratio mode's prefiltered range");

void expect_material(const Material& m, const glm::vec3& rho_d, float rho_s, float shininess) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(m.rho_d[c], rho_d[c], 1e-6f) << "rho_d channel " << c;
    EXPECT_NEAR(m.rho_s, rho_s, 1e-6f);
    EXPECT_NEAR(m.shininess, shininess, 1e-4f * shininess);
}

// The error is one line "<file>: <reason>" and the reason mentions `expected`.
void expect_input_error(const fs::path& file, const std::string& expected) {
    test::expect_one_line_error(file, expected, load_gltf);
}

// One mesh of two triangle primitives: the first at x in [0, 1] with material 0, the second at x in
// [5, 6] with material 1 (materials to be filled in by the test).
GltfWriter two_primitives(int first_material = 0, int second_material = 1) {
    GltfWriter w;
    const int mesh = w.mesh(w.vec3s({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
    json second = w.doc["meshes"][mesh]["primitives"][0];
    second["attributes"]["POSITION"] = w.vec3s({{5, 0, 0}, {6, 0, 0}, {5, 1, 0}});
    if (first_material >= 0) w.doc["meshes"][mesh]["primitives"][0]["material"] = first_material;
    if (second_material >= 0) second["material"] = second_material;
    w.doc["meshes"][mesh]["primitives"].push_back(second);
    w.scene({w.node({{"mesh", mesh}})});
    return w;
}

json metallic_roughness(const glm::vec3& base, double metallic, double roughness, const std::string& name) {
    return {{"name", name},
            {"pbrMetallicRoughness",
             {{"baseColorFactor", {base.r, base.g, base.b, 1.0}},
              {"metallicFactor", metallic},
              {"roughnessFactor", roughness}}}};
}

TEST(GltfMaterial, ShininessFromRoughness) {
    // alpha = r^2, n = 2 / alpha^2 - 2.
    EXPECT_NEAR(shininess_from_roughness(0.5f), 30.0f, 1e-4f);                  // alpha 0.25: 2 / 0.0625 - 2
    EXPECT_NEAR(shininess_from_roughness(0.6f), 2.0f / 0.1296f - 2.0f, 1e-3f);  // alpha 0.36
    EXPECT_EQ(shininess_from_roughness(1.0f), kGltfMinShininess);               // 0, clamped up to 1
    EXPECT_EQ(shininess_from_roughness(0.95f), kGltfMinShininess);              // alpha^2 = 0.8145: 0.46 < 1
    EXPECT_NEAR(shininess_from_roughness(0.9f), 2.0f / 0.6561f - 2.0f, 1e-4f);  // alpha^2 = 0.6561: 1.048
    EXPECT_EQ(shininess_from_roughness(0.1f), kGltfMaxShininess);               // 19998, clamped to 10^4
    EXPECT_EQ(shininess_from_roughness(0.0f), kGltfMaxShininess);               // a mirror
    // Monotone: rougher is never shinier.
    float previous = shininess_from_roughness(0.0f);
    for (int i = 1; i <= 100; ++i) {
        const float n = shininess_from_roughness(float(i) / 100.0f);
        EXPECT_LE(n, previous) << i;
        previous = n;
    }
}

TEST(GltfMaterial, TwoPrimitivesGetTheirOwnMappedMaterials) {
    GltfWriter w = two_primitives();
    w.doc["materials"] = json::array({metallic_roughness({0.8f, 0.4f, 0.2f}, 0.0, 0.5, "clay"),
                                      metallic_roughness({0.9f, 0.6f, 0.3f}, 1.0, 0.3, "brass")});
    const GltfModel model = load_gltf(w.write(test_folder(), "two"));
    ASSERT_EQ(model.parts.size(), 2u);
    EXPECT_EQ(model.triangle_count(), 2u);

    // clay, a dielectric: rho_d = 0.96 base; F0 = 0.04; n = 30; rho_s = 0.04 * 31 / 32 = 0.03875.
    const GltfPart& clay = model.parts[0];
    EXPECT_EQ(clay.name, "clay");
    EXPECT_EQ(clay.mesh->bounds_max.x, 1.0f) << "the first primitive";
    expect_material(clay.material, {0.768f, 0.384f, 0.192f}, 0.03875f, 30.0f);

    // brass, a metal: rho_d = 0; F0 = base, luminance 0.2126 * 0.9 + 0.7152 * 0.6 + 0.0722 * 0.3 =
    // 0.64212; alpha = 0.09, n = 2 / 0.0081 - 2 = 244.91358; rho_s = 0.64212 * 245.91358 / 246.91358.
    const GltfPart& brass = model.parts[1];
    EXPECT_EQ(brass.name, "brass");
    EXPECT_EQ(brass.mesh->bounds_min.x, 5.0f) << "the second primitive";
    expect_material(brass.material, {0.0f, 0.0f, 0.0f}, 0.64212f * 245.91358f / 246.91358f, 244.91358f);

    EXPECT_EQ(model.bounds_min, glm::vec3(0, 0, 0));
    EXPECT_EQ(model.bounds_max, glm::vec3(6, 1, 0));
}

TEST(GltfMaterial, FullyMetallicHasNoDiffuseWhateverItsColour) {
    for (const double roughness : {0.0, 0.25, 1.0}) {
        const Material m = material_from_metallic_roughness({{1.0f, 0.5f, 0.25f}, 1.0f, float(roughness)});
        EXPECT_EQ(m.rho_d, glm::vec3(0.0f)) << roughness;
        EXPECT_GT(m.rho_s, 0.0f) << roughness;
    }
}

TEST(GltfMaterial, TheSchemaDefaultsAndPrimitivesWithoutAMaterial) {
    // materials[0] = {}: base colour 1, metallic 1, roughness 1 (the glTF defaults): a rough white
    // metal, rho_d = 0, n = 1 (clamped from 0), rho_s = 1 * 2 / 3. The second primitive has no
    // material: Material{}.
    GltfWriter w = two_primitives(0, -1);
    w.doc["materials"] = json::array({json::object()});
    const GltfModel model = load_gltf(w.write(test_folder(), "defaults"));
    ASSERT_EQ(model.parts.size(), 2u);
    EXPECT_EQ(model.parts[0].name, "material 0");
    expect_material(model.parts[0].material, {0, 0, 0}, 2.0f / 3.0f, 1.0f);
    EXPECT_EQ(model.parts[1].name, "no material");
    expect_material(model.parts[1].material, Material{}.rho_d, Material{}.rho_s, Material{}.shininess);
    EXPECT_FALSE(model.parts[0].material.double_sided);  // glTF's doubleSided defaults to false
}

TEST(GltfMaterial, DoubleSidedIsRead) {
    GltfWriter w = two_primitives(0, -1);
    w.doc["materials"] = json::array({{{"doubleSided", true}}});
    EXPECT_TRUE(load_gltf(w.write(test_folder(), "sides")).parts.at(0).material.double_sided);
}

TEST(GltfMaterial, SpecularGlossinessExtensionTakesThePlaceOfMetallicRoughness) {
    GltfWriter w = two_primitives(0, 0);
    json material = metallic_roughness({0.1f, 0.1f, 0.1f}, 0.0, 1.0, "leather");
    material["extensions"]["KHR_materials_pbrSpecularGlossiness"] = {
        {"diffuseFactor", {0.5, 0.6, 0.7, 1.0}}, {"specularFactor", {0.2, 0.1, 0.05}}, {"glossinessFactor", 0.8}};
    w.doc["materials"] = json::array({material});
    w.doc["extensionsUsed"] = {"KHR_materials_pbrSpecularGlossiness"};
    const GltfModel model = load_gltf(w.write(test_folder(), "spec_gloss"));
    ASSERT_EQ(model.parts.size(), 1u) << "one material, one part";
    EXPECT_EQ(model.triangle_count(), 2u);
    EXPECT_TRUE(model.ignored_extensions.empty());
    // rho_d = diffuse (1 - max specular) = (0.5, 0.6, 0.7) * 0.8; roughness 0.2, alpha 0.04,
    // n = 2 / 0.0016 - 2 = 1248; luminance(specular) = 0.04252 + 0.07152 + 0.00361 = 0.11765,
    // rho_s = 0.11765 * 1249 / 1250.
    expect_material(model.parts[0].material, {0.4f, 0.48f, 0.56f}, 0.11765f * 1249.0f / 1250.0f, 1248.0f);
}

TEST(GltfMaterial, MaterialsThatMapAlikeShareOnePart) {
    GltfWriter w = two_primitives();
    w.doc["materials"] = json::array({metallic_roughness({0.3f, 0.3f, 0.3f}, 0.0, 0.5, "first"),
                                      metallic_roughness({0.3f, 0.3f, 0.3f}, 0.0, 0.5, "copy")});
    const GltfModel model = load_gltf(w.write(test_folder(), "alike"));
    ASSERT_EQ(model.parts.size(), 1u);
    EXPECT_EQ(model.parts[0].name, "first");
    EXPECT_EQ(model.parts[0].mesh->triangle_count(), 2u);
}

TEST(GltfMaterial, EnergyStaysBelowOneInEveryChannel) {
    // rho_d + the lobe's albedo at normal incidence, rho_s (n + 2) / (n + 1) (its largest), over a grid.
    for (int r = 0; r <= 4; ++r)
        for (int g = 0; g <= 4; ++g)
            for (int m = 0; m <= 4; ++m)
                for (int k = 0; k <= 4; ++k) {
                    const glm::vec3 colour(float(r) / 4, float(g) / 4, 1.0f);
                    const float t = float(m) / 4, roughness = float(k) / 4;
                    for (const Material& mat : {material_from_metallic_roughness({colour, t, roughness}),
                                                material_from_specular_glossiness(colour, colour * t, roughness)}) {
                        const float albedo_s = mat.rho_s * (mat.shininess + 2.0f) / (mat.shininess + 1.0f);
                        for (int c = 0; c < 3; ++c)
                            EXPECT_LE(mat.rho_d[c] + albedo_s, 1.0f + 1e-6f) << r << g << m << k << " channel " << c;
                    }
                }
}

TEST(GltfMaterial, TheSpecularGlossinessBoxLoadsWithItsOneMaterial) {
    const GltfModel model = load_gltf(kModels / "BoxTextured-glTF-pbrSpecularGlossiness/BoxTextured.gltf");
    ASSERT_EQ(model.parts.size(), 1u);
    EXPECT_EQ(model.triangle_count(), 12u);
    EXPECT_EQ(model.parts[0].name, "Texture");
    // The file: diffuseFactor absent (1), specularFactor 0.2 grey, glossinessFactor 1 (its texture is
    // not read): rho_d = 1 - 0.2, n = 10^4 (roughness 0), rho_s = 0.2 * 10001 / 10002.
    expect_material(model.parts[0].material, glm::vec3(0.8f), 0.2f * 10001.0f / 10002.0f, 10000.0f);
}

TEST(GltfMaterial, TheEngineKeepsItsSevenColours) {
    // 34 glTF materials, all metallicFactor 0 and roughness absent (1), with 7 distinct
    // baseColorFactors (read from the .glb's JSON with Python): 7 parts, the triangles all kept.
    const GltfModel model = load_gltf(kModels / "2CylinderEngine-glTF-Binary/2CylinderEngine.glb");
    ASSERT_EQ(model.parts.size(), 7u);
    EXPECT_EQ(model.triangle_count(), 121496u);
    // Material_19, 0.85 grey (Material_20 is the same grey and shares its part, named after the first
    // met): rho_d = 0.96 * 0.85; n = 1; rho_s = 0.04 * 2 / 3. Material_16, blue.
    int found = 0;
    for (const GltfPart& part : model.parts) {
        EXPECT_GT(part.mesh->triangle_count(), 0u) << part.name;
        EXPECT_NE(part.name, "Material_20");
        if (part.name == "Material_19") {
            ++found;
            expect_material(part.material, glm::vec3(0.96f * 0.85f), 0.04f * 2.0f / 3.0f, 1.0f);
        } else if (part.name == "Material_16") {
            ++found;
            expect_material(part.material, {0.0f, 0.0f, 0.96f * 0.85f}, 0.04f * 2.0f / 3.0f, 1.0f);
        }
    }
    EXPECT_EQ(found, 2);
}

TEST(GltfMaterial, UnsupportedMaterialExtensionsAreIgnoredNotRefused) {
    const GltfModel model = load_gltf(kModels / "ClearCoat-glTF/ClearCoatTest.gltf");
    EXPECT_EQ(model.ignored_extensions, std::vector<std::string>{"KHR_materials_clearcoat"});
    EXPECT_GE(model.parts.size(), 2u);
    // Simple_Base (the first material) as the core model maps it: base (0.5, 0.02, 0.01), metallic 0,
    // roughness 0.44: alpha = 0.1936, n = 2 / 0.03748 - 2 = 51.36.
    bool found = false;
    for (const GltfPart& part : model.parts)
        if (part.name == "Simple_Base") {
            found = true;
            const float alpha2 = 0.1936f * 0.1936f;
            const float n = 2.0f / alpha2 - 2.0f;
            expect_material(part.material, glm::vec3(0.5f, 0.02f, 0.01f) * 0.96f, 0.04f * (n + 1.0f) / (n + 2.0f), n);
        }
    EXPECT_TRUE(found);
}

TEST(GltfMaterialMalformed, MaterialIndexOutOfRange) {
    GltfWriter w = two_primitives(0, 3);
    w.doc["materials"] = json::array({json::object()});
    expect_input_error(w.write(test_folder(), "index"),
                       "mesh 0 primitive 1 refers to material 3, which does not exist");
}

TEST(GltfMaterialMalformed, FactorsOutsideTheirGltfRangeAreRefused) {
    const auto with = [](const std::string& name, json material) {
        GltfWriter w = two_primitives(0, 0);
        w.doc["materials"] = json::array({std::move(material)});
        return w.write(test_folder(), name);
    };
    expect_input_error(with("rough", metallic_roughness({0.5f, 0.5f, 0.5f}, 0.0, 1.5, "r")),
                       "materials[0].pbrMetallicRoughness.roughnessFactor: 1.5 is outside 0 … 1");
    expect_input_error(with("metal", metallic_roughness({0.5f, 0.5f, 0.5f}, -0.25, 0.5, "m")),
                       "materials[0].pbrMetallicRoughness.metallicFactor: -0.25 is outside 0 … 1");
    expect_input_error(with("colour", metallic_roughness({0.5f, -1.0f, 0.5f}, 0.0, 0.5, "c")),
                       "materials[0].pbrMetallicRoughness.baseColorFactor[1]: -1.0 is outside 0 … 1");
    json gloss = json::object();
    gloss["extensions"]["KHR_materials_pbrSpecularGlossiness"] = {{"glossinessFactor", 2}};
    expect_input_error(with("gloss", gloss),
                       "materials[0].extensions.KHR_materials_pbrSpecularGlossiness.glossinessFactor: 2 is outside");
    json specular = json::object();
    specular["extensions"]["KHR_materials_pbrSpecularGlossiness"] = {{"specularFactor", {0.1, 0.1}}};
    expect_input_error(with("specular", specular), "specularFactor: expected 3 numbers");
    json diffuse = json::object();
    diffuse["extensions"]["KHR_materials_pbrSpecularGlossiness"] = {{"diffuseFactor", "red"}};
    expect_input_error(with("diffuse", diffuse), "diffuseFactor: expected 4 numbers");
}

TEST(GltfMaterialMalformed, NaNIsNoJsonNumber) {
    const fs::path dir = test_folder();
    GltfWriter w = two_primitives(0, 0);
    w.doc["materials"] = json::array({{{"pbrMetallicRoughness", {{"roughnessFactor", 0.5}}}}});
    const fs::path file = w.write(dir, "nan");
    std::string text;
    {
        std::ifstream in(file);
        text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    const auto at = text.find("0.5");
    ASSERT_NE(at, std::string::npos);
    text.replace(at, 3, "NaN");
    std::ofstream(file) << text;
    expect_input_error(file, "invalid JSON");
}

}  // namespace
}  // namespace envshadow
