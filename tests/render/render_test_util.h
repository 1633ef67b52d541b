#pragma once
// What the renderer's GL tests share: a camera looking at a point, a textured quad facing the camera (and
// its quadrants' centres), the commands' default settings and the shading paths, a scene rendered with its
// map's lights and prefiltered levels or through the reference, and the PSNR of one linear frame against
// another over the reference's object pixels.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <utility>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/trigonometric.hpp>

#include "core/image.h"
#include "env/cells.h"
#include "env/environment.h"
#include "env/ggx_prefilter.h"
#include "env/prefilter.h"
#include "reference/reference.h"
#include "render/frame_plan.h"
#include "render/renderer.h"
#include "scene/meshes.h"

namespace envshadow::testing {

inline render::CameraView look_at(glm::vec3 eye, glm::vec3 target, int width, int height, float fov_degrees = 40.0f) {
    render::CameraView view;
    view.eye = eye;
    view.view_from_world = glm::lookAt(eye, target, glm::vec3(0, 1, 0));
    view.clip_from_view = glm::perspective(glm::radians(fov_degrees), float(width) / float(height), 0.1f, 50.0f);
    view.width = width;
    view.height = height;
    return view;
}

// The ground of the tests' open scenes: a 20 m plane, diffuse 0.7, casting no shadow.
inline Object ground_plane() {
    Object ground;
    ground.mesh = std::make_shared<Mesh>(make_mesh(PlaneShape{20.0f}));
    ground.material.rho_d = glm::vec3(0.7f);
    ground.casts_shadows = false;
    return ground;
}

// 2x2 texels, for nearest filtering: red, green (top row), blue, white.
inline std::shared_ptr<const TextureImage> four_colours() {
    auto image = std::make_shared<TextureImage>();
    image->width = image->height = 2;
    image->rgba = {255, 0, 0,   255, 0,   255, 0,   255,   // top row: red, green
                   0,   0, 255, 255, 255, 255, 255, 255};  // bottom row: blue, white
    return image;
}

// A 2 m quad of `material` facing +Z under a unit sky (builtin:constant), filling most of a square picture
// from the camera at z = 3; uv (0, 0) at its top-left corner.
inline Scene quad_facing_the_camera(const Material& material) {
    Scene scene;
    scene.environment.source = "builtin:constant";
    scene.camera.position = {0.0f, 0.0f, 3.0f};
    scene.camera.target = {0.0f, 0.0f, 0.0f};
    scene.camera.fov_y_degrees = 45.0f;
    auto mesh = std::make_shared<Mesh>();
    mesh->positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    mesh->normals.assign(4, glm::vec3(0, 0, 1));
    mesh->texcoords = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    mesh->indices = {0, 1, 2, 0, 2, 3};
    mesh->compute_bounds();
    Object object;
    object.mesh = mesh;
    object.material = material;
    scene.objects.push_back(std::move(object));
    return scene;
}

// The centre of quadrant (qx, qy), from the top left, of a square `image` (as quad_facing_the_camera fills it).
inline glm::vec3 quadrant_centre(const Image& image, int qx, int qy) {
    return glm::vec3(image.at(image.width * (1 + 2 * qx) / 4, image.height * (1 + 2 * qy) / 4));
}

// The settings the commands start from (app/setting_options.h): ratio shading, soft shadows, the
// shadowed fraction at half rate, MSAA 4.
inline render::RenderSettings commands_defaults() {
    render::RenderSettings s;
    s.shading = render::ShadingMode::ratio;
    s.shadows = render::ShadowMode::soft;
    s.shadow_rate = render::ShadowRate::half;
    s.msaa = 4;
    return s;
}

// The shading paths a material property must take alike: the paper's cells, ratio shading at the commands'
// defaults, and glTF's BRDF in ratio shading; `phong` is drawn by the first two, `gltf` by the third.
struct ShadingPath {
    const char* name;
    Material material;
    render::RenderSettings settings;
};
inline std::array<ShadingPath, 3> shading_paths(const Material& phong, const Material& gltf) {
    return {{{"cells", phong, {}},
             {"ratio, fraction at half rate, MSAA 4", phong, commands_defaults()},
             {"glTF's BRDF in ratio shading", gltf, commands_defaults()}}};
}

// A Renderer with `settings` holding `scene`: the lights decomposed from `map` with `cells`, the map prefiltered
// over the same hemisphere for ratio shading (the Phong and the GGX levels). For tests that render more than one
// frame or change it between frames.
inline std::unique_ptr<render::Renderer> prepared_renderer(const Scene& scene, const EnvironmentMap& map,
                                                           const render::RenderSettings& settings,
                                                           const DecomposeOptions& cells) {
    auto renderer = std::make_unique<render::Renderer>(settings);
    renderer->set_scene(scene);
    renderer->set_environment(map);
    renderer->set_prefiltered(prefilter_environment(map, cells.hemisphere));
    const CompactSourceSplit split = split_compact_sources(map, cells.hemisphere);
    renderer->set_ggx_prefiltered(prefilter_environment_ggx(split.rest, cells.hemisphere), split);
    renderer->set_lights(decompose(map, cells).cells);
    return renderer;
}

// `scene` drawn by prepared_renderer at width x height.
inline Image render_scene(const Scene& scene, const EnvironmentMap& map, const render::RenderSettings& settings,
                          int width, int height, const DecomposeOptions& cells) {
    const auto renderer = prepared_renderer(scene, map, settings, cells);
    renderer->render(0.0, render::camera_view(scene, width, height));
    return renderer->read_back();
}

inline Image render_scene(const Scene& scene, const render::RenderSettings& settings, int width, int height,
                          const DecomposeOptions& cells) {
    return render_scene(scene, load_environment(scene.environment.source), settings, width, height, cells);
}

// `scene` through the reference renderer at width x height (needs envshadow_reference), each pixel to
// `target_error`, with `filter` (point: the pixel's centre, as --msaa 1 shades it).
inline Image reference_image(const Scene& scene, int width, int height, double target_error,
                             reference::PixelFilter filter = reference::PixelFilter::point) {
    reference::ReferenceOptions options;
    options.width = width;
    options.height = height;
    options.target_error = target_error;
    options.pixel_filter = filter;
    return reference::render_reference(scene, load_environment(scene.environment.source), options).image;
}

// PSNR (dB) of `a` against `reference` over the RGB of the pixels where the reference has alpha 1 (the
// objects); the peak is the reference's largest value there. `pixels`, if given, hears how many.
inline double object_psnr(const Image& a, const Image& reference, long* pixels = nullptr) {
    double squared = 0.0, peak = 0.0;
    long count = 0;
    for (std::size_t i = 0; i < reference.pixels.size(); ++i) {
        if (reference.pixels[i].a < 0.5f) continue;
        for (int c = 0; c < 3; ++c) {
            const double d = double(a.pixels[i][c]) - double(reference.pixels[i][c]);
            squared += d * d;
            peak = std::max(peak, double(reference.pixels[i][c]));
        }
        ++count;
    }
    if (pixels) *pixels = count;
    const double mse = squared / double(3 * std::max(count, 1L));
    return mse > 0.0 ? 10.0 * std::log10(peak * peak / mse) : std::numeric_limits<double>::infinity();
}

}  // namespace envshadow::testing
