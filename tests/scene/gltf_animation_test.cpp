// glTF animation (scene/gltf_animation.h, docs/SCENES.md "Animation"): the three interpolations worked
// out by hand, a node-animated box that moves and loops (or stops), a two-bone skin whose tip turns
// about its joint, the real simple_skin and AnimatedMorphCube models posed at two times, and the bad
// inputs docs/ROBUSTNESS.md lists (joints past the skin, weights that are not numbers, keys out of order, outputs of
// the wrong type), each a one-line InputError naming the file.
#include <cmath>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>

#include "core/error.h"
#include "gltf_writer.h"
#include "scene/gltf.h"
#include "scene/gltf_animation.h"
#include "scene/scene.h"

namespace envshadow {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::GltfWriter;
using test::test_folder;

const fs::path& kModels = test::kAssimpModels;

void expect_input_error(const fs::path& file, const std::string& expected) {
    test::expect_one_line_error(file, expected, load_scene);
}

GltfSampler two_keys(GltfInterpolation interpolation, std::vector<float> output, int components = 1) {
    GltfSampler s;
    s.interpolation = interpolation;
    s.input = {0.0f, 1.0f};
    s.output = std::move(output);
    s.components = components;
    return s;
}

float at(const GltfSampler& s, double t) {
    float v = NAN;
    s.sample(t, false, &v);
    return v;
}

TEST(GltfSampler, StepLinearAndCubicSplineBetweenTwoKeys) {
    EXPECT_FLOAT_EQ(at(two_keys(GltfInterpolation::step, {0, 10}), 0.75), 0.0f);
    EXPECT_FLOAT_EQ(at(two_keys(GltfInterpolation::linear, {0, 10}), 0.25), 2.5f);
    // Cubic: in-tangent, value, out-tangent per key. Flat tangents: the Hermite midpoint is the mean;
    // key 0's out-tangent 4 adds h10(0.5) * 1 s * 4 = 0.125 * 4.
    EXPECT_FLOAT_EQ(at(two_keys(GltfInterpolation::cubic_spline, {0, 0, 0, 0, 10, 0}), 0.5), 5.0f);
    EXPECT_FLOAT_EQ(at(two_keys(GltfInterpolation::cubic_spline, {0, 0, 4, 0, 10, 0}), 0.5), 5.5f);
    // Before the first key and after the last: the end values.
    EXPECT_FLOAT_EQ(at(two_keys(GltfInterpolation::linear, {0, 10}), -1.0), 0.0f);
    EXPECT_FLOAT_EQ(at(two_keys(GltfInterpolation::linear, {0, 10}), 7.0), 10.0f);
}

TEST(GltfSampler, RotationsSlerpAlongTheShortestArc) {
    // Identity to 90 degrees about +Y (x, y, z, w): half way is 45 degrees about +Y.
    const float s45 = std::sin(glm::quarter_pi<float>() / 2), c45 = std::cos(glm::quarter_pi<float>() / 2);
    const GltfSampler s =
        two_keys(GltfInterpolation::linear,
                 {0, 0, 0, 1, 0, std::sin(glm::quarter_pi<float>()), 0, std::cos(glm::quarter_pi<float>())}, 4);
    float q[4];
    s.sample(0.5, true, q);
    EXPECT_NEAR(q[0], 0.0f, 1e-6f);
    EXPECT_NEAR(q[1], s45, 1e-6f);
    EXPECT_NEAR(q[2], 0.0f, 1e-6f);
    EXPECT_NEAR(q[3], c45, 1e-6f);
}

// A unit triangle on node 0, translated by an animation from x = 0 at t = 0 to x = 2 at t = 2.
struct AnimatedTriangle {
    GltfWriter writer;
    fs::path folder = test_folder();
    AnimatedTriangle() {
        const int p = writer.vec3s({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
        writer.mesh(p);
        writer.node({{"mesh", 0}});
        writer.scene({0});
        const std::vector<float> times{0.0f, 2.0f};
        const int input = writer.accessor(writer.view(times.data(), 8), 5126, 2, "SCALAR");
        const int output = writer.vec3s({{0, 0, 0}, {2, 0, 0}});
        writer.doc["animations"] = json::array(
            {{{"name", "slide"},
              {"samplers", json::array({{{"input", input}, {"output", output}, {"interpolation", "LINEAR"}}})},
              {"channels", json::array({{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}})}}});
    }
    // A scene with the model (no fit, so its space is the world's) and the given "animation" value.
    fs::path scene(const json& animation) {
        writer.write(folder, "triangle");
        json object = {{"model", "triangle.gltf"}};
        if (!animation.is_null()) object["animation"] = animation;
        const fs::path path = folder / "scene.json";
        std::ofstream(path) << json({{"objects", json::array({object})}}).dump();
        return path;
    }
};

float x_at(const Scene& scene, double t) {
    return (scene.objects.at(0).world_from_object(t) * glm::vec4(0, 0, 0, 1)).x;
}

TEST(GltfAnimation, NodeTranslationMovesTheObjectAndLoops) {
    AnimatedTriangle model;
    const Scene scene = load_scene(model.scene(nullptr));  // a model plays its first animation, looped
    ASSERT_EQ(scene.objects.size(), 1u);
    EXPECT_TRUE(scene.objects[0].moves());
    EXPECT_FALSE(scene.objects[0].deforms());  // one node, no skin or morph: it moves whole
    EXPECT_NEAR(x_at(scene, 0.0), 0.0f, 1e-6f);
    EXPECT_NEAR(x_at(scene, 1.0), 1.0f, 1e-6f);
    EXPECT_NEAR(x_at(scene, 3.0), 1.0f, 1e-6f);  // 3 s is 1 s into the second loop
    EXPECT_NEAR(scene.objects[0].motion_period(), 2.0, 1e-9);
}

TEST(GltfAnimation, AClipPickedByNameOrIndexAndPlayedOnceOrNotAtAll) {
    AnimatedTriangle model;
    EXPECT_NEAR(x_at(load_scene(model.scene(json{{"clip", "slide"}, {"loop", false}})), 3.0), 2.0f, 1e-6f);
    EXPECT_NEAR(x_at(load_scene(model.scene(0)), 1.5), 1.5f, 1e-6f);
    const Scene still = load_scene(model.scene(false));
    EXPECT_FALSE(still.objects[0].moves());
    EXPECT_NEAR(x_at(still, 1.0), 0.0f, 1e-6f);
    expect_input_error(model.scene("walk"), "no animation named \"walk\" (the model has \"slide\")");
    expect_input_error(model.scene(3), "clip 3 does not exist");
}

// Two joints up +Y: joint 0 at the origin, joint 1 at y = 1 (its child). A strip of two quads from
// y = 0 to y = 2; the top vertices follow joint 1 alone, the middle half each, the bottom joint 0.
// Joint 1 turns 90 degrees about +Z over 1 s.
struct TwoBoneSkin {
    GltfWriter writer;
    fs::path folder = test_folder();
    TwoBoneSkin(float top_weight = 1.0f, std::uint16_t top_joint = 1) {
        const int p = writer.vec3s({{0, 0, 0}, {0.2f, 0, 0}, {0, 1, 0}, {0.2f, 1, 0}, {0, 2, 0}, {0.2f, 2, 0}});
        const int i = writer.indices({0, 1, 3, 0, 3, 2, 2, 3, 5, 2, 5, 4});
        const std::vector<std::uint16_t> joints{0, 0, 0, 0, 0,         0, 0, 0, 0,         1, 0, 0,
                                                0, 1, 0, 0, top_joint, 0, 0, 0, top_joint, 0, 0, 0};
        const std::vector<float> weights{1,    0,    0, 0, 1,          0, 0, 0, 0.5f,       0.5f, 0, 0,
                                         0.5f, 0.5f, 0, 0, top_weight, 0, 0, 0, top_weight, 0,    0, 0};
        const int j = writer.accessor(writer.view(joints.data(), joints.size() * 2), 5123, 6, "VEC4");
        const int w = writer.accessor(writer.view(weights.data(), weights.size() * 4), 5126, 6, "VEC4");
        writer.mesh(p, i);
        writer.doc["meshes"][0]["primitives"][0]["attributes"]["JOINTS_0"] = j;
        writer.doc["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_0"] = w;
        // Inverse bind matrices: joint 0 at the origin (identity), joint 1 at y = 1 (translate by -1).
        const std::vector<float> ibm{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0,  0, 1,
                                     1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1};
        const int inverse_bind = writer.accessor(writer.view(ibm.data(), ibm.size() * 4), 5126, 2, "MAT4");
        writer.node({{"mesh", 0}, {"skin", 0}});    // 0: the skinned mesh
        writer.node({{"children", {2}}});           // 1: joint 0
        writer.node({{"translation", {0, 1, 0}}});  // 2: joint 1
        writer.doc["skins"] = json::array({{{"joints", {1, 2}}, {"inverseBindMatrices", inverse_bind}}});
        writer.scene({0, 1});
        const std::vector<float> times{0.0f, 1.0f};
        const float s = std::sin(glm::quarter_pi<float>()), c = std::cos(glm::quarter_pi<float>());
        const std::vector<float> turns{0, 0, 0, 1, 0, 0, s, c};  // identity, then 90 degrees about +Z
        const int input = writer.accessor(writer.view(times.data(), 8), 5126, 2, "SCALAR");
        const int output = writer.accessor(writer.view(turns.data(), 32), 5126, 2, "VEC4");
        writer.doc["animations"] = json::array(
            {{{"samplers", json::array({{{"input", input}, {"output", output}}})},
              {"channels", json::array({{{"sampler", 0}, {"target", {{"node", 2}, {"path", "rotation"}}}}})}}});
    }
    fs::path write() { return writer.write(folder, "skin"); }
};

TEST(GltfAnimation, TwoBoneSkinTurnsItsTipAboutTheJoint) {
    TwoBoneSkin model;
    const Scene scene = load_scene(model.write());  // a bare model: fitted and stood on the ground
    ASSERT_EQ(scene.objects.size(), 2u);            // the ground and the skin
    const Object& skin = scene.objects[1];
    ASSERT_TRUE(skin.deforms());
    // Half way through the 1 s clip (1 s itself is the start of the next loop): 45 degrees.
    const std::shared_ptr<const Mesh> rest = skin.mesh_at(0.0), turned = skin.mesh_at(0.5);
    ASSERT_EQ(turned->positions.size(), 6u);
    // Model space: the top vertex (0, 2, 0) goes round joint 1 at (0, 1, 0) by 45 degrees about +Z to
    // (-0.71, 1.71, 0); the bottom ones stay. The fit scales and moves the model: compare in world.
    const glm::mat4 world = skin.world_from_object(0.5);
    const glm::mat4 rest_world = skin.world_from_object(0.0);
    const auto world_of = [](const glm::mat4& m, const glm::vec3& p) { return glm::vec3(m * glm::vec4(p, 1)); };
    // The fit maps model (0, 2, 0) - (0, 1, 0) to a world offset; the same affine map applies to both.
    // The loader keeps vertices in the order the triangles first use them: find them by their rest place.
    const auto vertex = [&](const glm::vec3& p) {
        for (std::size_t v = 0; v < rest->positions.size(); ++v)
            if (glm::distance(rest->positions[v], p) < 1e-6f) return v;
        ADD_FAILURE() << "no vertex at rest at " << p.x << " " << p.y << " " << p.z;
        return std::size_t(0);
    };
    const std::size_t middle = vertex({0, 1, 0}), top = vertex({0, 2, 0}), bottom = vertex({0, 0, 0});
    const glm::vec3 joint = world_of(rest_world, rest->positions[middle]);
    const glm::vec3 tip_rest = world_of(rest_world, rest->positions[top]) - joint;
    const glm::vec3 tip_turned = world_of(world, turned->positions[top]) - joint;
    EXPECT_NEAR(glm::distance(world_of(world, turned->positions[middle]), joint), 0.0f, 1e-5f);  // on the joint
    EXPECT_NEAR(glm::length(tip_turned), glm::length(tip_rest), 1e-4f);
    EXPECT_NEAR(glm::dot(tip_turned, tip_rest) / glm::dot(tip_rest, tip_rest), std::sqrt(0.5f), 1e-4f);
    EXPECT_LT(tip_turned.x, 0.0f);  // counter-clockwise about +Z: to -X
    EXPECT_NEAR(
        glm::distance(world_of(world, turned->positions[bottom]), world_of(rest_world, rest->positions[bottom])), 0.0f,
        1e-5f);
    EXPECT_GT(turned->bounds_max.x - turned->bounds_min.x, rest->bounds_max.x - rest->bounds_min.x + 0.4f);
}

TEST(GltfAnimation, SimpleSkinAndMorphCubeChangeShapeOverTime) {
    for (const char* file :
         {"simple_skin/simple_skin.gltf", "glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf"}) {
        SCOPED_TRACE(file);
        const Scene scene = load_scene(kModels / file);
        const Object& model = scene.objects.back();
        ASSERT_TRUE(model.deforms());
        const std::shared_ptr<const Mesh> a = model.mesh_at(0.0), b = model.mesh_at(1.0);
        ASSERT_EQ(a->positions.size(), b->positions.size());
        float moved = 0.0f;
        for (std::size_t v = 0; v < a->positions.size(); ++v)
            moved = std::max(moved, glm::distance(a->positions[v], b->positions[v]));
        const float size = glm::distance(a->bounds_min, a->bounds_max);
        EXPECT_GT(moved, 0.05f * size);
        EXPECT_EQ(a->indices, b->indices);
        for (const glm::vec3& n : b->normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-4f);
    }
}

TEST(GltfAnimationMalformed, JointPastTheSkin) {
    TwoBoneSkin model(1.0f, 7);
    expect_input_error(model.write(), "is joint 7, past skin 0's 2 joints");
}

TEST(GltfAnimationMalformed, WeightThatIsNotANumber) {
    TwoBoneSkin model(NAN);
    expect_input_error(model.write(), "WEIGHTS_0 (accessor 3) element 4 is not finite");
}

TEST(GltfAnimationMalformed, KeysThatDoNotIncrease) {
    AnimatedTriangle model;
    const float backwards[2] = {2.0f, 1.0f};
    // The times' view follows the three positions (36 bytes).
    std::memcpy(&model.writer.bin[36], backwards, 8);
    expect_input_error(model.scene(nullptr), "animation 0 sampler 0 input is not increasing");
}

TEST(GltfAnimationMalformed, OutputOfTheWrongType) {
    AnimatedTriangle model;
    model.writer.doc["accessors"][2]["type"] = "VEC2";
    expect_input_error(model.scene(nullptr), "animation 0 sampler 0 output");
}

}  // namespace
}  // namespace envshadow
