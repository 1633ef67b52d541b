#include <algorithm>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "gltf_writer.h"
#include "scene/scene.h"

namespace envshadow {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::GltfWriter;
using test::test_folder;

const fs::path kEngine = "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb";

fs::path write_scene(const fs::path& folder, const json& scene, const std::string& name = "scene.json") {
    const fs::path path = folder / name;
    std::ofstream(path) << scene.dump(2);
    return path;
}

json minimal_scene() {
    return {{"environment", "builtin:sky"},
            {"camera", {{"position", {0, 1, 5}}, {"target", {0, 0.5, 0}}}},
            {"objects", json::array({{{"mesh", "sphere"}}})}};
}

// Loading fails with one line that starts with the scene file and mentions every piece of `expected`.
void expect_scene_error(const fs::path& file, std::initializer_list<std::string> expected) {
    try {
        load_scene(file);
        ADD_FAILURE() << file << " loaded without an error";
    } catch (const InputError& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.rfind(file.string() + ": ", 0), 0u) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        for (const std::string& piece : expected)
            EXPECT_NE(message.find(piece), std::string::npos) << "'" << piece << "' not in: " << message;
    }
}

void expect_scene_error_with(const json& scene, std::initializer_list<std::string> expected) {
    expect_scene_error(write_scene(test_folder(), scene), expected);
}

glm::vec3 world(const Object& o, const glm::vec3& p, double t = 0.0) {
    return glm::vec3(o.world_from_object(t) * glm::vec4(p, 1));
}
glm::vec3 world_direction(const Object& o, const glm::vec3& d) {
    return glm::vec3(o.transform * glm::vec4(d, 0));
}

void expect_near(const glm::vec3& a, const glm::vec3& b, float tolerance = 1e-5f) {
    EXPECT_LT(glm::distance(a, b), tolerance)
        << "(" << a.x << ", " << a.y << ", " << a.z << ") vs (" << b.x << ", " << b.y << ", " << b.z << ")";
}

bool inside_frustum(const Camera& c, float aspect, const glm::vec3& lo, const glm::vec3& hi) {
    const glm::mat4 clip_from_world = c.clip_from_view(aspect, 0.01f, 1000.0f) * c.view_from_world();
    for (int corner = 0; corner < 8; ++corner) {
        const glm::vec4 p = clip_from_world * glm::vec4((corner & 1) ? hi.x : lo.x, (corner & 2) ? hi.y : lo.y,
                                                        (corner & 4) ? hi.z : lo.z, 1);
        if (p.w <= 0 || std::abs(p.x) > p.w || std::abs(p.y) > p.w || std::abs(p.z) > p.w) return false;
    }
    return true;
}

TEST(SceneFile, ReadsEveryPart) {
    const json scene = {{"description", "test"},
                        {"environment", {{"source", "builtin:sky:elevation=30"}, {"rotation", 45}, {"exposure", -1.5}}},
                        {"camera", {{"position", {1, 2, 3}}, {"target", {0, 0.5, 0}}, {"up", {0, 1, 0}}, {"fov", 35}}},
                        {"objects",
                         {{{"name", "floor"},
                           {"mesh", {{"type", "plane"}, {"size", 8}}},
                           {"ground", true},
                           {"transform", {{"translation", {0, -0.5, 0}}}}},
                          {{"mesh", {{"type", "sphere"}, {"radius", 0.25}, {"segments", 16}}},
                           {"transform", {{"translation", {1, 0.25, 0}}}},
                           {"material", {{"diffuse", {0.1, 0.2, 0.3}}, {"specular", 0.4}, {"shininess", 250}}},
                           {"animation",
                            {{"type", "orbit"},
                             {"center", {0, 1, 0}},
                             {"radius", 2},
                             {"height", 0.5},
                             {"period", 6},
                             {"face_motion", false}}}},
                          {{"name", "crate"},
                           {"mesh", {{"type", "box"}, {"size", {1, 2, 3}}}},
                           {"casts_shadows", false},
                           {"material", {{"diffuse", 0.5}}}}}}};
    const Scene s = load_scene(write_scene(test_folder(), scene));

    EXPECT_EQ(s.environment.source, "builtin:sky:elevation=30");
    EXPECT_EQ(s.environment.rotation_degrees, 45.0f);
    EXPECT_EQ(s.environment.exposure_stops, -1.5f);
    EXPECT_EQ(s.camera.position, glm::vec3(1, 2, 3));
    EXPECT_EQ(s.camera.target, glm::vec3(0, 0.5f, 0));
    EXPECT_EQ(s.camera.fov_y_degrees, 35.0f);
    EXPECT_TRUE(s.has_ground);
    EXPECT_EQ(s.ground_height, -0.5f);

    ASSERT_EQ(s.objects.size(), 3u);
    const Object &floor = s.objects[0], &ball = s.objects[1], &crate = s.objects[2];
    EXPECT_EQ(floor.name, "floor");
    EXPECT_FALSE(floor.casts_shadows);  // the ground only receives
    EXPECT_EQ(floor.mesh->bounds_max, glm::vec3(4, 0, 4));

    EXPECT_EQ(ball.name, "sphere");
    EXPECT_TRUE(ball.casts_shadows);
    EXPECT_EQ(ball.mesh->triangle_count(), 2u * 16 * 7);
    EXPECT_EQ(ball.material.rho_d, glm::vec3(0.1f, 0.2f, 0.3f));
    EXPECT_EQ(ball.material.rho_s, 0.4f);
    EXPECT_EQ(ball.material.shininess, 250.0f);
    EXPECT_EQ(ball.animation.kind, Animation::Kind::orbit);
    EXPECT_EQ(ball.animation.period, 6.0);
    EXPECT_FALSE(ball.animation.face_motion);
    // At rest (1, 0.25, 0); the orbit adds centre + (radius, height, 0) at t = 0.
    expect_near(world(ball, {0, 0, 0}), {3, 1.75f, 0});

    EXPECT_EQ(crate.name, "crate");
    EXPECT_FALSE(crate.casts_shadows);
    EXPECT_EQ(crate.material.rho_d, glm::vec3(0.5f));
    EXPECT_EQ(crate.material.rho_s, 0.0f);
    EXPECT_EQ(crate.mesh->bounds_max, glm::vec3(0.5f, 1.0f, 1.5f));
    EXPECT_EQ(s.triangle_count(), 2u + 2u * 16 * 7 + 12u);
}

TEST(SceneFile, TransformsScaleThenRotateThenTranslate) {
    json scene = minimal_scene();
    scene["objects"] = {
        {{"mesh", "box"}, {"transform", {{"rotation", {90, 0, 0}}}}},
        {{"mesh", "box"}, {"transform", {{"rotation", {90, 90, 0}}}}},  // X first, then Y
        {{"mesh", "box"}, {"transform", {{"rotation", {{"axis", {0, 0, 2}}, {"angle", 90}}}}}},
        {{"mesh", "box"}, {"transform", {{"translation", {1, 2, 3}}, {"rotation", {0, 90, 0}}, {"scale", {1, 2, 3}}}}}};
    const Scene s = load_scene(write_scene(test_folder(), scene));
    expect_near(world_direction(s.objects[0], {0, 1, 0}), {0, 0, 1});
    expect_near(world_direction(s.objects[1], {0, 1, 0}), {1, 0, 0});
    expect_near(world_direction(s.objects[2], {1, 0, 0}), {0, 1, 0});
    // (1, 1, 1) -> scale (1, 2, 3) -> 90 degrees about Y: (x, y, z) -> (z, y, -x) -> + (1, 2, 3)
    expect_near(world(s.objects[3], {1, 1, 1}), {4, 4, 2});
    const json uniform = {{"mesh", "box"}, {"transform", {{"scale", 2}}}};
    scene["objects"] = {uniform};
    expect_near(world(load_scene(write_scene(test_folder(), scene)).objects[0], {1, 1, 1}), {2, 2, 2});
}

TEST(SceneFile, FitStandsTheMeshOnTheGroundAtTheGivenSize) {
    json scene = minimal_scene();
    scene["objects"] = {{{"mesh", {{"type", "torus"}, {"major_radius", 1.0}, {"minor_radius", 0.5}}},
                         {"fit", 0.75},
                         {"transform", {{"translation", {5, 0, 0}}}}}};
    const Scene s = load_scene(write_scene(test_folder(), scene));
    glm::vec3 lo, hi;
    s.bounds_at(0.0, lo, hi);
    // The torus is 3 x 1 x 3: scaled by 1/4, standing on y = 0, centred on x = 5.
    expect_near(lo, {4.625f, 0, -0.375f}, 1e-4f);
    expect_near(hi, {5.375f, 0.25f, 0.375f}, 1e-4f);
}

TEST(SceneFile, RelativePathsAreRelativeToTheSceneFile) {
    const fs::path dir = test_folder();
    fs::create_directories(dir / "maps");
    fs::create_directories(dir / "models");
    std::ofstream(dir / "maps/sky.exr") << "only its existence is checked here";
    GltfWriter w;
    w.scene({w.node({{"mesh", w.mesh(w.vec3s({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}))}})});
    w.write(dir / "models", "triangle");
    json scene = minimal_scene();
    scene["environment"] = "maps/sky.exr";
    scene["objects"] = {{{"model", "models/triangle.gltf"}}};
    const Scene s = load_scene(write_scene(dir, scene));
    EXPECT_EQ(fs::path(s.environment.source), (dir / "maps/sky.exr").lexically_normal());
    ASSERT_EQ(s.objects.size(), 1u);
    EXPECT_EQ(s.objects[0].name, "triangle");
    EXPECT_EQ(s.objects[0].mesh->triangle_count(), 1u);
}

// tinted.gltf in `folder`: one triangle of a rough blue dielectric (base (0.2, 0.4, 0.6), metallic 0, roughness 0.5).
void write_tinted_model(const fs::path& folder) {
    GltfWriter w;
    const int mesh = w.mesh(w.vec3s({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
    w.doc["meshes"][mesh]["primitives"][0]["material"] = 0;
    w.doc["materials"] = json::array(
        {{{"pbrMetallicRoughness",
           {{"baseColorFactor", {0.2, 0.4, 0.6, 1.0}}, {"metallicFactor", 0.0}, {"roughnessFactor", 0.5}}}}});
    w.scene({w.node({{"mesh", mesh}})});
    w.write(folder, "tinted");
}

TEST(SceneFile, ModelMaterialComesFromGltfUnlessTheSceneGivesOne) {
    const fs::path dir = test_folder();
    write_tinted_model(dir);
    json scene = minimal_scene();
    scene["objects"] = {{{"model", "tinted.gltf"}},
                        {{"model", "tinted.gltf"}, {"material", {{"specular", 0.3}}}},
                        {{"model", "tinted.gltf"}, {"material", {{"diffuse", {0.9, 0.8, 0.7}}}}}};
    const Scene s = load_scene(write_scene(dir, scene));
    ASSERT_EQ(s.objects.size(), 3u);
    // The glTF's, mapped (docs/SCENES.md): rho_d = 0.96 base, n = 30 (roughness 0.5), rho_s = 0.04 * 31 / 32.
    expect_near(s.objects[0].material.rho_d, {0.192f, 0.384f, 0.576f});
    EXPECT_NEAR(s.objects[0].material.rho_s, 0.03875f, 1e-6f);
    EXPECT_NEAR(s.objects[0].material.shininess, 30.0f, 1e-4f);
    // Each key given replaces the glTF's; the others stay.
    expect_near(s.objects[1].material.rho_d, {0.192f, 0.384f, 0.576f});
    EXPECT_EQ(s.objects[1].material.rho_s, 0.3f);
    EXPECT_NEAR(s.objects[1].material.shininess, 30.0f, 1e-4f);
    expect_near(s.objects[2].material.rho_d, {0.9f, 0.8f, 0.7f});
    EXPECT_NEAR(s.objects[2].material.rho_s, 0.03875f, 1e-6f);
    EXPECT_EQ(s.objects[0].mesh, s.objects[2].mesh);  // one file, loaded once
    // glTF's parameters are kept for its BRDF until a Phong key makes the material the paper's.
    ASSERT_TRUE(s.objects[0].material.metallic_roughness);
    EXPECT_EQ(*s.objects[0].material.metallic_roughness, (MetallicRoughness{{0.2f, 0.4f, 0.6f}, 0.0f, 0.5f}));
    EXPECT_FALSE(s.objects[1].material.metallic_roughness);
    EXPECT_FALSE(s.objects[2].material.metallic_roughness);
}

TEST(SceneFile, GltfMaterialKeysGiveTheMetallicRoughnessBrdf) {
    const fs::path dir = test_folder();
    write_tinted_model(dir);
    json scene = minimal_scene();
    scene["objects"] = {{{"mesh", "sphere"}, {"material", {{"base_color", {1.0, 0.78, 0.34}}, {"roughness", 0.3}}}},
                        {{"model", "tinted.gltf"}, {"material", {{"roughness", 0.2}}}}};
    const Scene s = load_scene(write_scene(dir, scene));
    ASSERT_EQ(s.objects.size(), 2u);
    // Keys not given are glTF's defaults (metallic 1) on a mesh, the file's on a model.
    ASSERT_TRUE(s.objects[0].material.metallic_roughness);
    EXPECT_EQ(*s.objects[0].material.metallic_roughness, (MetallicRoughness{{1.0f, 0.78f, 0.34f}, 1.0f, 0.3f}));
    ASSERT_TRUE(s.objects[1].material.metallic_roughness);
    EXPECT_EQ(*s.objects[1].material.metallic_roughness, (MetallicRoughness{{0.2f, 0.4f, 0.6f}, 0.0f, 0.2f}));
    // The stand-in follows: a metal has no diffuse.
    EXPECT_EQ(s.objects[0].material.rho_d, glm::vec3(0.0f));

    json mixed = minimal_scene();
    mixed["objects"][0]["material"] = {{"diffuse", 0.5}, {"metallic", 0.0}};
    expect_scene_error_with(mixed, {"objects[0].material", "not both"});
    json out_of_range = minimal_scene();
    out_of_range["objects"][0]["material"] = {{"roughness", 1.5}};
    expect_scene_error_with(out_of_range, {"objects[0].material.roughness"});
}

// "emission" goes with either kind of material, and keys of the material that do not name it keep it.
TEST(SceneFile, EmissionIsAKeyOfEitherMaterialKind) {
    json scene = minimal_scene();
    scene["objects"] = {{{"mesh", "sphere"}, {"material", {{"diffuse", 0.5}, {"emission", {2.0, 1.0, 0.0}}}}},
                        {{"mesh", "sphere"}, {"material", {{"roughness", 0.5}, {"emission", 3.0}}}},
                        {{"mesh", "sphere"}, {"material", {{"roughness", 0.5}}}}};
    const Scene s = load_scene(write_scene(test_folder(), scene));
    ASSERT_EQ(s.objects.size(), 3u);
    EXPECT_EQ(s.objects[0].material.emission, glm::vec3(2.0f, 1.0f, 0.0f));
    EXPECT_EQ(s.objects[0].material.rho_d, glm::vec3(0.5f));
    EXPECT_EQ(s.objects[1].material.emission, glm::vec3(3.0f));
    ASSERT_TRUE(s.objects[1].material.metallic_roughness);
    EXPECT_EQ(s.objects[2].material.emission, glm::vec3(0.0f));

    json negative = minimal_scene();
    negative["objects"][0]["material"] = {{"emission", {1.0, -1.0, 0.0}}};
    expect_scene_error_with(negative, {"objects[0].material.emission", "between 0 and 1e6"});
}

// A model of two materials (a triangle at x in [0, 1], another at x in [3, 4]) as two objects.
fs::path two_material_model(const fs::path& dir) {
    GltfWriter w;
    const int mesh = w.mesh(w.vec3s({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
    json second = w.doc["meshes"][mesh]["primitives"][0];
    second["attributes"]["POSITION"] = w.vec3s({{3, 0, 0}, {4, 0, 0}, {3, 1, 0}});
    second["material"] = 1;
    w.doc["meshes"][mesh]["primitives"][0]["material"] = 0;
    w.doc["meshes"][mesh]["primitives"].push_back(second);
    w.doc["materials"] = json::array(
        {{{"name", "red"}, {"pbrMetallicRoughness", {{"baseColorFactor", {1, 0, 0, 1}}, {"metallicFactor", 0}}}},
         {{"name", "steel"}, {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"roughnessFactor", 0.5}}}}});
    w.scene({w.node({{"mesh", mesh}})});
    return w.write(dir, "two");
}

TEST(SceneFile, AModelOfTwoMaterialsIsTwoObjectsThatTheSceneMaterialOverrides) {
    const fs::path dir = test_folder();
    two_material_model(dir);
    json scene = minimal_scene();
    scene["objects"] = {
        {{"model", "two.gltf"}, {"fit", 2.0}},
        {{"model", "two.gltf"}, {"name", "painted"}, {"material", {{"diffuse", 0.5}}}},
        {{"model", "two.gltf"}, {"material", {{"diffuse", 0.25}, {"specular", 0.1}, {"shininess", 7}}}}};
    const Scene s = load_scene(write_scene(dir, scene));
    ASSERT_EQ(s.objects.size(), 6u);
    EXPECT_EQ(s.objects[0].name, "two/red");
    EXPECT_EQ(s.objects[1].name, "two/steel");
    EXPECT_EQ(s.objects[2].name, "painted/red");
    // red: a rough dielectric, rho_d = 0.96 (1, 0, 0); steel: a metal (metallic 1 by default), rho_d = 0,
    // F0 = 1, n = 30, rho_s = 31 / 32.
    expect_near(s.objects[0].material.rho_d, {0.96f, 0.0f, 0.0f});
    expect_near(s.objects[1].material.rho_d, {0.0f, 0.0f, 0.0f});
    EXPECT_NEAR(s.objects[1].material.rho_s, 31.0f / 32.0f, 1e-6f);
    EXPECT_NEAR(s.objects[1].material.shininess, 30.0f, 1e-4f);
    // Both parts share one placement: the whole model (4 wide) fitted to 2 m, not each part alone.
    for (const std::size_t i : {0u, 1u}) EXPECT_EQ(s.objects[i].transform, s.objects[0].transform);
    glm::vec3 lo, hi;
    Scene first;
    first.objects = {s.objects[0], s.objects[1]};
    first.bounds_at(0.0, lo, hi);
    expect_near(lo, {-1.0f, 0.0f, 0.0f}, 1e-5f);
    expect_near(hi, {1.0f, 0.5f, 0.0f}, 1e-5f);
    // A partial override replaces its keys on every part.
    for (const std::size_t i : {2u, 3u}) expect_near(s.objects[i].material.rho_d, glm::vec3(0.5f));
    EXPECT_NEAR(s.objects[3].material.rho_s, 31.0f / 32.0f, 1e-6f);
    // A full one makes the parts alike.
    for (const std::size_t i : {4u, 5u}) {
        expect_near(s.objects[i].material.rho_d, glm::vec3(0.25f));
        EXPECT_EQ(s.objects[i].material.rho_s, 0.1f);
        EXPECT_EQ(s.objects[i].material.shininess, 7.0f);
    }
}

// An override of glTF's factors replaces those alone: the part's emission, alpha mask and occlusion
// strength stay (they are not the BRDF's).
TEST(SceneFile, AGltfFactorOverrideKeepsThePartsAlphaAndEmission) {
    const fs::path dir = test_folder();
    GltfWriter w;
    w.mesh(w.vec3s({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
    w.doc["meshes"][0]["primitives"][0]["material"] = 0;
    w.doc["materials"] = json::array({{{"name", "card"},
                                       {"alphaMode", "MASK"},
                                       {"alphaCutoff", 0.3},
                                       {"emissiveFactor", {0.5, 0.25, 0.0}},
                                       {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 0.2}}}}}});
    w.scene({w.node({{"mesh", 0}})});
    w.write(dir, "card");
    json scene = minimal_scene();
    scene["objects"] = {{{"model", "card.gltf"}, {"material", {{"roughness", 0.25}}}}};
    const Scene s = load_scene(write_scene(dir, scene));
    ASSERT_EQ(s.objects.size(), 1u);
    const Material& m = s.objects[0].material;
    ASSERT_TRUE(m.metallic_roughness);
    EXPECT_EQ(m.metallic_roughness->roughness, 0.25f);
    EXPECT_EQ(m.alpha_mode, AlphaMode::mask);
    EXPECT_EQ(m.alpha_cutoff, 0.3f);
    EXPECT_EQ(m.base_alpha, 0.2f);
    EXPECT_TRUE(m.masked());
    EXPECT_EQ(m.emission, glm::vec3(0.5f, 0.25f, 0.0f));
}

// A metallic or roughness given is the value seen: it replaces the metallic-roughness texture (which holds
// both), as base_color replaces the base-colour texture; a Phong material drops it, the emission keeps it.
TEST(SceneFile, AMetallicOrRoughnessOverrideReplacesTheParametersTexture) {
    const std::string bands = std::string(ENVSHADOW_SOURCE_DIR) + "/assets/models/roughness_bands.glb";
    const auto material_of = [&](const json& override) {
        json scene = minimal_scene();
        scene["objects"] = {{{"model", bands}}};
        if (!override.is_null()) scene["objects"][0]["material"] = override;
        const Scene s = load_scene(write_scene(test_folder(), scene));
        EXPECT_EQ(s.objects.size(), 1u);
        return s.objects.at(0).material;
    };
    EXPECT_TRUE(material_of(nullptr).metallic_roughness_texture.has_value());
    EXPECT_TRUE(material_of({{"base_color", 0.5}}).metallic_roughness_texture.has_value());
    const Material glowing = material_of({{"emission", 1.0}});
    EXPECT_TRUE(glowing.metallic_roughness_texture.has_value());
    EXPECT_TRUE(glowing.metallic_roughness.has_value());  // the emission alone leaves the BRDF glTF's
    const Material rough = material_of({{"roughness", 0.25}});
    EXPECT_FALSE(rough.metallic_roughness_texture.has_value());
    EXPECT_EQ(rough.metallic_roughness->roughness, 0.25f);
    EXPECT_FALSE(material_of({{"metallic", 0.0}}).metallic_roughness_texture.has_value());
    EXPECT_FALSE(material_of({{"diffuse", 0.5}}).metallic_roughness_texture.has_value());
}

TEST(SceneFile, ABareModelOfTwoMaterialsStandsOnTheGroundAsTwoObjects) {
    const Scene s = load_scene(two_material_model(test_folder()));
    ASSERT_EQ(s.objects.size(), 3u);
    EXPECT_EQ(s.objects[0].name, "ground");
    EXPECT_EQ(s.objects[1].name, "two/red");
    EXPECT_EQ(s.objects[2].name, "two/steel");
    expect_near(s.objects[1].material.rho_d, {0.96f, 0.0f, 0.0f});
    EXPECT_EQ(s.objects[1].transform, s.objects[2].transform);
}

TEST(SceneFile, IdenticalBuiltinMeshesAreShared) {
    json scene = minimal_scene();
    scene["objects"] = {{{"mesh", {{"type", "virus"}, {"spikes", 12}}}},
                        {{"mesh", {{"type", "virus"}, {"spikes", 12}}}},
                        {{"mesh", {{"type", "virus"}, {"spikes", 13}}}}};
    const Scene s = load_scene(write_scene(test_folder(), scene));
    EXPECT_EQ(s.objects[0].mesh, s.objects[1].mesh);
    EXPECT_NE(s.objects[0].mesh, s.objects[2].mesh);
}

TEST(SceneFile, WithoutACameraTheObjectsAreFramed) {
    json scene = minimal_scene();
    scene.erase("camera");
    scene["objects"] = {{{"mesh", {{"type", "plane"}, {"size", 50}}}, {"ground", true}},
                        {{"mesh", "figure"}, {"transform", {{"translation", {3, 0, -2}}}}},
                        {{"mesh", "box"}, {"transform", {{"translation", {-1, 0.5, 0}}}}}};
    const Scene s = load_scene(write_scene(test_folder(), scene));
    for (std::size_t i = 1; i < s.objects.size(); ++i) {
        Scene one;
        one.objects = {s.objects[i]};
        glm::vec3 lo, hi;
        one.bounds_at(0.0, lo, hi);
        EXPECT_TRUE(inside_frustum(s.camera, 4.0f / 3.0f, lo, hi)) << s.objects[i].name;
    }
}

TEST(SceneFile, UnknownKeysNameTheFileAndTheKey) {
    const auto with = [](const std::function<void(json&)>& change) {
        json scene = minimal_scene();
        change(scene);
        return scene;
    };
    expect_scene_error_with(with([](json& s) { s["objcts"] = json::array(); }), {"objcts: unknown key", "objects"});
    expect_scene_error_with(with([](json& s) { s["objects"][0]["materal"] = json::object(); }),
                            {"objects[0].materal: unknown key"});
    expect_scene_error_with(with([](json& s) {
                                s["objects"][0]["material"] = {{"shinyness", 3}};
                            }),
                            {"objects[0].material.shinyness: unknown key"});
    expect_scene_error_with(with([](json& s) { s["camera"]["fov_y"] = 30; }), {"camera.fov_y: unknown key"});
    expect_scene_error_with(with([](json& s) {
                                s["environment"] = {{"source", "builtin:sky"}, {"rotate", 3}};
                            }),
                            {"environment.rotate: unknown key"});
    expect_scene_error_with(with([](json& s) {
                                s["objects"][0]["mesh"] = {{"type", "sphere"}, {"radus", 1}};
                            }),
                            {"objects[0].mesh.radus: unknown key"});
    expect_scene_error_with(with([](json& s) {
                                s["objects"][0]["transform"] = {{"rotate", {0, 1, 0}}};
                            }),
                            {"objects[0].transform.rotate: unknown key"});
    expect_scene_error_with(with([](json& s) {
                                s["objects"][0]["animation"] = {{"type", "orbit"}, {"radious", 1}};
                            }),
                            {"objects[0].animation.radious: unknown key"});
}

TEST(SceneFile, WrongTypesNameTheFileAndTheKey) {
    const auto with = [](const std::function<void(json&)>& change) {
        json scene = minimal_scene();
        change(scene);
        return scene;
    };
    expect_scene_error_with(with([](json& s) {
                                s["objects"][0]["mesh"] = {{"type", "sphere"}, {"radius", "big"}};
                            }),
                            {"objects[0].mesh.radius: expected a number"});
    expect_scene_error_with(with([](json& s) {
                                s["objects"][0]["mesh"] = {{"type", "sphere"}, {"segments", 3.5}};
                            }),
                            {"objects[0].mesh.segments: expected an integer"});
    expect_scene_error_with(with([](json& s) {
                                s["camera"]["position"] = {0, 1};
                            }),
                            {"camera.position: expected an array of 3 numbers"});
    expect_scene_error_with(with([](json& s) { s["objects"] = json::object(); }),
                            {"objects: expected a non-empty array"});
    expect_scene_error_with(with([](json& s) { s["objects"][0]["ground"] = "yes"; }),
                            {"objects[0].ground: expected true or false"});
    expect_scene_error_with(with([](json& s) {
                                s["objects"][0]["material"] = {{"diffuse", {0.5, "red", 0.5}}};
                            }),
                            {"objects[0].material.diffuse[1]: expected a number"});
    expect_scene_error_with(with([](json& s) { s["environment"] = 3; }), {"environment: expected a map file"});
    expect_scene_error_with(with([](json& s) { s["objects"][0]["name"] = 7; }), {"objects[0].name: expected a string"});
    expect_scene_error_with(json::array(), {"scene: expected an object"});
}

TEST(SceneFile, ValuesOutOfRange) {
    const auto with = [](const std::function<void(json&)>& change) {
        json scene = minimal_scene();
        change(scene);
        return scene;
    };
    expect_scene_error_with(with([](json& s) {
                                s["objects"][0]["material"] = {{"diffuse", 1.5}};
                            }),
                            {"objects[0].material.diffuse", "between 0 and 1"});
    expect_scene_error_with(with([](json& s) {
                                s["objects"][0]["material"] = {{"shininess", -1}};
                            }),
                            {"objects[0].material.shininess"});
    expect_scene_error_with(with([](json& s) {
                                s["objects"][0]["mesh"] = {{"type", "sphere"}, {"segments", 5000}};
                            }),
                            {"segments", "between 4 and 3000"});
    expect_scene_error_with(
        with([](json& s) {
            s["objects"][0]["mesh"] = {{"type", "torus"}, {"major_radius", 0.2}, {"minor_radius", 0.3}};
        }),
        {"minor_radius: must be smaller than major_radius"});
    expect_scene_error_with(with([](json& s) {
                                s["objects"][0]["mesh"] = {{"type", "blob"}, {"triangles", 10}};
                            }),
                            {"objects[0].mesh.triangles"});
    expect_scene_error_with(with([](json& s) { s["objects"][0]["mesh"] = "teapot"; }),
                            {"unknown built-in mesh \"teapot\""});
    expect_scene_error_with(with([](json& s) {
                                s["objects"][0]["transform"] = {{"scale", {1, -1, 1}}};
                            }),
                            {"objects[0].transform.scale"});
    expect_scene_error_with(with([](json& s) { s["camera"]["fov"] = 0; }), {"camera.fov"});
    expect_scene_error_with(with([](json& s) { s["camera"]["target"] = s["camera"]["position"]; }),
                            {"camera: position and target are the same point"});
    expect_scene_error_with(with([](json& s) { s["camera"]["up"] = {0, 0, 0}; }), {"camera.up"});
    expect_scene_error_with(with([](json& s) {
                                s["objects"][0]["animation"] = {{"type", "orbit"}, {"period", 0}};
                            }),
                            {"objects[0].animation.period"});
    expect_scene_error_with(with([](json& s) {
                                s["objects"][0]["animation"] = {{"type", "path"}, {"points", {{0, 0, 0}}}};
                            }),
                            {"objects[0].animation.points"});
    expect_scene_error_with(with([](json& s) {
                                s["objects"][0]["animation"] = {{"type", "path"}, {"points", {{1, 0, 0}, {1, 0, 0}}}};
                            }),
                            {"the path has zero length"});
    expect_scene_error_with(with([](json& s) {
                                s["objects"][0]["animation"] = {{"type", "spin"}};
                            }),
                            {"unknown animation \"spin\""});
}

TEST(SceneFile, ObjectsNeedExactlyOneShape) {
    json scene = minimal_scene();
    scene["objects"] = {{{"name", "nothing"}}};
    expect_scene_error_with(scene, {"objects[0]: needs exactly one of \"model\""});
    scene["objects"] = {{{"mesh", "box"}, {"model", "x.glb"}}};
    expect_scene_error_with(scene, {"objects[0]: needs exactly one of \"model\""});
}

TEST(SceneFile, GroundRules) {
    json scene = minimal_scene();
    scene["objects"] = {{{"mesh", "sphere"}, {"ground", true}}};
    expect_scene_error_with(scene, {"objects[0].ground: only a plane mesh can be the ground"});
    scene["objects"] = {{{"mesh", "plane"}, {"ground", true}}, {{"mesh", "plane"}, {"ground", true}}};
    expect_scene_error_with(scene, {"objects[1].ground: only one object can be the ground"});
    scene["objects"] = {{{"mesh", "plane"}, {"ground", true}, {"transform", {{"rotation", {10, 0, 0}}}}}};
    expect_scene_error_with(scene, {"objects[0].ground: the ground plane must stay horizontal"});
    scene["objects"] = {
        {{"mesh", "plane"}, {"ground", true}, {"transform", {{"rotation", {0, 30, 0}}, {"translation", {0, 2, 0}}}}}};
    const Scene s = load_scene(write_scene(test_folder(), scene));
    EXPECT_TRUE(s.has_ground);
    EXPECT_EQ(s.ground_height, 2.0f);
    scene["objects"] = {{{"mesh", "plane"}}};
    EXPECT_FALSE(load_scene(write_scene(test_folder(), scene)).has_ground);
}

TEST(SceneFile, MissingFilesNameBothFiles) {
    const fs::path dir = test_folder();
    json scene = minimal_scene();
    scene["objects"] = {{{"model", "models/absent.glb"}}};
    const fs::path path = write_scene(dir, scene);
    expect_scene_error(path, {"objects[0].model", (dir / "models/absent.glb").string(), "not found"});

    scene = minimal_scene();
    scene["environment"] = {{"source", "../maps/absent.exr"}};
    const fs::path env = write_scene(dir, scene, "env.json");
    expect_scene_error(env, {"environment.source", (dir.parent_path() / "maps/absent.exr").string(), "not found"});
}

TEST(SceneFile, BrokenModelsNameBothFiles) {
    json scene = minimal_scene();
    const fs::path broken = "/usr/share/assimp/models/glTF2/RecursiveNodes/RecursiveNodes.gltf";
    scene["objects"] = {{{"model", broken.string()}}};
    const fs::path path = write_scene(test_folder(), scene);
    expect_scene_error(path, {"objects[0].model", broken.string() + ": node cycle"});
}

TEST(SceneFile, UnreadableSceneFiles) {
    const fs::path dir = test_folder();
    expect_scene_error(dir / "absent.json", {"no such scene file"});
    std::ofstream(dir / "broken.json") << "{ \"objects\": [ }";
    expect_scene_error(dir / "broken.json", {"invalid JSON", "line 1"});
    std::ofstream(dir / "overflow.json") << R"({"objects": [{"mesh": {"type": "sphere", "radius": 1e400}}]})";
    expect_scene_error(dir / "overflow.json", {"invalid JSON: number overflow"});
}

TEST(SceneFile, TheDocumentedExampleLoads) {
    std::ifstream doc(fs::path(ENVSHADOW_SOURCE_DIR) / "docs/SCENES.md");
    const std::string text((std::istreambuf_iterator<char>(doc)), std::istreambuf_iterator<char>());
    const std::size_t begin = text.find("```json\n");
    ASSERT_NE(begin, std::string::npos);
    const std::size_t end = text.find("```", begin + 8);
    const fs::path path = test_folder() / "example.json";
    std::ofstream(path) << text.substr(begin + 8, end - begin - 8);
    const Scene s = load_scene(path);
    EXPECT_EQ(s.objects.size(), 4u + 7u);  // the engine model is one object per material (7)
    EXPECT_TRUE(s.has_ground);
    EXPECT_EQ(s.objects.back().animation.kind, Animation::Kind::orbit);
}

TEST(SceneFile, BareGlbStandsOnAGroundPlaneInView) {
    const Scene s = load_scene(kEngine);
    EXPECT_TRUE(s.has_ground);
    EXPECT_EQ(s.ground_height, 0.0f);
    ASSERT_EQ(s.objects.size(), 1u + 7u);  // the ground, then one object per material
    const Object& ground = s.objects[0];
    EXPECT_FALSE(ground.casts_shadows);
    Scene only_model;
    std::size_t triangles = 0;
    for (std::size_t i = 1; i < s.objects.size(); ++i) {
        const Object& part = s.objects[i];
        EXPECT_TRUE(part.casts_shadows);
        EXPECT_EQ(part.name.rfind("2CylinderEngine/Material_", 0), 0u) << part.name;
        EXPECT_EQ(part.transform, s.objects[1].transform);
        triangles += part.mesh->triangle_count();
        only_model.objects.push_back(part);
    }
    EXPECT_EQ(triangles, 121496u);
    glm::vec3 lo, hi;
    only_model.bounds_at(0.0, lo, hi);
    EXPECT_NEAR(lo.y, 0.0f, 1e-4f);  // standing on the ground
    EXPECT_NEAR(std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}), 2.0f, 1e-4f);
    for (const float aspect : {1.0f, 4.0f / 3.0f, 16.0f / 9.0f})
        EXPECT_TRUE(inside_frustum(s.camera, aspect, lo, hi)) << aspect;
    // The ground reaches well past the model, to catch its shadows.
    EXPECT_GT(ground.mesh->bounds_max.x, 5.0f * std::max(std::abs(lo.x), std::abs(hi.x)));

    const fs::path courtyard = "/usr/share/blender/datafiles/studiolights/world/courtyard.exr";
    EXPECT_EQ(s.environment.source, fs::exists(courtyard) ? courtyard.string() : std::string("builtin:sky"));
}

TEST(SceneFile, BareGltfErrorsNameTheModel) {
    const fs::path broken = "/usr/share/assimp/models/glTF2/IndexOutOfRange/IndexOutOfRange.gltf";
    expect_scene_error(broken, {"out of range"});
}

}  // namespace
}  // namespace envshadow
