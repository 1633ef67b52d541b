// The scenes shipped in assets/scenes/: each loads, shows what its figure in the paper needs, and
// keeps every object in view, above the ground and within the triangle budget.
#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "scene/meshes.h"
#include "scene/scene.h"

namespace envshadow {
namespace {

namespace fs = std::filesystem;

const fs::path kScenes = fs::path(ENVSHADOW_SOURCE_DIR) / "assets/scenes";

std::vector<fs::path> scene_files() {
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(kScenes))
        if (entry.path().extension() == ".json") files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    return files;
}

// Tight world bounds of the vertices (Scene::bounds_at boxes the object-space box, looser when rotated).
void object_bounds(const Object& o, double t, glm::vec3& lo, glm::vec3& hi) {
    const glm::mat4 world_from_object = o.world_from_object(t);
    lo = glm::vec3(1e30f);
    hi = glm::vec3(-1e30f);
    for (const glm::vec3& p : o.mesh->positions) {
        const glm::vec3 w(world_from_object * glm::vec4(p, 1.0f));
        lo = glm::min(lo, w);
        hi = glm::max(hi, w);
    }
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

const Object& named(const Scene& s, const std::string& name) {
    for (const Object& o : s.objects)
        if (o.name == name) return o;
    throw std::runtime_error("no object named " + name + " in " + s.file.string());
}

std::vector<double> sample_times() {
    std::vector<double> times;
    for (int i = 0; i < 96; ++i) times.push_back(0.25 * i);  // 24 s: every period used here, and more
    return times;
}

TEST(SceneAssets, TheExpectedScenesAreThere) {
    std::set<std::string> names;
    for (const fs::path& f : scene_files()) names.insert(f.stem().string());
    for (const char* expected : {"default", "spheres", "flyover", "flyover_single", "viruses", "engine"})
        EXPECT_TRUE(names.count(expected)) << expected << ".json is missing";
}

TEST(SceneAssets, EverySceneLoadsAndKeepsItsObjectsInViewAboveTheGround) {
    for (const fs::path& file : scene_files()) {
        SCOPED_TRACE(file.string());
        const Scene s = load_scene(file);
        EXPECT_TRUE(s.has_ground);
        EXPECT_LT(s.triangle_count(), 200'000u);
        EXPECT_TRUE(fs::is_regular_file(s.environment.source)) << s.environment.source;

        const Object* ground = nullptr;
        for (const Object& o : s.objects)
            if (o.mesh->triangle_count() == 2 && !o.casts_shadows) ground = &o;
        ASSERT_NE(ground, nullptr);
        glm::vec3 ground_lo, ground_hi;
        object_bounds(*ground, 0.0, ground_lo, ground_hi);
        EXPECT_FLOAT_EQ(ground_lo.y, s.ground_height);

        glm::vec3 all_lo(1e9f), all_hi(-1e9f);
        for (const Object& o : s.objects) {
            if (&o == ground) continue;
            EXPECT_TRUE(o.casts_shadows) << o.name;
            for (const double t : sample_times()) {
                glm::vec3 lo, hi;
                object_bounds(o, t, lo, hi);
                all_lo = glm::min(all_lo, lo);
                all_hi = glm::max(all_hi, hi);
                EXPECT_GE(lo.y, s.ground_height - 1e-3f) << o.name << " below the ground at t = " << t;
                // The regression screenshots are 4:3; the viewer is usually wider.
                EXPECT_TRUE(inside_frustum(s.camera, 4.0f / 3.0f, lo, hi)) << o.name << " out of view at t = " << t;
                EXPECT_TRUE(inside_frustum(s.camera, 16.0f / 9.0f, lo, hi)) << o.name << " out of view at t = " << t;
                if (o.animation.kind == Animation::Kind::none) break;
            }
        }
        // Room on the ground for shadows: at least three times the objects' footprint each way.
        const glm::vec3 centre = 0.5f * (all_lo + all_hi);
        const float reach = std::max(all_hi.x - all_lo.x, all_hi.z - all_lo.z);
        EXPECT_LE(ground_lo.x, centre.x - 1.5f * reach);
        EXPECT_GE(ground_hi.x, centre.x + 1.5f * reach);
        EXPECT_LE(ground_lo.z, centre.z - 1.5f * reach);
        EXPECT_GE(ground_hi.z, centre.z + 1.5f * reach);
    }
}

TEST(SceneAssets, SpheresRiseInShininessFromOneToOneThousand) {
    const Scene s = load_scene(kScenes / "spheres.json");
    std::vector<float> shininess;
    for (const Object& o : s.objects) {
        if (o.name == "ground") continue;
        EXPECT_EQ(o.mesh->triangle_count(), 2u * 64 * 31) << o.name;  // 64-segment spheres
        EXPECT_GT(o.material.rho_s, 0.0f);
        shininess.push_back(o.material.shininess);
    }
    ASSERT_GE(shininess.size(), 5u);
    ASSERT_LE(shininess.size(), 7u);
    EXPECT_EQ(shininess.front(), 1.0f);
    EXPECT_EQ(shininess.back(), 1000.0f);
    EXPECT_TRUE(std::is_sorted(shininess.begin(), shininess.end()));
    EXPECT_TRUE(std::count(shininess.begin(), shininess.end(), 100.0f));  // the paper's Fig. 7 value
}

// roughness_bands.glb as Blender's exporter wrote it (scripts/blender-roughness.py): one material whose
// metallicRoughnessTexture, data read as stored, gives smooth and rough bands, metal above and not below.
TEST(SceneAssets, RoughnessBandsCarryBlendersMetallicRoughnessTexture) {
    const Scene s = load_scene(kScenes / "roughness_bands.json");
    std::vector<const Material*> textured;
    for (const Object& o : s.objects)
        if (o.material.metallic_roughness_texture) textured.push_back(&o.material);
    ASSERT_EQ(textured.size(), 1u);
    const Material& m = *textured[0];
    ASSERT_TRUE(m.metallic_roughness.has_value());
    EXPECT_EQ(m.metallic_roughness->roughness, 1.0f);  // the texture alone: the factors at glTF's default
    EXPECT_EQ(m.metallic_roughness->metallic, 1.0f);
    EXPECT_FALSE(m.metallic_roughness_texture->srgb);
    EXPECT_TRUE(m.metallic_roughness_texture->nearest);
    const TextureImage& image = *m.metallic_roughness_texture->image;
    std::set<int> roughness, metalness;
    for (std::size_t i = 0; i + 3 < image.rgba.size(); i += 4) {
        roughness.insert(image.rgba[i + 1]);
        metalness.insert(image.rgba[i + 2]);
    }
    EXPECT_EQ(roughness, (std::set<int>{20, 153}));  // 0.08 and 0.6
    EXPECT_EQ(metalness, (std::set<int>{0, 255}));
}

// normal_panel.glb as Blender's exporter wrote it (scripts/blender-normal-panel.py): a normalTexture, data read
// as stored, with the mesh's own tangents: u along +x, the image's up along -z (w = +1), as the loader makes
// them too.
TEST(SceneAssets, NormalPanelCarriesBlendersNormalMapAndTangents) {
    const Scene s = load_scene(kScenes / "normal_panel.json");
    const Object& panel = named(s, "panel");
    const Material& m = panel.material;
    ASSERT_TRUE(m.normal_texture.has_value());
    EXPECT_FALSE(m.normal_texture->srgb);
    EXPECT_EQ(m.normal_scale, 1.0f);
    ASSERT_EQ(panel.mesh->tangents.size(), panel.mesh->positions.size());
    for (const glm::vec4& t : panel.mesh->tangents) EXPECT_LT(glm::distance(t, glm::vec4(1, 0, 0, 1)), 1e-6f);
    Mesh made = *panel.mesh;
    compute_vertex_tangents(made);
    EXPECT_EQ(made.tangents, panel.mesh->tangents);
    // The flat field between the domes is (0, 0, 1): texel (128, 128, 255); every texel faces outwards.
    const TextureImage& image = *m.normal_texture->image;
    std::size_t flat = 0;
    for (std::size_t i = 0; i + 3 < image.rgba.size(); i += 4) {
        flat += image.rgba[i] == 128 && image.rgba[i + 1] == 128 && image.rgba[i + 2] == 255;
        EXPECT_GT(image.rgba[i + 2], 128);
    }
    EXPECT_GT(flat, image.rgba.size() / 4 / 3);
}

// emissive_sphere.glb as Blender's exporter wrote it (scripts/blender-emissive.py): Emission (1, 0.45, 0.1) at a
// strength of 2, as emissiveFactor times KHR_materials_emissive_strength.
TEST(SceneAssets, EmissiveSphereCarriesBlendersEmissionStrength) {
    const Scene s = load_scene(kScenes / "emissive_sphere.json");
    const Material& m = named(s, "sphere").material;
    EXPECT_LT(glm::distance(m.emission, glm::vec3(2.0f, 0.9f, 0.2f)), 1e-6f);
    EXPECT_FALSE(m.emission_texture.has_value());
    ASSERT_TRUE(m.metallic_roughness.has_value());
    EXPECT_LT(glm::distance(m.metallic_roughness->base_color, glm::vec3(0.1f)), 1e-6f);
}

// glass_pane.glb as Blender's exporter wrote it (scripts/blender-glass.py): Alpha Blend, the alpha in the
// base-colour texture: 1 on the frame, 0.3 on the glass.
TEST(SceneAssets, GlassPaneIsBlendedByItsTexturesAlpha) {
    const Scene s = load_scene(kScenes / "glass_pane.json");
    const Material& m = named(s, "pane").material;
    EXPECT_EQ(m.alpha_mode, AlphaMode::blend);
    EXPECT_TRUE(m.blended());
    ASSERT_TRUE(m.base_color_texture.has_value());
    const TextureImage& image = *m.base_color_texture->image;
    int glass = 0, frame = 0;
    for (std::size_t i = 3; i < image.rgba.size(); i += 4) {
        glass += std::abs(int(image.rgba[i]) - 77) <= 1;  // 0.3 of 255
        frame += image.rgba[i] == 255;
    }
    EXPECT_EQ(glass + frame, image.width * image.height);
    EXPECT_GT(glass, 2 * frame);
}

TEST(SceneAssets, FlyoverFiguresAreFifteenThousandTrianglesEach) {
    const Scene two = load_scene(kScenes / "flyover.json");
    const Scene one = load_scene(kScenes / "flyover_single.json");
    ASSERT_EQ(two.objects.size(), 3u);
    ASSERT_EQ(one.objects.size(), 2u);
    const Object& standing = named(two, "standing figure");
    const Object& flying = named(two, "flying figure");
    // Paper Table 1: "A single Armadillo character consists of 15000 triangles".
    EXPECT_NEAR(double(standing.mesh->triangle_count()), 15000.0, 300.0);
    EXPECT_EQ(flying.mesh->triangle_count(), standing.mesh->triangle_count());
    EXPECT_NEAR(double(two.triangle_count()), 30000.0, 600.0);
    // The one-figure scene is the same figure in the same place under the same light and camera.
    const Object& alone = named(one, "standing figure");
    EXPECT_EQ(alone.mesh->triangle_count(), standing.mesh->triangle_count());
    EXPECT_EQ(alone.transform, standing.transform);
    EXPECT_EQ(one.environment.source, two.environment.source);
    EXPECT_EQ(one.environment.rotation_degrees, two.environment.rotation_degrees);
    EXPECT_EQ(one.camera.position, two.camera.position);
    EXPECT_EQ(one.triangle_count(), two.triangle_count() - flying.mesh->triangle_count());
}

TEST(SceneAssets, FlyoverFigureFliesOverTheStandingOneAndLoops) {
    const Scene s = load_scene(kScenes / "flyover.json");
    const Object& standing = named(s, "standing figure");
    const Object& flying = named(s, "flying figure");
    EXPECT_EQ(standing.animation.kind, Animation::Kind::none);
    ASSERT_NE(flying.animation.kind, Animation::Kind::none);
    const double period = flying.animation.period;

    const auto centre_at = [&](double t) { return glm::vec3(flying.world_from_object(t) * glm::vec4(0, 0.9f, 0, 1)); };
    EXPECT_GT(glm::distance(centre_at(0.0), centre_at(1.0)), 0.5f);  // it moves
    for (const double t : {0.0, 0.7, 3.1})
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r)
                EXPECT_NEAR(flying.world_from_object(t)[c][r], flying.world_from_object(t + period)[c][r], 1e-4f);

    glm::vec3 standing_lo, standing_hi;
    object_bounds(standing, 0.0, standing_lo, standing_hi);
    float closest = 1e9f;
    for (double t = 0.0; t < period; t += period / 64) {
        glm::vec3 lo, hi;
        object_bounds(flying, t, lo, hi);
        EXPECT_GT(lo.y, standing_hi.y) << "the flyer hits the standing figure at t = " << t;
        const glm::vec3 c = centre_at(t);
        closest = std::min(closest, glm::length(glm::vec2(c.x, c.z)));
    }
    // Close enough overhead that, with the sun 48 degrees up, its shadow crosses the standing figure.
    EXPECT_LT(closest, 2.0f);
}

TEST(SceneAssets, VirusesAreSeveralSpikyBalls) {
    const Scene s = load_scene(kScenes / "viruses.json");
    int viruses = 0;
    for (const Object& o : s.objects)
        if (o.name.rfind("virus", 0) == 0) ++viruses;
    EXPECT_GE(viruses, 4);
    EXPECT_EQ(viruses + 1, int(s.objects.size()));
}

TEST(SceneAssets, EngineIsTheAssimpModelAtAHumanScale) {
    const Scene s = load_scene(kScenes / "engine.json");
    // One object per distinct material (7, tests/scene/gltf_material_test.cpp), named engine/<material>,
    // each with its own colour and the scene's specular 0.2 and shininess 40.
    std::size_t triangles = 0, parts = 0;
    std::set<std::tuple<float, float, float>> colours;
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (const Object& o : s.objects) {
        if (o.name.rfind("engine/", 0) != 0) continue;
        ++parts;
        triangles += o.mesh->triangle_count();
        colours.insert({o.material.rho_d.r, o.material.rho_d.g, o.material.rho_d.b});
        EXPECT_EQ(o.material.rho_s, 0.2f) << o.name;
        EXPECT_EQ(o.material.shininess, 40.0f) << o.name;
        glm::vec3 part_lo, part_hi;
        object_bounds(o, 0.0, part_lo, part_hi);
        lo = glm::min(lo, part_lo);
        hi = glm::max(hi, part_hi);
    }
    EXPECT_EQ(parts, 7u);
    EXPECT_EQ(colours.size(), 7u);
    EXPECT_EQ(triangles, 121496u);  // 75,730 stored, some parts instanced
    EXPECT_NEAR(std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}), 0.75f, 1e-3f);
    EXPECT_NEAR(lo.y, s.ground_height, 1e-4f);
}

TEST(SceneAssets, DefaultSceneHasSeveralMaterials) {
    const Scene s = load_scene(kScenes / "default.json");
    std::set<std::tuple<float, float, float, float, float>> materials;
    for (const Object& o : s.objects)
        materials.insert(
            {o.material.rho_d.r, o.material.rho_d.g, o.material.rho_d.b, o.material.rho_s, o.material.shininess});
    EXPECT_GE(s.objects.size(), 4u);
    EXPECT_EQ(materials.size(), s.objects.size());
}

}  // namespace
}  // namespace envshadow
