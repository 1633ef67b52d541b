#pragma once
// Ground truth for the renderer (docs/DESIGN.md §6 `envshadow reference`): per pixel, the full integral
//   L = integral over the sphere of L_env(w) (k_d cos theta' + k_s cos^n psi) V(x, w) dw   (cos theta' > 0)
// with the renderer's camera, geometry, shading normals, BRDF (docs/DESIGN.md §2) and environment rotation;
// for a material with metallic_roughness, glTF's BRDF in place of its Phong stand-in (docs/DESIGN.md §11):
//   L = integral of L_env(w) (f_diffuse + f_specular)(v, w) cos theta' V(x, w) dw   (gltf_brdf::evaluate_lobes)
// with the base-colour texture multiplying base_color as it does rho_d.
// Each pixel's value is the mean of that radiance over the pixel's square (PixelFilter::box: camera rays
// spread over the pixel, equal weights, as the renderer's multisample resolve averages its samples), or
// its value at the pixel's centre (PixelFilter::point: one camera ray, as the renderer at one sample).
// The renderer's conventions, held here too: row 0 at the top; the interpolated shading normal, turned
// towards the viewer; the environment alone lights (no interreflection: V = 0 where an object blocks);
// only objects with casts_shadows block; a scene with a ground plane hides every direction below the
// horizon (Scene::ground_height: "lights under it see nothing"); the map is constant over each texel
// (the function the decomposition sums).
// Monte Carlo with known error: each pixel takes rounds of samples from three strategies (the map's
// light above its mean, see EnvironmentSampler; the cosine lobe; the specular lobe, Phong's or GGX's visible
// normals; each a jittered grid per round; under the box filter a round spreads over the pixel: each position
// of a jittered grid over its square takes one sample of each strategy at its own camera ray's hit); the
// diffuse term combines the map's and the cosine's samples, the specular term the map's and the specular
// lobe's (power heuristic).
// Rounds are independent, so their spread gives the standard error (under the box filter, of the pixel's
// mean: it holds the variation over the pixel's square too). A pilot of 8 rounds plans how many fresh rounds bring
// every channel's standard error below `target_error` of its value; the value and its error come from those fresh
// rounds only (one top-up if the plan fell short). Pixels that need many rounds take finer ones (12 x 12, 24 x 24 per
// strategy). The reported error adds value / N (N samples in those rounds) to the rounds' spread: what no sample met
// leaves no spread, and a feature of weight 1/N can go unseen.
#include <atomic>
#include <cstdint>
#include <functional>

#include "core/image.h"
#include "env/environment.h"
#include "scene/scene.h"

namespace envshadow::reference {

// How a pixel's value weighs the image plane: its centre, or its square with equal weights (docs/DESIGN.md §6).
enum class PixelFilter { point, box };

struct ReferenceOptions {
    int width = 640, height = 360;
    double time = 0.0;                // seconds, for animated objects
    long long max_samples = 1 << 18;  // per pixel (roughly); a pixel that reaches it stops with the error it has
    double target_error = 0.0025;     // relative standard error at which a pixel stops (half the 0.5% promise,
                                      // so that the noise of the error estimate itself cannot break it)
    std::uint64_t seed = 1;
    PixelFilter pixel_filter = PixelFilter::box;
    // Called after each image row, from the worker threads (so at the same time from several):
    // rows finished so far out of `rows_total`. For a progress line; may be empty.
    std::function<void(int rows_done, int rows_total)> on_row_done;
    // When it reads true, the render stops after the rows in flight and throws Interrupted (Ctrl-C).
    const std::atomic<bool>* stop = nullptr;
};

struct ReferenceStatistics {
    long long object_pixels = 0;       // pixels that an object covers, wholly or in part
    long long dark_pixels = 0;         // object pixels whose channels are all darker than 2% of the map's mean
                                       // radiance: they stop on target_error times that floor, and are left
                                       // out of the relative errors below
    double mean_relative_error = 0.0;  // largest over channels above the floor of standard error / value
    double p99_relative_error = 0.0;
    double max_relative_error = 0.0;
    long long pixels_over_half_percent = 0;
    double mean_samples = 0.0;  // per object pixel
    long long shadow_rays = 0;
    double seconds = 0.0;
};

struct ReferenceImage {
    Image image;           // linear RGB; alpha: the share of the pixel that objects cover (box filter: a fraction,
                           // estimated from the samples' camera rays; point filter: 1 or 0), the rest shows the map
    Image standard_error;  // per pixel, RGB standard error of the value (see above); alpha: samples taken
    ReferenceStatistics statistics;
};

// `map` is the scene's environment (or its override); its rotation is scene.environment.rotation_degrees.
// Throws Interrupted when options.stop is set before the last row is done.
ReferenceImage render_reference(const Scene& scene, const EnvironmentMap& map, const ReferenceOptions& options);

}  // namespace envshadow::reference
