// Shadow-caster levels of detail (render/caster_lod.h): the chain simplifies, its errors grow and are
// honest (checked against a sphere's analytic surface), the level choice and the error budget.
#include <algorithm>
#include <cmath>
#include <map>
#include <span>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>

#include "render/caster_lod.h"
#include "scene/meshes.h"

namespace envshadow::render {
namespace {

// Level k's indices: level 0 is the mesh's own index buffer, the others are in lod.indices.
std::span<const std::uint32_t> level_indices(const CasterLod& lod, const Mesh& mesh, std::size_t k) {
    if (k == 0) return mesh.indices;
    return {lod.indices.data() + lod.levels[k].first_index, lod.levels[k].index_count};
}

// How far inside the unit sphere the level's triangles sag at worst (deepest at a centroid).
float worst_centroid(const Mesh& sphere, std::span<const std::uint32_t> indices) {
    float worst = 0.0f;
    for (std::size_t i = 0; i < indices.size(); i += 3)
        worst = std::max(worst, 1.0f - glm::length(sphere.positions[indices[i]] + sphere.positions[indices[i + 1]] +
                                                   sphere.positions[indices[i + 2]]) /
                                           3.0f);
    return worst;
}

TEST(CasterLod, ChainOfASphereSimplifiesWithGrowingError) {
    const Mesh sphere = make_mesh(SphereShape{1.0f, 128});  // 16,128 triangles, seams at the poles/meridian
    const CasterLod lod = build_caster_lod(sphere.positions, sphere.indices);
    ASSERT_GE(lod.levels.size(), 4u);
    EXPECT_EQ(lod.levels[0].index_count, sphere.indices.size());
    EXPECT_EQ(lod.levels[0].error, 0.0f);
    for (std::size_t k = 1; k < lod.levels.size(); ++k) {
        EXPECT_LE(double(lod.levels[k].index_count), 0.9 * double(lod.levels[k - 1].index_count)) << k;
        EXPECT_GE(lod.levels[k].error, lod.levels[k - 1].error) << k;
        EXPECT_EQ(lod.levels[k].index_count % 3, 0u);
        EXPECT_LE(lod.levels[k].first_index + lod.levels[k].index_count, lod.indices.size());  // level 0 not copied
    }
    EXPECT_LT(lod.levels.back().index_count, sphere.indices.size() / 10);  // the coarsest is far coarser
}

// Large models take seconds: the progress callback rises from 0 to 1, never backwards, and the
// levels are the same with it as without.
TEST(CasterLod, ReportsItsProgressFromZeroToOne) {
    const Mesh sphere = make_mesh(SphereShape{1.0f, 64});
    std::vector<double> fractions;
    const CasterLod lod =
        build_caster_lod(sphere.positions, sphere.indices, [&](double fraction) { fractions.push_back(fraction); });
    ASSERT_GE(fractions.size(), 3u);
    EXPECT_EQ(fractions.front(), 0.0);
    EXPECT_EQ(fractions.back(), 1.0);
    EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
    EXPECT_EQ(lod.indices, build_caster_lod(sphere.positions, sphere.indices).indices);
}

// Every simplified triangle's centroid (where a flat triangle sags deepest) lies within the level's
// error of the unit sphere, beyond what the full tessellation itself is off: the error the renderer
// budgets is a bound, not an estimate.
TEST(CasterLod, ErrorBoundsTheDistanceFromTheSurface) {
    const Mesh sphere = make_mesh(SphereShape{1.0f, 128});
    const CasterLod lod = build_caster_lod(sphere.positions, sphere.indices);
    const float full = worst_centroid(sphere, level_indices(lod, sphere, 0));
    for (std::size_t k = 1; k < lod.levels.size(); ++k)
        EXPECT_LE(worst_centroid(sphere, level_indices(lod, sphere, k)), lod.levels[k].error + full)
            << "level " << k << " error " << lod.levels[k].error;
}

// Watertight: every edge a -> b as often as b -> a, so no edge borders a hole (is_closed asks more:
// each once, which a simplifier that pinches a thin part into a fold need not keep).
bool watertight(std::span<const std::uint32_t> indices) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> balance;
    for (std::size_t t = 0; t < indices.size(); t += 3)
        for (std::size_t e = 0; e < 3; ++e) {
            const std::uint32_t a = indices[t + e], b = indices[t + (e + 1) % 3];
            balance[{std::min(a, b), std::max(a, b)}] += a < b ? 1 : -1;
        }
    return std::all_of(balance.begin(), balance.end(), [](const auto& edge) { return edge.second == 0; });
}

// A large mesh's levels are simplified in spatial chunks with locked borders (CasterLodChunks; the
// thresholds lowered here so that a small sphere is cut into 17 chunks): the chunks still meet edge to
// edge (every level of the closed sphere is watertight: no crack between chunks), the errors still
// bound the distance from the surface, and the progress still rises from 0 to 1.
TEST(CasterLod, ChunkedLevelsMeetEdgeToEdgeWithinTheirError) {
    const Mesh sphere = make_mesh(SphereShape{1.0f, 128});  // 16,128 triangles
    std::vector<double> fractions;
    const CasterLod lod = build_caster_lod(
        sphere.positions, sphere.indices, [&](double fraction) { fractions.push_back(fraction); },
        CasterLodChunks{2000, 1000});
    ASSERT_GE(lod.levels.size(), 4u);
    EXPECT_TRUE(lod.levels[0].closed);
    const float full = worst_centroid(sphere, level_indices(lod, sphere, 0));
    for (std::size_t k = 1; k < lod.levels.size(); ++k) {
        const CasterLevel& level = lod.levels[k];
        EXPECT_TRUE(watertight(level_indices(lod, sphere, k))) << "level " << k;
        EXPECT_LE(double(level.index_count), 0.9 * double(lod.levels[k - 1].index_count)) << k;
        EXPECT_LE(worst_centroid(sphere, level_indices(lod, sphere, k)), level.error + full)
            << "level " << k << " error " << level.error;
    }
    EXPECT_LT(lod.levels.back().index_count, sphere.indices.size() / 10);
    ASSERT_GE(fractions.size(), 3u);
    EXPECT_EQ(fractions.front(), 0.0);
    EXPECT_EQ(fractions.back(), 1.0);
    EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
}

// Closed: every directed edge once and its reverse once, whatever the vertex numbers (a level of a
// large mesh uses a few of its vertices, numbered sparsely).
TEST(CasterLod, ClosedMeansEveryEdgeMeetsItsReverse) {
    const Mesh sphere = make_mesh(SphereShape{1.0f, 16});
    EXPECT_TRUE(is_closed(sphere.indices));
    std::vector<std::uint32_t> sparse = sphere.indices;
    for (std::uint32_t& index : sparse) index = 7 * index + 1'000'000;
    EXPECT_TRUE(is_closed(sparse));
    std::vector<std::uint32_t> open(sphere.indices.begin(), sphere.indices.end() - 3);  // one triangle missing
    EXPECT_FALSE(is_closed(open));
    std::vector<std::uint32_t> flipped = sphere.indices;  // one triangle wound the other way
    std::swap(flipped[4], flipped[5]);
    EXPECT_FALSE(is_closed(flipped));
    std::vector<std::uint32_t> doubled = sphere.indices;  // a triangle twice
    doubled.insert(doubled.end(), sphere.indices.begin(), sphere.indices.begin() + 3);
    EXPECT_FALSE(is_closed(doubled));
}

TEST(CasterLod, ChoosesTheCoarsestLevelWithinTheBudget) {
    CasterLod lod;
    lod.levels = {{0, 300, 0.0f}, {300, 150, 0.01f}, {450, 60, 0.04f}, {510, 30, 0.2f}};
    EXPECT_EQ(choose_caster_level(lod, 0.0f), 0);
    EXPECT_EQ(choose_caster_level(lod, 0.009f), 0);
    EXPECT_EQ(choose_caster_level(lod, 0.01f), 1);
    EXPECT_EQ(choose_caster_level(lod, 0.05f), 2);
    EXPECT_EQ(choose_caster_level(lod, 1.0f), 3);
}

TEST(CasterLod, SmallMeshesKeepOnlyTheFullLevel) {
    const Mesh box = make_mesh(BoxShape{glm::vec3(1.0f)});
    const CasterLod lod = build_caster_lod(box.positions, box.indices);
    ASSERT_EQ(lod.levels.size(), 1u);
    EXPECT_EQ(lod.levels[0].index_count, 36u);
}

// Degenerate input: a large mesh whose vertices all lie at one point has nothing to simplify (and
// no extent to size the error grids by).
TEST(CasterLod, MeshAtOnePointKeepsOnlyTheFullLevel) {
    Mesh point = make_mesh(SphereShape{1.0f, 32});
    for (glm::vec3& p : point.positions) p = glm::vec3(2.0f, 3.0f, 4.0f);
    const CasterLod lod = build_caster_lod(point.positions, point.indices);
    ASSERT_EQ(lod.levels.size(), 1u);
    EXPECT_EQ(lod.levels[0].index_count, point.indices.size());
    EXPECT_FALSE(lod.levels[0].closed);  // welded, every triangle is degenerate
}

TEST(CasterLod, ErrorBudgetIsAFractionOfATexelInObjectSpace) {
    // 256 texels over 4 m: texel 1/64 m; half a texel is 1/128 m in the world.
    const float texel = 4.0f / 256.0f;
    EXPECT_FLOAT_EQ(caster_error_budget(glm::mat4(1.0f), texel, 0.5f), texel / 2.0f);
    // An object scaled by 2 (and by 0.5 on another axis): its object-space error counts twice.
    const glm::mat4 scaled =
        glm::scale(glm::translate(glm::mat4(1.0f), glm::vec3(3, 1, 2)), glm::vec3(2.0f, 0.5f, 1.0f));
    EXPECT_FLOAT_EQ(caster_error_budget(scaled, texel, 0.5f), texel / 4.0f);
    // A rotation does not change it.
    const glm::mat4 turned = glm::rotate(glm::mat4(1.0f), 0.7f, glm::normalize(glm::vec3(1, 2, 3)));
    EXPECT_NEAR(caster_error_budget(turned, texel, 0.5f), texel / 2.0f, 1e-7f);
    EXPECT_EQ(caster_error_budget(glm::mat4(1.0f), texel, 0.0f), 0.0f);  // LOD off
    EXPECT_EQ(caster_error_budget(glm::mat4(1.0f), 0.0f, 0.5f), 0.0f);   // no tiles
}

// Tiles over the same casters at 128^2, 256^2 and 1024^2: the small tile's texel is 8 times the large
// one's and takes a coarser level; tiles of one level are drawn together, every tile exactly once.
TEST(CasterLod, EachTileTakesTheLevelOfItsOwnTexel) {
    CasterLod lod;
    lod.levels = {{0, 300, 0.0f}, {300, 150, 0.01f}, {450, 60, 0.04f}, {510, 30, 0.2f}};
    const float large = 4.0f / 1024.0f, middle = 4.0f / 256.0f, small = 4.0f / 128.0f;
    const std::vector<float> texels = {small, large, small, middle, large};
    CasterTiles tiles;
    tiles.tiles = {7};  // appended after what is there
    tiles.runs = {{2, 0, 1}};
    // Half a texel: 0.0020 and 0.0078 m (level 0), 0.0156 m (level 1).
    append_caster_tiles(lod, glm::mat4(1.0f), texels, 0.5f, tiles);
    ASSERT_EQ(tiles.runs.size(), 3u);
    EXPECT_EQ(tiles.runs[1].level, 0);
    EXPECT_EQ(tiles.runs[1].first, 1u);
    EXPECT_EQ(tiles.runs[1].count, 3u);
    EXPECT_EQ(tiles.runs[2].level, 1);
    EXPECT_EQ(tiles.runs[2].first, 4u);
    EXPECT_EQ(tiles.runs[2].count, 2u);
    EXPECT_EQ(tiles.tiles, (std::vector<std::int32_t>{7, 1, 3, 4, 0, 2}));
    // An object scaled by 0.1: an object-space error moves its surface a tenth as far, so ten times the
    // error is allowed (0.020 m: level 1; 0.078 and 0.156 m: level 2).
    CasterTiles scaled;
    append_caster_tiles(lod, glm::scale(glm::mat4(1.0f), glm::vec3(0.1f)), texels, 0.5f, scaled);
    ASSERT_EQ(scaled.runs.size(), 2u);
    EXPECT_EQ(scaled.runs[0].level, 1);
    EXPECT_EQ(scaled.runs[1].level, 2);
    EXPECT_EQ(scaled.tiles, (std::vector<std::int32_t>{1, 4, 0, 2, 3}));
    // LOD off: one run of every tile at level 0.
    CasterTiles off;
    append_caster_tiles(lod, glm::mat4(1.0f), texels, 0.0f, off);
    ASSERT_EQ(off.runs.size(), 1u);
    EXPECT_EQ(off.runs[0].level, 0);
    EXPECT_EQ(off.runs[0].count, 5u);
}

}  // namespace
}  // namespace envshadow::render
