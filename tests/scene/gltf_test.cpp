#include "scene/gltf.h"

#include <cmath>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "core/error.h"
#include "gltf_writer.h"
#include "mesh_checks.h"
#include "scene/meshes.h"

namespace envshadow {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::GltfWriter;
using test::test_folder;

const fs::path& kModels = test::kAssimpModels;

// The mesh of a model with one material (one part).
const Mesh& only_part(const GltfModel& model) {
    EXPECT_EQ(model.parts.size(), 1u);
    return *model.parts.at(0).mesh;
}

bool contains_point(const Mesh& m, const glm::vec3& p, float tolerance = 1e-5f) {
    for (const glm::vec3& q : m.positions)
        if (glm::distance(p, q) <= tolerance) return true;
    return false;
}

// The error is one line: "<file>: <reason>", and the reason mentions `expected`.
void expect_input_error(const fs::path& file, const std::string& expected) {
    test::expect_one_line_error(file, expected, load_gltf);
}

TEST(SceneGltf, EngineNodeTransformsGiveTheIndependentlyComputedBounds) {
    const GltfModel model = load_gltf(kModels / "2CylinderEngine-glTF-Binary/2CylinderEngine.glb");
    // From tests/scene/tools/gltf_world_bounds.py (plain Python over the .glb): 29 meshes, several
    // instanced by more than one node (75,730 triangles stored, 121,496 in the scene).
    EXPECT_EQ(model.triangle_count(), 121496u);
    const glm::vec3 lo(-371.6923f, -180.9716f, -140.0f), hi(371.6922f, 92.0416f, 128.0f);
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(model.bounds_min[k], lo[k], 1e-3f) << "axis " << k;
        EXPECT_NEAR(model.bounds_max[k], hi[k], 1e-3f) << "axis " << k;
    }
    for (const GltfPart& part : model.parts) EXPECT_LT(test::worst_normal_length_error(*part.mesh), 1e-5);
}

TEST(SceneGltf, TrsParentAndMatrixChildCompose) {
    GltfWriter w;
    const int mesh = w.mesh(w.vec3s({{0, 0, 0}, {1, 0, 0}, {0, 0, 1}}), w.indices({0, 1, 2}));
    const int child =
        w.node({{"mesh", mesh}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 1, 0, 1}}});  // +1 in y
    const float h = std::sqrt(0.5f);
    const int parent =
        w.node({{"children", {child}}, {"translation", {10, 0, 0}}, {"rotation", {0, h, 0, h}}, {"scale", {2, 2, 2}}});
    w.scene({parent});
    const GltfModel model = load_gltf(w.write(test_folder(), "hierarchy"));
    const Mesh& m = only_part(model);
    // By hand: p -> p + (0,1,0) -> 2p -> 90 degrees about +Y: (x, y, z) -> (z, y, -x) -> + (10, 0, 0).
    ASSERT_EQ(m.positions.size(), 3u);
    EXPECT_TRUE(contains_point(m, {10, 2, 0}));
    EXPECT_TRUE(contains_point(m, {10, 2, -2}));
    EXPECT_TRUE(contains_point(m, {12, 2, 0}));
    // No normals in the file: computed from the face, which points down.
    for (const glm::vec3& n : m.normals) EXPECT_LT(glm::distance(n, glm::vec3(0, -1, 0)), 1e-5f);
}

TEST(SceneGltf, NormalsTransformWithTheInverseTranspose) {
    GltfWriter w;
    const glm::vec3 n = glm::normalize(glm::vec3(1, 1, 0));  // the plane x + y = 1
    const int mesh = w.mesh(w.vec3s({{1, 0, 0}, {0, 1, 0}, {1, 0, 1}}), w.indices({0, 1, 2}), w.vec3s({n, n, n}));
    w.scene({w.node({{"mesh", mesh}, {"scale", {2, 1, 1}}})});
    const GltfModel model = load_gltf(w.write(test_folder(), "stretched"));
    const Mesh& m = only_part(model);
    // Stretched by 2 along x the plane becomes x / 2 + y = 1, whose normal is (1, 2, 0) / sqrt 5.
    const glm::vec3 expected = glm::normalize(glm::vec3(1, 2, 0));
    for (const glm::vec3& v : m.normals) EXPECT_LT(glm::distance(v, expected), 1e-5f);
    EXPECT_GT(glm::dot(glm::vec3(test::face_normal(m, 0)), expected), 0.0f);
}

TEST(SceneGltf, MirroringNodeKeepsFacesAgreeingWithNormals) {
    GltfWriter w;
    const glm::vec3 z(0, 0, 1);
    const int mesh = w.mesh(w.vec3s({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}), w.indices({0, 1, 2}), w.vec3s({z, z, z}));
    w.scene({w.node({{"mesh", mesh}, {"scale", {-1, 1, 1}}})});
    const GltfModel model = load_gltf(w.write(test_folder(), "mirrored"));
    const Mesh& m = only_part(model);
    EXPECT_TRUE(contains_point(m, {-1, 0, 0}));
    for (const glm::vec3& v : m.normals) EXPECT_EQ(v, z);  // a mirror in x leaves +z alone
    EXPECT_GT(test::face_normal(m, 0).z, 0.0);             // so the face must still look along +z
}

TEST(SceneGltf, MissingNormalsAreComputedUnitAndOutwardOnABox) {
    // A cube with 8 shared corners and no normals.
    const Mesh box = make_mesh(BoxShape{glm::vec3(2.0f)});
    std::vector<glm::vec3> corners;
    std::vector<std::uint16_t> order;
    for (const std::uint32_t i : box.indices) {
        const auto it = std::find(corners.begin(), corners.end(), box.positions[i]);
        order.push_back(std::uint16_t(it - corners.begin()));
        if (it == corners.end()) corners.push_back(box.positions[i]);
    }
    ASSERT_EQ(corners.size(), 8u);
    GltfWriter w;
    w.scene({w.node({{"mesh", w.mesh(w.vec3s(corners), w.indices(order))}})});
    const GltfModel model = load_gltf(w.write(test_folder(), "cube"));
    const Mesh& m = only_part(model);
    ASSERT_EQ(m.positions.size(), 8u);
    EXPECT_LT(test::worst_normal_length_error(m), 1e-6);
    for (std::size_t i = 0; i < 8; ++i) {
        // Each corner's normal leans into its own octant.
        const glm::vec3 p = m.positions[i], n = m.normals[i];
        EXPECT_GT(n.x * p.x, 0.0f);
        EXPECT_GT(n.y * p.y, 0.0f);
        EXPECT_GT(n.z * p.z, 0.0f);
    }
}

TEST(SceneGltf, MissingNormalsOnASpherePointAwayFromItsCentre) {
    const Mesh sphere = make_mesh(SphereShape{1.5f, 48});
    GltfWriter w;
    std::vector<std::uint16_t> order(sphere.indices.begin(), sphere.indices.end());
    w.scene({w.node({{"mesh", w.mesh(w.vec3s(sphere.positions), w.indices(order))}})});
    const GltfModel model = load_gltf(w.write(test_folder(), "sphere"));
    const Mesh& m = only_part(model);
    EXPECT_LT(test::worst_normal_length_error(m), 1e-6);
    for (std::size_t i = 0; i < m.positions.size(); ++i)
        EXPECT_GT(glm::dot(m.normals[i], glm::normalize(m.positions[i])), 0.999f) << i;
}

TEST(SceneGltf, StripsFansAndListsGiveTheSameFrontFacingQuad) {
    // glTF-Asset-Generator's quad, facing the viewer at +Z, in every triangle mode and index type.
    for (const char* n : {"04", "05", "06", "11", "12", "13", "14", "15"}) {
        const fs::path file =
            kModels / "glTF-Asset-Generator/Mesh_PrimitiveMode" / (std::string("Mesh_PrimitiveMode_") + n + ".gltf");
        SCOPED_TRACE(file.string());
        const GltfModel model = load_gltf(file);
        const Mesh& m = only_part(model);
        EXPECT_EQ(m.triangle_count(), 2u);
        EXPECT_EQ(m.bounds_min, glm::vec3(-0.5f, -0.5f, 0.0f));
        EXPECT_EQ(m.bounds_max, glm::vec3(0.5f, 0.5f, 0.0f));
        for (std::size_t t = 0; t < m.indices.size(); t += 3) EXPECT_GT(test::face_normal(m, t).z, 0.0);
        for (const glm::vec3& v : m.normals) EXPECT_EQ(v, glm::vec3(0, 0, 1));
    }
}

TEST(SceneGltf, PointsAndLinesAloneAreNoTriangles) {
    for (const char* n : {"00", "01", "02", "03"})
        expect_input_error(
            kModels / "glTF-Asset-Generator/Mesh_PrimitiveMode" / (std::string("Mesh_PrimitiveMode_") + n + ".gltf"),
            "no triangles");
}

TEST(SceneGltf, LinesBesideTrianglesAreSkipped) {
    GltfWriter w;
    const int positions = w.vec3s({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
    const int triangles = w.mesh(positions);
    const int lines = w.mesh(positions, -1, -1, 1);
    w.scene({w.node({{"mesh", triangles}}), w.node({{"mesh", lines}})});
    const GltfModel model = load_gltf(w.write(test_folder(), "mixed"));
    EXPECT_EQ(model.triangle_count(), 1u);
    EXPECT_EQ(model.skipped_primitives, 1u);
}

TEST(SceneGltf, VerticesNoTriangleUsesAreLeftOut) {
    GltfWriter w;
    const int mesh = w.mesh(w.vec3s({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {100, 100, 100}}), w.indices({0, 1, 2}));
    w.scene({w.node({{"mesh", mesh}})});
    const GltfModel model = load_gltf(w.write(test_folder(), "unused"));
    const Mesh& m = only_part(model);
    EXPECT_EQ(m.positions.size(), 3u);
    EXPECT_EQ(m.bounds_max, glm::vec3(1, 1, 0));
}

TEST(SceneGltf, TheDefaultSceneIsTheOneNamedByScene) {
    GltfWriter w;
    const int small = w.node({{"mesh", w.mesh(w.vec3s({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}))}});
    const int large = w.node({{"mesh", w.mesh(w.vec3s({{0, 0, 0}, {5, 0, 0}, {0, 5, 0}}))}});
    w.doc["scenes"] = json::array({{{"nodes", {small}}}, {{"nodes", {large}}}});
    w.doc["scene"] = 1;
    EXPECT_EQ(load_gltf(w.write(test_folder(), "two_scenes")).bounds_max, glm::vec3(5, 5, 0));
}

// The malformed models shipped with assimp's tests, each checked for what it really contains.
TEST(SceneGltfMalformed, IndexOutOfRange) {
    expect_input_error(kModels / "IndexOutOfRange/IndexOutOfRange.gltf",
                       "index 255 at position 0 is out of range (24 vertices)");
    expect_input_error(kModels / "IndexOutOfRange/AllIndicesOutOfRange.gltf",
                       "index 65535 at position 0 is out of range");
}

TEST(SceneGltfMalformed, MissingBin) {
    expect_input_error(kModels / "MissingBin/BoxTextured.gltf", "BoxTextured0.bin not found");
}

TEST(SceneGltfMalformed, RecursiveNodesAreACycleNotAHang) {
    expect_input_error(kModels / "RecursiveNodes/RecursiveNodes.gltf", "node cycle");
}

TEST(SceneGltfMalformed, WrongTypes) {
    const fs::path dir = kModels / "wrongTypes";
    expect_input_error(dir / "badArray.gltf", "meshes[0].primitives: expected an array");
    expect_input_error(
        dir / "badExtension.gltf",
        "materials[0].pbrMetallicRoughness.baseColorTexture.extensions.KHR_texture_transform: expected an object");
    expect_input_error(dir / "badNumber.gltf", "materials[0].normalTexture.scale: expected a number");
    expect_input_error(dir / "badObject.gltf", "materials[0].pbrMetallicRoughness: expected an object");
    expect_input_error(dir / "badString.gltf", "name: expected a string");
    expect_input_error(dir / "badUint.gltf", "index: expected a non-negative integer");
}

TEST(SceneGltfMalformed, BoxWithInfinites) {
    expect_input_error(kModels / "BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb", "POSITION 0 is not finite");
}

TEST(SceneGltfMalformed, IncorrectVertexArrays) {
    // Mesh 0 is a sound cube; mesh 1 ("TruncatedCube") is a triangle list of 35 vertices. (The file's
    // buffer is also too short for the views that only unused accessors read.)
    expect_input_error(kModels / "IncorrectVertexArrays/Cube.gltf",
                       "mesh 1 primitive 0 has 35 vertices, not a multiple of 3");
}

TEST(SceneGltfMalformed, BufferViewPastItsBuffer) {
    GltfWriter w;
    const int positions = w.vec3s({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
    w.doc["bufferViews"][0]["byteLength"] = 40;
    w.scene({w.node({{"mesh", w.mesh(positions)}})});
    expect_input_error(w.write(test_folder(), "short"),
                       "bufferView 0 (bytes 0 + 40) runs past the end of buffer 0 (36 bytes)");
}

TEST(SceneGltfMalformed, SceneOfTheWrongType) {
    expect_input_error(kModels / "SchemaFailures/sceneWrongType.gltf", "scene: expected a non-negative integer");
}

TEST(SceneGltfMalformed, NoSceneOrEmptyScene) {
    expect_input_error(kModels / "TestNoRootNode/NoScene.gltf", "scene 0 does not exist");
    expect_input_error(kModels / "TestNoRootNode/SceneWithoutNodes.gltf", "no triangles");
}

TEST(SceneGltfMalformed, CompressedGeometryIsRefusedByName) {
    expect_input_error(kModels / "draco/2CylinderEngine.gltf",
                       "requires KHR_draco_mesh_compression, which is not supported");
}

TEST(SceneGltfMalformed, CycleBelowTheRoot) {
    GltfWriter w;
    // 0 -> 1 -> 2 -> 1
    w.node({{"children", {1}}});
    w.node({{"children", {2}}});
    w.node({{"children", {1}}});
    w.scene({0});
    expect_input_error(w.write(test_folder(), "cycle"), "node cycle: node 1");
}

TEST(SceneGltfMalformed, NodeWithTwoParents) {
    GltfWriter w;
    const int mesh = w.mesh(w.vec3s({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
    const int shared = w.node({{"mesh", mesh}});
    w.scene({w.node({{"children", {shared}}}), w.node({{"children", {shared}}})});
    expect_input_error(w.write(test_folder(), "shared"), "more than one parent");
}

TEST(SceneGltfMalformed, ReferencesOutOfRange) {
    GltfWriter w;
    w.scene({w.node({{"mesh", 7}})});
    expect_input_error(w.write(test_folder(), "mesh"), "mesh 7, which does not exist");

    GltfWriter v;
    v.scene({v.node({{"mesh", v.mesh(9)}})});
    expect_input_error(v.write(test_folder(), "accessor"), "accessor 9, which does not exist");
}

TEST(SceneGltfMalformed, WrongComponentTypes) {
    GltfWriter w;
    const float xy[] = {0, 0, 1, 0, 0, 1};
    w.scene({w.node({{"mesh", w.mesh(w.accessor(w.view(xy, sizeof xy), 5126, 3, "VEC2"))}})});
    expect_input_error(w.write(test_folder(), "vec2"), "POSITION (accessor 0) must be float VEC3");

    GltfWriter v;
    const float order[] = {0, 1, 2};
    const int positions = v.vec3s({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
    v.scene({v.node({{"mesh", v.mesh(positions, v.accessor(v.view(order, sizeof order), 5126, 3, "SCALAR"))}})});
    expect_input_error(v.write(test_folder(), "float_indices"), "must be unsigned byte, short or int SCALAR");
}

TEST(SceneGltfMalformed, StrideShorterThanAnElement) {
    GltfWriter w;
    const float p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    w.scene({w.node({{"mesh", w.mesh(w.accessor(w.view(p, sizeof p, 8), 5126, 3, "VEC3"))}})});
    expect_input_error(w.write(test_folder(), "stride"), "has byteStride 8");
}

TEST(SceneGltfMalformed, AccessorPastItsView) {
    GltfWriter w;
    const float p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    w.scene({w.node({{"mesh", w.mesh(w.accessor(w.view(p, sizeof p), 5126, 4, "VEC3"))}})});
    expect_input_error(w.write(test_folder(), "count"),
                       "4 elements from byte 0) runs past the end of bufferView 0 (36 bytes)");
}

TEST(SceneGltfMalformed, TriangleListNotAMultipleOfThree) {
    GltfWriter w;
    w.scene({w.node({{"mesh", w.mesh(w.vec3s({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}}))}})});
    expect_input_error(w.write(test_folder(), "four"), "has 4 vertices, not a multiple of 3");
}

TEST(SceneGltfMalformed, AbsurdTriangleCount) {
    // 150 million and 3 indices declared: refused on the count alone, before any reading.
    GltfWriter w;
    const int positions = w.vec3s({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
    const std::uint16_t order[] = {0, 1, 2};
    const int indices = w.accessor(w.view(order, sizeof order), 5123, 150'000'003, "SCALAR");
    w.scene({w.node({{"mesh", w.mesh(positions, indices)}})});
    expect_input_error(w.write(test_folder(), "huge"), "more than 50000000 triangles");
}

TEST(SceneGltfMalformed, SparseAccessorsAreRefused) {
    GltfWriter w;
    const int positions = w.vec3s({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
    w.doc["accessors"][positions]["sparse"] = {
        {"count", 1}, {"indices", {{"bufferView", 0}, {"componentType", 5123}}}, {"values", {{"bufferView", 0}}}};
    w.scene({w.node({{"mesh", w.mesh(positions)}})});
    expect_input_error(w.write(test_folder(), "sparse"), "is sparse");
}

TEST(SceneGltfMalformed, FixedSizeArraysOfTheWrongLength) {
    GltfWriter w;
    w.scene({w.node({{"mesh", w.mesh(w.vec3s({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}))}, {"translation", {1, 2}}})});
    expect_input_error(w.write(test_folder(), "translation"), "nodes[0].translation: expected 3 numbers, found 2");
}

TEST(SceneGltfMalformed, FileProblems) {
    const fs::path dir = test_folder();
    expect_input_error(dir / "absent.glb", "no such file");
    std::ofstream(dir / "text.gltf") << "{ \"asset\": ";
    expect_input_error(dir / "text.gltf", "invalid JSON");
    std::ofstream(dir / "huge.gltf") << R"({"asset": {"version": "2.0"}, "nodes": [{"translation": [1e999, 0, 0]}]})";
    expect_input_error(dir / "huge.gltf", "invalid JSON: number overflow");
    std::ofstream(dir / "bad.glb") << "not a glb at all, certainly not";
    expect_input_error(dir / "bad.glb", "bad magic");
    std::ofstream(dir / "model.obj") << "v 0 0 0";
    expect_input_error(dir / "model.obj", "not a glTF file");
    std::ofstream(dir / "noversion.gltf") << R"({"asset": {}})";
    expect_input_error(dir / "noversion.gltf", "asset.version: required property is missing");
}

}  // namespace
}  // namespace envshadow
