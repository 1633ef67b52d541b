// Shading normals at silhouettes (docs/DESIGN.md §5.4): on a coarse smooth mesh the interpolated normal
// of a front-facing triangle near the silhouette can face away from the viewer. The side is decided by
// the triangle and such a normal is bent back towards the viewer, in the rasteriser and the reference
// alike, so no silhouette pixel goes black. A low-poly sphere under a constant sky is lit about equally
// everywhere: every fully covered object pixel must be at least 40% of the median object pixel (with
// the normal turned into the surface they were near 0). The sphere mirrored (negative determinant) must
// give the same picture (it is the same set of triangles in the world but for the quads' diagonals):
// facing follows the object's winding through the mirror, not its screen winding.
// With MSAA, a fine diffuse sphere under the same sky must be exactly rho_d everywhere it covers a pixel
// wholly: nothing can shadow it but itself, and every triangle of it must see its own plane in the
// shadow atlas, whichever of its pixel's samples it covers (its receiver-plane bias included).
#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/ext/matrix_transform.hpp>

#include "env/cells.h"
#include "env/environment.h"
#include "env/latlong.h"
#include "env/prefilter.h"
#include "gl_fixture.h"
#include "reference/reference.h"
#include "render/frame_plan.h"
#include "render/renderer.h"
#include "scene/meshes.h"

namespace envshadow::testing {
namespace {

using SilhouetteTest = GlTest;

constexpr int kSize = 64;
constexpr double kDarkFraction = 0.4;
constexpr double kMirrorDifference = 0.02;  // mean luminance difference, mirrored or not (about rho_d = 0.7)

// A sphere at the origin under builtin:constant, seen from (0, 0.5, 3).
Scene sphere_under_constant_sky(SphereShape shape, Material material, float fov_y_degrees,
                                glm::mat4 transform = glm::mat4(1.0f)) {
    Scene scene;
    scene.environment.source = "builtin:constant";
    scene.camera.position = {0.0f, 0.5f, 3.0f};
    scene.camera.target = {0.0f, 0.0f, 0.0f};
    scene.camera.fov_y_degrees = fov_y_degrees;
    Object object;
    object.mesh = std::make_shared<Mesh>(make_mesh(shape));
    object.transform = transform;
    object.material = material;
    scene.objects.push_back(std::move(object));
    return scene;
}

Scene low_poly_sphere(bool mirrored) {
    const glm::mat4 transform = mirrored ? glm::scale(glm::mat4(1.0f), glm::vec3(-1.0f, 1.0f, 1.0f)) : glm::mat4(1.0f);
    return sphere_under_constant_sky(SphereShape{0.8f, 10}, Material{glm::vec3(0.7f), 0.2f, 10.0f}, 40.0f,
                                     transform);  // 10 segments, 5 bands
}

// Fully covered object pixels (alpha 1) darker than kDarkFraction of their median luminance.
struct DarkPixels {
    int object_pixels = 0, dark = 0;
    double median = 0.0, darkest = 0.0;
};

// Mean absolute difference of the luminance over the pixels both call objects, relative to `scale`.
double mean_difference(const Image& a, const Image& b, double scale) {
    double sum = 0.0;
    int pixels = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
        if (a.pixels[i].a < 1.0f || b.pixels[i].a < 1.0f) continue;
        sum += std::abs(latlong::luminance(glm::dvec3(glm::vec3(a.pixels[i]))) -
                        latlong::luminance(glm::dvec3(glm::vec3(b.pixels[i]))));
        ++pixels;
    }
    return pixels ? sum / double(pixels) / scale : 1.0;
}

DarkPixels dark_pixels(const Image& image) {
    std::vector<double> luminance;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            const glm::vec4 p = image.at(x, y);
            if (p.a >= 1.0f) luminance.push_back(latlong::luminance(glm::dvec3(glm::vec3(p))));
        }
    DarkPixels result;
    result.object_pixels = int(luminance.size());
    if (luminance.empty()) return result;
    std::vector<double> sorted = luminance;
    std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(sorted.size() / 2), sorted.end());
    result.median = sorted[sorted.size() / 2];
    result.darkest = *std::min_element(luminance.begin(), luminance.end());
    for (double l : luminance) result.dark += l < kDarkFraction * result.median ? 1 : 0;
    return result;
}

TEST_P(SilhouetteTest, RasteriserShowsNoDarkSilhouettePixels) {
    const EnvironmentMap map = load_environment("builtin:constant");
    std::vector<Image> images;
    for (bool mirrored : {false, true}) {
        const Scene scene = low_poly_sphere(mirrored);
        render::Renderer renderer(render::RenderSettings{});
        renderer.set_scene(scene);
        renderer.set_environment(map);
        renderer.set_lights(decompose(map, {.method = Method::lloyd, .lights = 32}).cells);
        renderer.render(0.0, render::camera_view(scene, kSize, kSize));
        images.push_back(renderer.read_back());
        const DarkPixels found = dark_pixels(images.back());
        EXPECT_GT(found.object_pixels, kSize * kSize / 8);
        EXPECT_GT(found.median, 0.3);  // about rho_d under a unit sky
        EXPECT_EQ(found.dark, 0) << "mirrored " << mirrored << ": " << found.dark << " of " << found.object_pixels
                                 << " pixels, darkest " << found.darkest << ", median " << found.median;
    }
    EXPECT_LT(mean_difference(images[0], images[1], 1.0), kMirrorDifference);
}

TEST_P(SilhouetteTest, MultisampledConvexSphereShadowsNoPixelItCovers) {
    constexpr float kRhoD = 0.7f, kTolerance = 0.01f;  // relative
    const Scene scene = sphere_under_constant_sky(SphereShape{0.6f, 64}, Material{glm::vec3(kRhoD), 0.0f, 1.0f}, 45.0f);
    const EnvironmentMap map = load_environment("builtin:constant");
    for (int samples : {1, 4}) {
        render::RenderSettings settings;
        settings.msaa = samples;
        settings.shading = render::ShadingMode::ratio;  // exact where nothing is shadowed; cells are a quadrature
        render::Renderer renderer(settings);
        ASSERT_EQ(renderer.samples(), samples);
        renderer.set_scene(scene);
        renderer.set_environment(map);
        renderer.set_prefiltered(prefilter_environment(map, Hemisphere::full));
        renderer.set_lights(decompose(map, {.method = Method::lloyd, .lights = 32}).cells);
        renderer.render(0.0, render::camera_view(scene, 64, 48));
        const Image image = renderer.read_back();
        int covered = 0, off = 0;
        float worst = kRhoD;
        for (int y = 0; y < image.height; ++y)
            for (int x = 0; x < image.width; ++x) {
                const glm::vec4 p = image.at(x, y);
                if (p.a < 1.0f) continue;
                ++covered;
                for (int c = 0; c < 3; ++c) {
                    if (std::abs(p[c] - kRhoD) <= kTolerance * kRhoD) continue;
                    if (std::abs(p[c] - kRhoD) > std::abs(worst - kRhoD)) worst = p[c];
                    ++off;
                    break;
                }
            }
        EXPECT_GT(covered, 64 * 48 / 8);
        EXPECT_EQ(off, 0) << samples << " samples: " << off << " of " << covered
                          << " covered pixels off rho_d, the worst " << worst;
    }
}

// The reference needs no GL context.
TEST(SilhouetteReferenceTest, ReferenceShowsNoDarkSilhouettePixels) {
    const EnvironmentMap map = load_environment("builtin:constant");
    std::vector<Image> images;
    for (bool mirrored : {false, true}) {
        reference::ReferenceOptions options;
        options.width = options.height = kSize;
        options.target_error = 0.03;
        options.pixel_filter = reference::PixelFilter::point;  // one shading point per pixel, at its centre
        images.push_back(reference::render_reference(low_poly_sphere(mirrored), map, options).image);
        const DarkPixels found = dark_pixels(images.back());
        EXPECT_GT(found.object_pixels, kSize * kSize / 8);
        EXPECT_GT(found.median, 0.3);
        EXPECT_EQ(found.dark, 0) << "mirrored " << mirrored << ": " << found.dark << " of " << found.object_pixels
                                 << " pixels, darkest " << found.darkest << ", median " << found.median;
    }
    EXPECT_LT(mean_difference(images[0], images[1], 1.0), kMirrorDifference);
}

ENVSHADOW_INSTANTIATE_GL_TEST(SilhouetteTest);

}  // namespace
}  // namespace envshadow::testing
