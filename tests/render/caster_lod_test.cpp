// Shadow-caster levels of detail (render/caster_lod.h): the chain simplifies, its errors grow and are
// honest (checked against a sphere's analytic surface), the level choice and the error budget.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>

#include "render/caster_lod.h"
#include "scene/meshes.h"

namespace envshadow::render {
namespace {

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
        EXPECT_LE(lod.levels[k].first_index + lod.levels[k].index_count, lod.indices.size());
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
    auto worst_centroid = [&](const CasterLevel& level) {
        float worst = 0.0f;
        for (std::uint32_t i = level.first_index; i < level.first_index + level.index_count; i += 3) {
            const glm::vec3 centroid = (sphere.positions[lod.indices[i]] + sphere.positions[lod.indices[i + 1]] +
                                        sphere.positions[lod.indices[i + 2]]) /
                                       3.0f;
            worst = std::max(worst, 1.0f - glm::length(centroid));
        }
        return worst;
    };
    const float full = worst_centroid(lod.levels[0]);
    for (std::size_t k = 1; k < lod.levels.size(); ++k)
        EXPECT_LE(worst_centroid(lod.levels[k]), lod.levels[k].error + full)
            << "level " << k << " error " << lod.levels[k].error;
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

}  // namespace
}  // namespace envshadow::render
