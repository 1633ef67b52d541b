#pragma once
// What the renderer's GL tests share: a camera looking at a point, and the PSNR of one linear frame
// against another over the reference's object pixels.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/trigonometric.hpp>

#include "core/image.h"
#include "render/frame_plan.h"

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
