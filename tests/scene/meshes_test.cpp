#include "scene/meshes.h"

#include <cmath>
#include <utility>

#include <gtest/gtest.h>
#include <glm/gtc/constants.hpp>

#include "mesh_checks.h"
#include "scene/mesh_topology.h"

namespace envshadow {
namespace {

using test::normals_against_faces;
using test::signed_volume;
using test::unpaired_edges;
using test::worst_normal_length_error;

constexpr double kPi = glm::pi<double>();

void expect_well_formed(const Mesh& m) {
    ASSERT_EQ(m.normals.size(), m.positions.size());
    ASSERT_EQ(m.indices.size() % 3, 0u);
    for (const std::uint32_t i : m.indices) ASSERT_LT(i, m.positions.size());
    EXPECT_LT(worst_normal_length_error(m), 1e-5);
    EXPECT_EQ(normals_against_faces(m), 0u);
}

// Closed once welded: the box's faces have vertices of their own (flat normals), which is_closed alone
// sees as twelve separate triangles; the plane stays open; a turned triangle breaks the box.
TEST(SceneMeshTopology, ClosedSurfacesAreClosedOnceWeldedByPosition) {
    const Mesh box = make_mesh(BoxShape{});
    EXPECT_FALSE(is_closed(box.indices));
    EXPECT_TRUE(is_closed_surface(box));
    EXPECT_TRUE(is_closed_surface(make_mesh(SphereShape{})));
    EXPECT_FALSE(is_closed_surface(make_mesh(PlaneShape{})));
    Mesh turned = box;
    std::swap(turned.indices[1], turned.indices[2]);
    EXPECT_FALSE(is_closed_surface(turned));
    EXPECT_FALSE(is_closed_surface(Mesh{}));
}

TEST(SceneBuiltinMeshes, PlaneIsTwoUpwardTrianglesOfTheGivenSize) {
    const Mesh m = make_mesh(PlaneShape{6.0f});
    expect_well_formed(m);
    EXPECT_EQ(m.triangle_count(), 2u);
    for (std::size_t t = 0; t < m.indices.size(); t += 3) EXPECT_GT(test::face_normal(m, t).y, 0.0);
    for (const glm::vec3& n : m.normals) EXPECT_EQ(n, glm::vec3(0, 1, 0));
    EXPECT_EQ(m.bounds_min, glm::vec3(-3, 0, -3));
    EXPECT_EQ(m.bounds_max, glm::vec3(3, 0, 3));
}

TEST(SceneBuiltinMeshes, SphereIsClosedOutwardAndRound) {
    const Mesh m = make_mesh(SphereShape{2.0f, 32});
    expect_well_formed(m);
    // 32 around, 16 bands: two polar fans of 32 plus 14 bands of 64.
    EXPECT_EQ(m.triangle_count(), 2u * 32 + 14u * 64);
    EXPECT_EQ(unpaired_edges(m), 0u);
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        EXPECT_NEAR(glm::length(m.positions[i]), 2.0f, 1e-5f);
        EXPECT_LT(glm::distance(m.normals[i], m.positions[i] / 2.0f), 1e-5f);
    }
    // Inscribed polyhedron: a little less than the ball, never more.
    const double ball = 4.0 / 3.0 * kPi * 8.0;
    EXPECT_LT(signed_volume(m), ball);
    EXPECT_GT(signed_volume(m), 0.97 * ball);
}

TEST(SceneBuiltinMeshes, SphereTriangleCountFollowsSegments) {
    EXPECT_EQ(make_mesh(SphereShape{1.0f, 64}).triangle_count(), 2u * 64 * 31);
    EXPECT_EQ(make_mesh(SphereShape{1.0f, 4}).triangle_count(), 2u * 4 * 1);
}

TEST(SceneBuiltinMeshes, TorusIsClosedWithItsAnalyticVolume) {
    const Mesh m = make_mesh(TorusShape{1.0f, 0.25f, 96, 48});
    expect_well_formed(m);
    EXPECT_EQ(m.triangle_count(), 96u * 48 * 2);
    EXPECT_EQ(unpaired_edges(m), 0u);
    const double volume = 2.0 * kPi * kPi * 1.0 * 0.25 * 0.25;  // Pappus
    EXPECT_NEAR(signed_volume(m), volume, 0.01 * volume);
    EXPECT_NEAR(m.bounds_max.x, 1.25f, 1e-5f);
    EXPECT_NEAR(m.bounds_max.y, 0.25f, 1e-5f);
}

TEST(SceneBuiltinMeshes, BoxIsClosedWithFlatOutwardFaces) {
    const Mesh m = make_mesh(BoxShape{glm::vec3(1.0f, 2.0f, 3.0f)});
    expect_well_formed(m);
    EXPECT_EQ(m.triangle_count(), 12u);
    EXPECT_EQ(unpaired_edges(m), 0u);
    EXPECT_NEAR(signed_volume(m), 6.0, 1e-5);
    EXPECT_EQ(m.bounds_min, glm::vec3(-0.5f, -1.0f, -1.5f));
    EXPECT_EQ(m.bounds_max, glm::vec3(0.5f, 1.0f, 1.5f));
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        // Each vertex normal is one axis, pointing to the face the vertex lies on.
        const glm::vec3 n = m.normals[i];
        EXPECT_FLOAT_EQ(std::abs(n.x) + std::abs(n.y) + std::abs(n.z), 1.0f);
        EXPECT_GT(glm::dot(n, m.positions[i]), 0.0f);
        EXPECT_FLOAT_EQ(std::abs(glm::dot(n, m.positions[i])), std::abs(glm::dot(n, m.bounds_max)));
    }
}

TEST(SceneBuiltinMeshes, GeodesicFrequencyPicksTheNearestCount) {
    EXPECT_EQ(geodesic_frequency(20), 1);
    EXPECT_EQ(geodesic_frequency(80), 2);
    EXPECT_EQ(geodesic_frequency(15000), 27);  // 14580 (28 gives 15680)
    EXPECT_EQ(geodesic_frequency(1), 1);
}

TEST(SceneBuiltinMeshes, BlobHasAboutTheAskedTriangleCount) {
    for (const int target : {500, 2000, 5000, 15000, 60000}) {
        const Mesh m = make_mesh(BlobShape{0.5f, target, 0.25f, 7});
        EXPECT_NEAR(double(m.triangle_count()), double(target), 0.08 * target) << "target " << target;
    }
}

TEST(SceneBuiltinMeshes, BlobIsClosedOutwardLumpyAndDeterministic) {
    const Mesh m = make_mesh(BlobShape{0.5f, 5000, 0.3f, 3});
    expect_well_formed(m);
    EXPECT_EQ(unpaired_edges(m), 0u);
    EXPECT_GT(signed_volume(m), 0.0);
    float lo = 1e9f, hi = 0.0f;
    for (const glm::vec3& p : m.positions) {
        lo = std::min(lo, glm::length(p));
        hi = std::max(hi, glm::length(p));
    }
    EXPECT_GT(hi - lo, 0.05f) << "not lumpy";

    const Mesh again = make_mesh(BlobShape{0.5f, 5000, 0.3f, 3});
    EXPECT_EQ(again.positions, m.positions);
    EXPECT_EQ(again.indices, m.indices);
    EXPECT_NE(make_mesh(BlobShape{0.5f, 5000, 0.3f, 4}).positions, m.positions);
}

TEST(SceneBuiltinMeshes, BlobWithoutLumpsIsASphere) {
    const Mesh m = make_mesh(BlobShape{0.7f, 2000, 0.0f, 1});
    for (const glm::vec3& p : m.positions) EXPECT_NEAR(glm::length(p), 0.7f, 1e-5f);
    for (std::size_t i = 0; i < m.positions.size(); ++i)
        EXPECT_GT(glm::dot(m.normals[i], glm::normalize(m.positions[i])), 0.99f);
}

TEST(SceneBuiltinMeshes, FigureStandsOnTheGroundAtItsHeight) {
    const Mesh m = make_mesh(FigureShape{1.8f, 15000});
    expect_well_formed(m);
    EXPECT_NEAR(double(m.triangle_count()), 15000.0, 0.02 * 15000);
    EXPECT_EQ(unpaired_edges(m), 0u);
    EXPECT_GT(signed_volume(m), 0.0);
    EXPECT_NEAR(m.bounds_min.y, 0.0f, 1e-5f);
    EXPECT_NEAR(m.bounds_max.y, 1.8f, 1e-5f);
    EXPECT_NEAR(m.bounds_min.x + m.bounds_max.x, 0.0f, 1e-5f);
    EXPECT_NEAR(m.bounds_min.z + m.bounds_max.z, 0.0f, 1e-5f);
    // A figure, not a ball: much thinner front to back and narrower than it is tall.
    EXPECT_LT(m.bounds_max.z - m.bounds_min.z, 0.3f * 1.8f);
    EXPECT_LT(m.bounds_max.x - m.bounds_min.x, 0.6f * 1.8f);
}

TEST(SceneBuiltinMeshes, FigureFollowsTheAskedTriangleCount) {
    for (const int target : {3000, 15000, 40000})
        EXPECT_NEAR(double(make_mesh(FigureShape{1.0f, target}).triangle_count()), double(target), 0.02 * target);
}

TEST(SceneBuiltinMeshes, VirusPartsAreClosedAndSpikesReachOut) {
    const VirusShape shape{0.3f, 40, 0.12f, 8};
    const Mesh m = make_mesh(shape);
    expect_well_formed(m);
    // Body 20 * 8^2, per spike a stalk of 8 sides (16 side + 16 cap triangles) and a knob of 80.
    EXPECT_EQ(m.triangle_count(), 20u * 64 + 40u * (32 + 80));
    EXPECT_EQ(unpaired_edges(m), 0u);
    EXPECT_GT(signed_volume(m), 0.0);
    // Spikes stick out beyond the body: knob centres at radius + length, knob radius 0.3 * length.
    const float reach =
        std::max({-m.bounds_min.x, -m.bounds_min.y, -m.bounds_min.z, m.bounds_max.x, m.bounds_max.y, m.bounds_max.z});
    EXPECT_GT(reach, 0.3f + 0.12f);
    EXPECT_LE(reach, 0.3f + 1.3f * 0.12f + 1e-4f);
}

TEST(SceneVertexNormals, AreAreaWeighted) {
    // Vertex 0 is shared by a triangle of area 2 facing +Z and one of area 1/2 facing +X.
    Mesh m;
    m.positions = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 1, 0}, {0, 0, 1}};
    m.indices = {0, 1, 2, 0, 3, 4};
    compute_vertex_normals(m);
    EXPECT_LT(glm::distance(m.normals[0], glm::normalize(glm::vec3(0.5f, 0.0f, 2.0f))), 1e-6f);
    EXPECT_EQ(m.normals[1], glm::vec3(0, 0, 1));
    EXPECT_EQ(m.normals[4], glm::vec3(1, 0, 0));
}

TEST(SceneVertexNormals, UnusedVertexGetsUp) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 5, 5}};
    m.indices = {0, 1, 2};
    compute_vertex_normals(m);
    EXPECT_EQ(m.normals[3], glm::vec3(0, 1, 0));
}

// Tangents for normal maps (glTF's convention: v runs down the image, a normal map's +y up it).
TEST(SceneVertexTangents, FollowUAndTheImagesUp) {
    // A triangle in the XY plane facing +Z, u along +x; v along -y (the image upright), then along +y
    // (mirrored: the image's up is -y, so the bitangent cross(n, t) = +y needs w = -1).
    Mesh m;
    m.positions = {{0, 0, 0}, {2, 0, 0}, {0, 1, 0}};
    m.normals.assign(3, glm::vec3(0, 0, 1));
    m.indices = {0, 1, 2};
    m.texcoords = {{0, 1}, {1, 1}, {0, 0}};
    compute_vertex_tangents(m);
    ASSERT_EQ(m.tangents.size(), 3u);
    for (const glm::vec4& t : m.tangents) EXPECT_LT(glm::distance(t, glm::vec4(1, 0, 0, 1)), 1e-6f);
    m.texcoords = {{0, 0}, {1, 0}, {0, 1}};
    compute_vertex_tangents(m);
    for (const glm::vec4& t : m.tangents) EXPECT_LT(glm::distance(t, glm::vec4(1, 0, 0, -1)), 1e-6f);
    // A sheared mapping: u along the diagonal's projection, made orthogonal to the normal.
    m.normals.assign(3, glm::normalize(glm::vec3(0, 1, 1)));
    m.texcoords = {{0, 1}, {1, 1}, {0, 0}};
    compute_vertex_tangents(m);
    for (const glm::vec4& t : m.tangents) {
        EXPECT_LT(glm::distance(glm::vec3(t), glm::vec3(1, 0, 0)), 1e-6f);
        EXPECT_NEAR(glm::dot(glm::vec3(t), m.normals[0]), 0.0f, 1e-6f);
    }
}

TEST(SceneVertexTangents, WithoutAUvGradientAnyDirectionInThePlane) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.normals.assign(3, glm::vec3(0, 0, 1));
    m.indices = {0, 1, 2};
    m.texcoords.assign(3, glm::vec2(0.5f));  // every vertex at one uv
    compute_vertex_tangents(m);
    for (const glm::vec4& t : m.tangents) {
        EXPECT_NEAR(glm::length(glm::vec3(t)), 1.0f, 1e-6f);
        EXPECT_NEAR(t.z, 0.0f, 1e-6f);
        EXPECT_EQ(std::abs(t.w), 1.0f);
    }
}

}  // namespace
}  // namespace envshadow
