// Frames averaged with their samples moved within the pixel (CameraView::jitter, render::subpixel_jitter,
// docs/DESIGN.md §5.16): a dark box tilted against a bright sky, its edges the hardest case for a few samples a
// pixel. Sixteen frames must come closer than one to the image's box filter, taken here from a render at
// eight times the size averaged down, and move nothing: the image's mean stays the supersampled one's. At MSAA 4
// and at one sample a pixel.
#include <cmath>
#include <vector>

#include <glm/ext/matrix_transform.hpp>

#include "env/cells.h"
#include "env/environment.h"
#include "gl_fixture.h"
#include "render/frame_plan.h"
#include "render/renderer.h"
#include "render_test_util.h"
#include "scene/meshes.h"

namespace envshadow::testing {
namespace {

using AccumulationTest = GlTest;

constexpr int kWidth = 40, kHeight = 30, kSuper = 8;

// A dark box, turned about two axes so that its outline runs at odd angles, under a unit sky.
Scene tilted_box() {
    Scene scene;
    scene.environment.source = "builtin:constant";
    scene.camera.position = {0.0f, 0.0f, 4.0f};
    scene.camera.target = {0.0f, 0.0f, 0.0f};
    scene.camera.fov_y_degrees = 40.0f;
    Object box;
    box.mesh = std::make_shared<Mesh>(make_mesh(BoxShape{glm::vec3(1.2f, 0.8f, 0.6f)}));
    box.transform = glm::rotate(glm::rotate(glm::mat4(1.0f), 0.35f, glm::vec3(0, 0, 1)), 0.5f, glm::vec3(0, 1, 0));
    box.material.rho_d = glm::vec3(0.05f);
    scene.objects.push_back(std::move(box));
    return scene;
}

// The mean of `frames` frames at the shifts of subpixel_jitter, width x height.
Image accumulated(render::Renderer& renderer, const Scene& scene, int width, int height, int frames) {
    render::CameraView view = render::camera_view(scene, width, height);
    Image sum;
    for (const glm::vec2 shift : render::subpixel_jitter(frames, renderer.sample_positions())) {
        view.jitter = shift;
        renderer.render(0.0, view);
        const Image frame = renderer.read_back();
        if (sum.pixels.empty())
            sum = frame;
        else
            for (std::size_t i = 0; i < sum.pixels.size(); ++i) sum.pixels[i] += frame.pixels[i];
    }
    for (glm::vec4& pixel : sum.pixels) pixel /= float(frames);
    return sum;
}

// `image` averaged over factor x factor blocks.
Image shrunk(const Image& image, int factor) {
    Image out;
    out.width = image.width / factor;
    out.height = image.height / factor;
    out.pixels.assign(std::size_t(out.width) * std::size_t(out.height), glm::vec4(0.0f));
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            out.pixels[std::size_t(y / factor) * std::size_t(out.width) + std::size_t(x / factor)] +=
                image.at(x, y) / float(factor * factor);
    return out;
}

double rms_difference(const Image& a, const Image& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
        const glm::vec3 d = glm::vec3(a.pixels[i] - b.pixels[i]);
        sum += double(glm::dot(d, d)) / 3.0;
    }
    return std::sqrt(sum / double(a.pixels.size()));
}

double mean_value(const Image& image) {
    double sum = 0.0;
    for (const glm::vec4& p : image.pixels) sum += (double(p.r) + double(p.g) + double(p.b)) / 3.0;
    return sum / double(image.pixels.size());
}

TEST_P(AccumulationTest, SixteenJitteredFramesComeCloseToThePixelsMeanAndMoveNothing) {
    const Scene scene = tilted_box();
    const EnvironmentMap map = load_environment(scene.environment.source);
    DecomposeOptions cells;
    cells.lights = 32;
    for (int msaa : {4, 1}) {
        SCOPED_TRACE("MSAA " + std::to_string(msaa));
        render::RenderSettings settings = commands_defaults();
        settings.msaa = msaa;
        const auto renderer = prepared_renderer(scene, map, settings, cells);
        const Image truth = shrunk(accumulated(*renderer, scene, kWidth * kSuper, kHeight * kSuper, 1), kSuper);
        const Image one = accumulated(*renderer, scene, kWidth, kHeight, 1);
        const Image sixteen = accumulated(*renderer, scene, kWidth, kHeight, 16);
        const double error_one = rms_difference(one, truth), error_sixteen = rms_difference(sixteen, truth);
        EXPECT_GT(error_one, 0.01) << "the outline must cost one frame something to resolve";
        // At one sample a pixel the shifts cover the pixel; GL's four samples each sweep a quarter's box about
        // themselves, which resolves edges along x and y finely and slanted ones less (0.13 and 0.64 measured).
        const double most = msaa == 1 ? 0.25 : 0.8;
        EXPECT_LT(error_sixteen, most * error_one) << "one frame " << error_one << ", sixteen " << error_sixteen;
        EXPECT_NEAR(mean_value(sixteen), mean_value(truth), 0.002 * mean_value(truth));
    }
}

}  // namespace

ENVSHADOW_INSTANTIATE_GL_TEST(AccumulationTest);

}  // namespace envshadow::testing
