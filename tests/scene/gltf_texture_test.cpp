// Base-colour textures from glTF (docs/SCENES.md "Textures"): the real BoxTextured models in each of
// their storage forms, texture coordinates through KHR_texture_transform worked out by hand, and the
// bad inputs docs/ROBUSTNESS.md lists (absurd image sizes, truncated and missing images, texture coordinate sets the
// primitive lacks), each a one-line InputError naming the file and the reason.
#include <cmath>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <stb_image_write.h>
#include <glm/gtc/constants.hpp>

#include "core/error.h"
#include "core/image.h"
#include "gltf_writer.h"
#include "scene/gltf.h"
#include "scene/texture.h"

namespace envshadow {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::GltfWriter;
using test::test_folder;

const fs::path& kModels = test::kAssimpModels;

void expect_input_error(const fs::path& file, const std::string& expected) {
    test::expect_one_line_error(file, expected, load_gltf);
}

// CesiumLogoFlat.png: a disc of blue sky over a green hill on a white rim.
void expect_cesium_logo(const GltfModel& model, TextureWrap wrap_s, TextureWrap wrap_t) {
    ASSERT_EQ(model.parts.size(), 1u);
    const Mesh& mesh = *model.parts[0].mesh;
    const Material& material = model.parts[0].material;
    ASSERT_TRUE(material.base_color_texture.has_value());
    const MaterialTexture& t = *material.base_color_texture;
    EXPECT_EQ(t.image->width, 211);
    EXPECT_EQ(t.image->height, 211);
    EXPECT_EQ(t.wrap_s, wrap_s);
    EXPECT_EQ(t.wrap_t, wrap_t);
    ASSERT_EQ(mesh.texcoords.size(), mesh.positions.size());
    for (const glm::vec2& uv : mesh.texcoords) {  // the accessor's min and max: u mirrors six times round the box
        EXPECT_GE(uv.x, 0.0f);
        EXPECT_LE(uv.x, 6.0f);
        EXPECT_GE(uv.y, 0.0f);
        EXPECT_LE(uv.y, 1.0f);
    }
    // v = 0 is the top of the image (glTF's uv origin): the sky there, the hill at the bottom.
    const glm::vec3 sky = sample_linear_rgb(t, {0.35f, 0.25f});
    const glm::vec3 hill = sample_linear_rgb(t, {0.5f, 0.85f});
    EXPECT_GT(sky.b, 1.5f * sky.r) << sky.r << " " << sky.g << " " << sky.b;
    EXPECT_GT(hill.g, 1.5f * hill.b) << hill.r << " " << hill.g << " " << hill.b;
}

TEST(SceneGltfTexture, BoxTexturedInEveryStorageForm) {
    // The .gltf copy's sampler mirrors in s and clamps in t; the other two repeat.
    const struct {
        const char* file;
        TextureWrap s, t;
    } cases[] = {{"BoxTextured-glTF/BoxTextured.gltf", TextureWrap::mirrored_repeat, TextureWrap::clamp_to_edge},
                 {"BoxTextured-glTF-Binary/BoxTextured.glb", TextureWrap::repeat, TextureWrap::repeat},
                 {"BoxTextured-glTF-Embedded/BoxTextured.gltf", TextureWrap::repeat, TextureWrap::repeat}};
    for (const auto& c : cases) {
        SCOPED_TRACE(c.file);
        const GltfModel model = load_gltf(kModels / c.file);
        expect_cesium_logo(model, c.s, c.t);
        // metallic 0: rho_d = 1 * (1 - 0.04), the texture multiplying it.
        EXPECT_NEAR(model.parts[0].material.rho_d.r, 0.96f, 1e-6f);
    }
}

TEST(SceneGltfTexture, SpecularGlossinessTakesItsDiffuseTexture) {
    const GltfModel model = load_gltf(kModels / "BoxTextured-glTF-pbrSpecularGlossiness/BoxTextured.gltf");
    expect_cesium_logo(model, TextureWrap::repeat, TextureWrap::repeat);
    EXPECT_NEAR(model.parts[0].material.rho_d.r, 1.0f - 0.2f, 1e-6f);  // diffuse (1 - max specular)
}

// A quad with texture coordinates, its material reading `texture_info` (baseColorTexture), and a 2x2
// PNG; returns the .gltf path.
struct TexturedQuad {
    GltfWriter writer;
    fs::path folder = test_folder();

    TexturedQuad() {
        const std::vector<glm::vec3> positions{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
        const std::vector<glm::vec2> uvs{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        const int p = writer.vec3s(positions);
        const int uv = writer.vec2s(uvs);
        const int i = writer.indices({0, 1, 2, 0, 2, 3});
        writer.mesh(p, i);
        writer.doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = uv;
        writer.doc["meshes"][0]["primitives"][0]["material"] = 0;
        writer.node({{"mesh", 0}});
        writer.scene({0});
        Image8 png(2, 2);
        for (int k = 0; k < 4; ++k)
            png.rgba[std::size_t(k) * 4 + std::size_t(k % 3)] = 255, png.rgba[std::size_t(k) * 4 + 3] = 255;
        write_png(folder / "checker.png", png);
        writer.doc["images"] = json::array({{{"uri", "checker.png"}}});
        writer.doc["textures"] = json::array({{{"source", 0}}});
        material({{"index", 0}});
    }
    void material(const json& texture_info) {
        writer.doc["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", texture_info}}}}});
    }
    fs::path write() { return writer.write(folder, "quad"); }
};

TEST(SceneGltfTexture, TextureTransformIsTranslationRotationScaleOfTheUvs) {
    TexturedQuad quad;
    quad.material({{"index", 0},
                   {"extensions",
                    {{"KHR_texture_transform",
                      {{"offset", {0.5, 0.25}}, {"rotation", glm::half_pi<double>()}, {"scale", {2.0, 3.0}}}}}}});
    const GltfModel model = load_gltf(quad.write());
    const Mesh& mesh = *model.parts.at(0).mesh;
    ASSERT_EQ(mesh.texcoords.size(), 4u);
    // uv' = offset + R(rotation) (scale * uv), R turning (u, v) to (u cos + v sin, -u sin + v cos):
    // (1, 0) -> (2, 0) -> (0, -2) -> (0.5, -1.75); (0, 1) -> (0, 3) -> (3, 0) -> (3.5, 0.25).
    const auto find = [&](const glm::vec3& p) {
        for (std::size_t v = 0; v < mesh.positions.size(); ++v)
            if (mesh.positions[v] == p) return mesh.texcoords[v];
        ADD_FAILURE() << "no vertex at the corner";
        return glm::vec2(NAN);
    };
    const glm::vec2 a = find({1, 0, 0}), b = find({0, 1, 0}), c = find({0, 0, 0});
    EXPECT_NEAR(a.x, 0.5f, 1e-5f);
    EXPECT_NEAR(a.y, -1.75f, 1e-5f);
    EXPECT_NEAR(b.x, 3.5f, 1e-5f);
    EXPECT_NEAR(b.y, 0.25f, 1e-5f);
    EXPECT_NEAR(c.x, 0.5f, 1e-5f);
    EXPECT_NEAR(c.y, 0.25f, 1e-5f);
}

TEST(SceneGltfTexture, ThePngDecodesToItsTexels) {
    TexturedQuad quad;
    const GltfModel model = load_gltf(quad.write());
    const TextureImage& image = *model.parts.at(0).material.base_color_texture->image;
    ASSERT_EQ(image.width, 2);
    ASSERT_EQ(image.height, 2);
    EXPECT_EQ(image.rgba[0], 255);       // texel (0, 0) red
    EXPECT_EQ(image.rgba[4 + 1], 255);   // texel (1, 0) green
    EXPECT_EQ(image.rgba[8 + 2], 255);   // texel (0, 1) blue
    EXPECT_EQ(image.rgba[12 + 0], 255);  // texel (1, 1) red again
}

TEST(SceneGltfTexture, HeaderClaimingAHugeImageIsRefusedBeforeDecoding) {
    TexturedQuad quad;
    // A PNG signature and an IHDR chunk of 100000 x 100000 RGBA, 8 bits, then nothing.
    const unsigned char header[] = {0x89, 'P',  'N',  'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R', 0,
                                    1,    0x86, 0xA0, 0,   1,    0x86, 0xA0, 8,    6, 0, 0, 0,  0,   0,   0,   0};
    std::ofstream(quad.folder / "checker.png", std::ios::binary)
        .write(reinterpret_cast<const char*>(header), sizeof header);
    expect_input_error(quad.write(), "100000x100000 is beyond the 16384x16384 limit");
}

TEST(SceneGltfTexture, TruncatedPngIsAnError) {
    TexturedQuad quad;
    const fs::path png = quad.folder / "checker.png";
    fs::copy_file(kModels / "BoxTextured-glTF/CesiumLogoFlat.png", png, fs::copy_options::overwrite_existing);
    fs::resize_file(png, fs::file_size(png) / 2);
    expect_input_error(quad.write(), "image 0: cannot decode it");
}

// A 16 x 16 JPEG of a horizontal ramp (stb_image_write), as checker.png's replacement.
std::vector<std::uint8_t> ramp_jpeg() {
    std::vector<std::uint8_t> rgb(16 * 16 * 3);
    for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = std::uint8_t((i / 3 % 16) * 16);
    std::vector<std::uint8_t> out;
    stbi_write_jpg_to_func(
        [](void* context, void* data, int size) {
            auto* o = static_cast<std::vector<std::uint8_t>*>(context);
            o->insert(o->end(), static_cast<std::uint8_t*>(data), static_cast<std::uint8_t*>(data) + size);
        },
        &out, 16, 16, 3, rgb.data(), 95);
    return out;
}

TEST(SceneGltfTexture, JpegDecodesAndATruncatedOneIsAnError) {
    TexturedQuad quad;
    const std::vector<std::uint8_t> jpeg = ramp_jpeg();
    const auto write = [&](std::size_t bytes) {
        std::ofstream(quad.folder / "checker.png", std::ios::binary)
            .write(reinterpret_cast<const char*>(jpeg.data()), std::streamsize(bytes));
    };
    write(jpeg.size());
    const GltfModel model = load_gltf(quad.write());
    const TextureImage& image = *model.parts.at(0).material.base_color_texture->image;
    EXPECT_EQ(image.width, 16);
    EXPECT_LT(image.rgba[0], 20);        // the ramp's dark left end
    EXPECT_GT(image.rgba[15 * 4], 200);  // and bright right end
    write(jpeg.size() / 2);
    expect_input_error(quad.write(), "image 0: cannot decode it");
}

TEST(SceneGltfTexture, AnImageThatIsNotPngOrJpegIsAnError) {
    TexturedQuad quad;
    std::ofstream(quad.folder / "checker.png") << "GIF89a, or anything else";
    expect_input_error(quad.write(), "image 0: not a PNG or JPEG image");
}

TEST(SceneGltfTexture, MissingImageFileIsNamed) {
    TexturedQuad quad;
    fs::remove(quad.folder / "checker.png");
    expect_input_error(quad.write(), "image 0 file " + (quad.folder / "checker.png").string() + " not found");
}

TEST(SceneGltfTexture, TexCoordSetThePrimitiveLacksIsAnError) {
    TexturedQuad quad;
    quad.material({{"index", 0}, {"texCoord", 1}});
    expect_input_error(quad.write(), "mesh 0 primitive 0: its material's textures read TEXCOORD_1");
}

TEST(SceneGltfTexture, TextureIndexOutOfRangeIsAnError) {
    TexturedQuad quad;
    quad.material({{"index", 3}});
    expect_input_error(quad.write(), "materials[0] uses texture 3, which does not exist");
}

TEST(SceneGltfTexture, TexcoordsOfTheWrongTypeAreAnError) {
    TexturedQuad quad;
    quad.writer.doc["accessors"][1]["type"] = "VEC3";
    quad.writer.doc["accessors"][1]["count"] = 2;  // stays inside the view
    expect_input_error(quad.write(), "TEXCOORD_0 (accessor 1) must be VEC2");
}

TEST(SceneGltfTexture, NonFiniteTexcoordsAreAnError) {
    TexturedQuad quad;
    const float nan = NAN;
    std::memcpy(&quad.writer.bin[48 + 4], &nan, 4);  // after 4 positions of 12 bytes: the first uv's v
    expect_input_error(quad.write(), "TEXCOORD_0 0 is not finite");
}

// Emission (docs/SCENES.md "Emission"): emissiveFactor times KHR_materials_emissive_strength, and
// emissiveTexture where it reads the base colour's texture coordinates.
TEST(SceneGltfEmission, FactorTimesStrengthAndTheTextureOnTheBaseColoursCoordinates) {
    TexturedQuad quad;
    quad.writer.doc["materials"][0]["emissiveFactor"] = {0.5, 0.25, 1.0};
    quad.writer.doc["materials"][0]["extensions"] = {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4.0}}}};
    quad.writer.doc["materials"][0]["emissiveTexture"] = {{"index", 0}};
    const GltfModel model = load_gltf(quad.write());
    const Material& m = model.parts.at(0).material;
    EXPECT_EQ(m.emission, glm::vec3(2.0f, 1.0f, 4.0f));
    ASSERT_TRUE(m.emission_texture.has_value());
    EXPECT_EQ(m.emission_texture->image, m.base_color_texture->image);  // the one texture both use
}

TEST(SceneGltfEmission, NoFactorIsBlackAndAStrengthAloneIsBlackToo) {
    TexturedQuad quad;
    EXPECT_EQ(load_gltf(quad.write()).parts.at(0).material.emission, glm::vec3(0.0f));
    quad.writer.doc["materials"][0]["extensions"] = {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4.0}}}};
    EXPECT_EQ(load_gltf(quad.write()).parts.at(0).material.emission, glm::vec3(0.0f));
    quad.writer.doc["materials"][0]["emissiveFactor"] = {1.0, 1.0, 1.0};
    quad.writer.doc["materials"][0]["extensions"] = json::object();  // strength 1 without the extension
    EXPECT_EQ(load_gltf(quad.write()).parts.at(0).material.emission, glm::vec3(1.0f));
}

TEST(SceneGltfEmission, AnEmissionTextureWithoutABaseColourTextureGivesTheMeshItsCoordinates) {
    TexturedQuad quad;
    quad.writer.doc["materials"] =
        json::array({{{"emissiveFactor", {1.0, 1.0, 1.0}}, {"emissiveTexture", {{"index", 0}}}}});
    const GltfModel model = load_gltf(quad.write());
    const Material& m = model.parts.at(0).material;
    EXPECT_FALSE(m.base_color_texture.has_value());
    ASSERT_TRUE(m.emission_texture.has_value());
    EXPECT_EQ(model.parts.at(0).mesh->texcoords.size(), 4u);
}

TEST(SceneGltfEmission, AnEmissionTextureOnOtherCoordinatesShowsItsFactorAlone) {
    TexturedQuad quad;
    quad.writer.doc["materials"][0]["emissiveFactor"] = {1.0, 1.0, 1.0};
    quad.writer.doc["materials"][0]["emissiveTexture"] = {
        {"index", 0}, {"extensions", {{"KHR_texture_transform", {{"scale", {2.0, 2.0}}}}}}};
    const GltfModel model = load_gltf(quad.write());
    EXPECT_FALSE(model.parts.at(0).material.emission_texture.has_value());
    EXPECT_EQ(model.parts.at(0).material.emission, glm::vec3(1.0f));
}

TEST(SceneGltfEmission, BadEmissionIsAnErrorNamingTheProperty) {
    TexturedQuad quad;
    quad.writer.doc["materials"][0]["emissiveFactor"] = {1.5, 0.0, 0.0};
    expect_input_error(quad.write(), "materials[0].emissiveFactor[0]: 1.5 is outside 0");
    quad.writer.doc["materials"][0]["emissiveFactor"] = {1.0, 0.0, 0.0};
    quad.writer.doc["materials"][0]["extensions"] = {{"KHR_materials_emissive_strength", {{"emissiveStrength", -1.0}}}};
    expect_input_error(
        quad.write(), "materials[0].extensions.KHR_materials_emissive_strength.emissiveStrength: must not be negative");
    quad.writer.doc["materials"][0]["extensions"] = json::object();
    quad.writer.doc["materials"][0]["emissiveTexture"] = {{"index", 7}};
    expect_input_error(quad.write(), "materials[0] uses texture 7, which does not exist");
}

// Occlusion (docs/SCENES.md "Occlusion"): occlusionTexture with its strength, read as stored (linear),
// where it reads the base colour's texture coordinates.
TEST(SceneGltfOcclusion, TheTextureIsDataWithItsStrength) {
    TexturedQuad quad;
    quad.writer.doc["materials"][0]["occlusionTexture"] = {{"index", 0}, {"strength", 0.25}};
    const GltfModel model = load_gltf(quad.write());
    const Material& m = model.parts.at(0).material;
    ASSERT_TRUE(m.occlusion_texture.has_value());
    EXPECT_FALSE(m.occlusion_texture->srgb);
    EXPECT_TRUE(m.base_color_texture->srgb);  // the same image, decoded as colour there
    EXPECT_EQ(m.occlusion_texture->image, m.base_color_texture->image);
    EXPECT_EQ(m.occlusion_strength, 0.25f);
    quad.writer.doc["materials"][0]["occlusionTexture"] = {{"index", 0}};
    EXPECT_EQ(load_gltf(quad.write()).parts.at(0).material.occlusion_strength, 1.0f);  // glTF's default
}

TEST(SceneGltfOcclusion, AnOcclusionTextureAloneGivesTheMeshItsCoordinates) {
    TexturedQuad quad;
    quad.writer.doc["materials"] = json::array({{{"occlusionTexture", {{"index", 0}}}}});
    const GltfModel model = load_gltf(quad.write());
    EXPECT_TRUE(model.parts.at(0).material.occlusion_texture.has_value());
    EXPECT_EQ(model.parts.at(0).mesh->texcoords.size(), 4u);
}

TEST(SceneGltfOcclusion, AnOcclusionTextureOnOtherCoordinatesIsIgnored) {
    TexturedQuad quad;
    quad.writer.doc["materials"][0]["occlusionTexture"] = {{"index", 0}, {"texCoord", 1}};
    EXPECT_FALSE(load_gltf(quad.write()).parts.at(0).material.occlusion_texture.has_value());
}

TEST(SceneGltfOcclusion, BadOcclusionIsAnErrorNamingTheProperty) {
    TexturedQuad quad;
    quad.writer.doc["materials"][0]["occlusionTexture"] = {{"index", 0}, {"strength", 1.5}};
    expect_input_error(quad.write(), "materials[0].occlusionTexture.strength: 1.5 is outside 0");
    quad.writer.doc["materials"][0]["occlusionTexture"] = {{"index", 3}};
    expect_input_error(quad.write(), "materials[0] uses texture 3, which does not exist");
}

// Metallic-roughness texture (docs/SCENES.md "Textures"): its G and B scale the factors; read as stored (linear),
// where it reads the base colour's texture coordinates; with KHR_materials_pbrSpecularGlossiness, none.
TEST(SceneGltfMetallicRoughnessTexture, TheTextureIsDataBesideTheFactors) {
    TexturedQuad quad;
    quad.writer.doc["materials"][0]["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {{"index", 0}};
    quad.writer.doc["materials"][0]["pbrMetallicRoughness"]["roughnessFactor"] = 0.5;
    const Material m = load_gltf(quad.write()).parts.at(0).material;
    ASSERT_TRUE(m.metallic_roughness_texture.has_value());
    EXPECT_FALSE(m.metallic_roughness_texture->srgb);
    EXPECT_TRUE(m.base_color_texture->srgb);  // the same image, decoded as colour there
    EXPECT_EQ(m.metallic_roughness_texture->image, m.base_color_texture->image);
    ASSERT_TRUE(m.metallic_roughness.has_value());
    EXPECT_EQ(m.metallic_roughness->roughness, 0.5f);  // the factor, the texture's G applied per pixel
    EXPECT_EQ(m.metallic_roughness->metallic, 1.0f);
}

TEST(SceneGltfMetallicRoughnessTexture, TheTextureAloneGivesTheMeshItsCoordinates) {
    TexturedQuad quad;
    quad.writer.doc["materials"] =
        json::array({{{"pbrMetallicRoughness", {{"metallicRoughnessTexture", {{"index", 0}}}}}}});
    const GltfModel model = load_gltf(quad.write());
    EXPECT_TRUE(model.parts.at(0).material.metallic_roughness_texture.has_value());
    EXPECT_EQ(model.parts.at(0).mesh->texcoords.size(), 4u);
}

TEST(SceneGltfMetallicRoughnessTexture, OnOtherCoordinatesOrUnderSpecularGlossinessItIsIgnored) {
    TexturedQuad quad;
    quad.writer.doc["materials"][0]["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {{"index", 0},
                                                                                           {"texCoord", 1}};
    EXPECT_FALSE(load_gltf(quad.write()).parts.at(0).material.metallic_roughness_texture.has_value());
    quad.writer.doc["materials"][0]["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {{"index", 0}};
    quad.writer.doc["materials"][0]["extensions"] = {
        {"KHR_materials_pbrSpecularGlossiness", {{"diffuseTexture", {{"index", 0}}}}}};
    const Material m = load_gltf(quad.write()).parts.at(0).material;
    EXPECT_FALSE(m.metallic_roughness_texture.has_value());
    EXPECT_TRUE(m.base_color_texture.has_value());
}

TEST(SceneGltfMetallicRoughnessTexture, AMissingTextureIsAnError) {
    TexturedQuad quad;
    quad.writer.doc["materials"][0]["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {{"index", 3}};
    expect_input_error(quad.write(), "materials[0] uses texture 3, which does not exist");
}

// Alpha (docs/SCENES.md "Alpha"): alphaMode, alphaCutoff and baseColorFactor's alpha.
TEST(SceneGltfAlpha, MaskTakesItsCutoffAndTheFactorsAlpha) {
    TexturedQuad quad;
    EXPECT_EQ(load_gltf(quad.write()).parts.at(0).material.alpha_mode, AlphaMode::opaque);
    EXPECT_FALSE(load_gltf(quad.write()).parts.at(0).material.masked());
    quad.writer.doc["materials"][0]["alphaMode"] = "MASK";
    quad.writer.doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = {1.0, 1.0, 1.0, 0.8};
    Material m = load_gltf(quad.write()).parts.at(0).material;
    EXPECT_EQ(m.alpha_mode, AlphaMode::mask);
    EXPECT_EQ(m.alpha_cutoff, 0.5f);  // glTF's default
    EXPECT_EQ(m.base_alpha, 0.8f);
    EXPECT_TRUE(m.masked());
    quad.writer.doc["materials"][0]["alphaCutoff"] = 0.25;
    EXPECT_EQ(load_gltf(quad.write()).parts.at(0).material.alpha_cutoff, 0.25f);
}

TEST(SceneGltfAlpha, BlendKeepsTheAlphaAndIgnoresTheCutoff) {
    TexturedQuad quad;
    quad.writer.doc["materials"][0]["alphaMode"] = "BLEND";
    quad.writer.doc["materials"][0]["alphaCutoff"] = 0.9;  // MASK's alone: ignored
    quad.writer.doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = {1.0, 1.0, 1.0, 0.4};
    const Material m = load_gltf(quad.write()).parts.at(0).material;
    EXPECT_EQ(m.alpha_mode, AlphaMode::blend);
    EXPECT_EQ(m.base_alpha, 0.4f);
    EXPECT_TRUE(m.blended());
    EXPECT_FALSE(m.masked());
}

// A blend material whose alpha is 1 everywhere (no texture, factor alpha 1) hides what is behind it: opaque.
TEST(SceneGltfAlpha, BlendWithoutAnAlphaBelowOneIsOpaque) {
    Material m;
    m.alpha_mode = AlphaMode::blend;
    EXPECT_FALSE(m.blended());
    m.base_alpha = 0.99f;
    EXPECT_TRUE(m.blended());
}

TEST(SceneGltfAlpha, BadAlphaIsAnErrorNamingTheProperty) {
    TexturedQuad quad;
    quad.writer.doc["materials"][0]["alphaMode"] = "CUTOUT";
    expect_input_error(quad.write(), "materials[0].alphaMode: \"CUTOUT\" is not OPAQUE, MASK or BLEND");
    quad.writer.doc["materials"][0]["alphaMode"] = "MASK";
    quad.writer.doc["materials"][0]["alphaCutoff"] = -0.5;
    expect_input_error(quad.write(), "materials[0].alphaCutoff: must not be negative");
    quad.writer.doc["materials"][0]["alphaCutoff"] = 0.5;
    quad.writer.doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = {1.0, 1.0, 1.0, 1.5};
    expect_input_error(quad.write(), "baseColorFactor[3]: 1.5 is outside 0");
}

// Normal maps (docs/SCENES.md "Normal maps"): normalTexture with its scale, read as stored (linear), and the
// tangents it needs: the file's TANGENT through the node's transform, or made from the normals and uvs.
TEST(SceneGltfNormalTexture, TheTextureIsDataWithItsScaleAndTangentsAreMade) {
    TexturedQuad quad;
    quad.writer.doc["materials"][0]["normalTexture"] = {{"index", 0}, {"scale", 0.5}};
    const GltfModel model = load_gltf(quad.write());
    const Material& m = model.parts.at(0).material;
    ASSERT_TRUE(m.normal_texture.has_value());
    EXPECT_FALSE(m.normal_texture->srgb);
    EXPECT_EQ(m.normal_scale, 0.5f);
    // The quad's u runs along +x and its v along +y, up the quad: glTF's v runs down the image, so the
    // image's up (a normal map's +y) is -y here, and cross(normal, tangent) = +y needs w = -1.
    const Mesh& mesh = *model.parts.at(0).mesh;
    ASSERT_EQ(mesh.tangents.size(), 4u);
    for (const glm::vec4& t : mesh.tangents) {
        EXPECT_NEAR(t.x, 1.0f, 1e-6f);
        EXPECT_NEAR(t.y, 0.0f, 1e-6f);
        EXPECT_NEAR(t.z, 0.0f, 1e-6f);
        EXPECT_EQ(t.w, -1.0f);
    }
    quad.writer.doc["materials"][0]["normalTexture"] = {{"index", 0}};
    EXPECT_EQ(load_gltf(quad.write()).parts.at(0).material.normal_scale, 1.0f);  // glTF's default
    quad.writer.doc["materials"][0].erase("normalTexture");
    EXPECT_TRUE(load_gltf(quad.write()).parts.at(0).mesh->tangents.empty());  // no normal map, no tangents
}

TEST(SceneGltfNormalTexture, TheFilesTangentsTurnWithTheNode) {
    TexturedQuad quad;
    quad.writer.doc["materials"][0]["normalTexture"] = {{"index", 0}};
    const std::vector<glm::vec4> tangents(4, glm::vec4(0.0f, 1.0f, 0.0f, 1.0f));  // not what the uvs would give
    quad.writer.doc["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] =
        quad.writer.accessor(quad.writer.view(tangents.data(), tangents.size() * 16), 5126, 4, "VEC4");
    for (const double turn : {1.0, -1.0}) {  // a quarter turn about z, then the same with x mirrored
        quad.writer.doc["nodes"][0]["matrix"] = {0, turn, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
        const GltfModel model = load_gltf(quad.write());
        const Mesh& mesh = *model.parts.at(0).mesh;
        ASSERT_EQ(mesh.tangents.size(), 4u);
        for (const glm::vec4& t : mesh.tangents) {  // +y to -x
            EXPECT_NEAR(t.x, -1.0f, 1e-6f) << "turn " << turn;
            EXPECT_NEAR(t.y, 0.0f, 1e-6f) << "turn " << turn;
            EXPECT_EQ(t.w, float(turn)) << "a mirror turns the handedness round";
        }
    }
}

TEST(SceneGltfNormalTexture, BadTangentsAndTexturesAreErrors) {
    TexturedQuad quad;
    quad.writer.doc["materials"][0]["normalTexture"] = {{"index", 0}};
    const std::vector<glm::vec3> three(4, glm::vec3(1.0f, 0.0f, 0.0f));
    quad.writer.doc["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] = quad.writer.vec3s(three);
    expect_input_error(quad.write(), "TANGENT (accessor");
    const std::vector<glm::vec4> two(2, glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
    quad.writer.doc["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] =
        quad.writer.accessor(quad.writer.view(two.data(), two.size() * 16), 5126, 2, "VEC4");
    expect_input_error(quad.write(), "has 2 tangents for 4 positions");
    quad.writer.doc["meshes"][0]["primitives"][0]["attributes"].erase("TANGENT");
    quad.writer.doc["materials"][0]["normalTexture"] = {{"index", 4}};
    expect_input_error(quad.write(), "materials[0] uses texture 4, which does not exist");
}

}  // namespace
}  // namespace envshadow
