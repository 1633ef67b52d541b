// Sides (docs/SCENES.md "Sides"): a camera inside a closed box under a unit sky sees the box's inner
// walls, in the dark of the box, when the box is double-sided, and the sky through them (1 exactly) when
// it is single-sided (glTF's doubleSided false), in both renderers and in each shading path. The same
// single-sided box seen from outside looks as the double-sided one does.
#include <memory>

#include "gl_fixture.h"
#include "reference/reference.h"
#include "render_test_util.h"
#include "scene/meshes.h"

namespace envshadow::testing {
namespace {

using SidesTest = GlTest;

constexpr int kSize = 32;

Scene box_around(glm::vec3 eye, bool double_sided) {
    Scene scene;
    scene.environment.source = "builtin:constant";
    scene.camera.position = eye;
    scene.camera.target = {0.0f, 0.0f, -5.0f};
    scene.camera.fov_y_degrees = 60.0f;
    Object box;
    box.name = "box";
    box.mesh = std::make_shared<Mesh>(make_mesh(BoxShape{glm::vec3(2.0f)}));
    box.material.rho_d = glm::vec3(0.5f);
    box.material.double_sided = double_sided;
    scene.objects.push_back(std::move(box));
    return scene;
}

Image render_scene(const Scene& scene, const render::RenderSettings& settings) {
    return testing::render_scene(scene, settings, kSize, kSize, {.method = Method::lloyd, .lights = 16});
}

Image reference_of(const Scene& scene) {
    return reference_image(scene, kSize, kSize, 0.05, reference::PixelFilter::box);
}

float centre(const Image& image) {
    return image.at(kSize / 2, kSize / 2).g;
}

TEST_P(SidesTest, FromInsideASingleSidedClosedBoxTheCameraSeesOut) {
    const glm::vec3 inside{0.0f, 0.0f, 0.5f};
    for (const render::RenderSettings& settings : {render::RenderSettings{}, commands_defaults()}) {
        SCOPED_TRACE(settings.shading == render::ShadingMode::ratio ? "the commands' defaults" : "cells");
        EXPECT_NEAR(centre(render_scene(box_around(inside, false), settings)), 1.0f, 1e-3f);
        EXPECT_LT(centre(render_scene(box_around(inside, true), settings)), 0.1f);  // no sky reaches inside
    }
    EXPECT_NEAR(centre(reference_of(box_around(inside, false))), 1.0f, 1e-3f);
    EXPECT_LT(centre(reference_of(box_around(inside, true))), 0.1f);
}

TEST_P(SidesTest, FromOutsideBothSidednessesLookAlike) {
    const glm::vec3 outside{0.3f, 0.6f, 4.0f};
    const render::RenderSettings settings = commands_defaults();
    const Image single = render_scene(box_around(outside, false), settings);
    const Image both = render_scene(box_around(outside, true), settings);
    ASSERT_EQ(single.pixels.size(), both.pixels.size());
    for (std::size_t i = 0; i < single.pixels.size(); ++i) ASSERT_EQ(single.pixels[i], both.pixels[i]) << "pixel " << i;
}

ENVSHADOW_INSTANTIATE_GL_TEST(SidesTest);

}  // namespace
}  // namespace envshadow::testing
