#include "reference/image_compare.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <limits>
#include <vector>

#include "core/error.h"
#include "core/image_compare.h"

namespace envshadow::reference {
namespace {

std::string prefix(const std::string& what) {
    return what.empty() ? std::string() : what + ": ";
}

// Which pixels are compared (see the header).
std::vector<bool> selection(const Image& a, const Image& b, const Image8* mask, const std::string& what) {
    if (a.width != b.width || a.height != b.height) {
        throw InputError(prefix(what) + "images differ in size (" + std::to_string(a.width) + "x" +
                         std::to_string(a.height) + " and " + std::to_string(b.width) + "x" + std::to_string(b.height) +
                         ")");
    }
    if (mask && (mask->width != a.width || mask->height != a.height)) {
        throw InputError(prefix(what) + "mask is " + std::to_string(mask->width) + "x" + std::to_string(mask->height) +
                         ", images are " + std::to_string(a.width) + "x" + std::to_string(a.height));
    }
    std::vector<bool> selected(a.pixels.size());
    for (int y = 0; y < a.height; ++y) {
        for (int x = 0; x < a.width; ++x) {
            const std::size_t k = std::size_t(y) * std::size_t(a.width) + std::size_t(x);
            selected[k] = mask ? (mask->at(x, y)[0] > 127 && mask->at(x, y)[3] > 127) : a.pixels[k].a > 0.5f;
        }
    }
    return selected;
}

}  // namespace

Comparison compare_images(const Image& a, const Image& b, const Image8* mask, const std::string& what) {
    const std::vector<bool> selected = selection(a, b, mask, what);
    const HdrDifference d = compare_hdr(a, b, selected);  // a is the reference
    if (d.pixels == 0)
        throw InputError(prefix(what) + "no pixels to compare (no alpha > 0.5 in the first image, or an empty mask)");
    if (std::isnan(d.relative_rmse) || std::isnan(d.psnr)) throw InputError(prefix(what) + "non-finite pixel values");
    return {d.relative_rmse, d.psnr, d.pixels};
}

Image8 relative_error_image(const Image& a, const Image& b, const Image8* mask, double full_scale) {
    const std::vector<bool> selected = selection(a, b, mask, "");
    double sum = 0.0;
    long long count = 0;
    for (std::size_t k = 0; k < selected.size(); ++k) {
        if (!selected[k]) continue;
        sum += glm::length(glm::dvec3(a.pixels[k]));
        ++count;
    }
    const double floor = count > 0 ? std::max(1e-3 * sum / double(count), 1e-30) : 1e-30;
    // Black, blue, green, yellow, red at 0, 1/4, 1/2, 3/4, 1 of full scale.
    const glm::dvec3 ramp[] = {{0, 0, 0}, {0, 0, 1}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}};
    Image8 out(a.width, a.height);
    for (int y = 0; y < a.height; ++y) {
        for (int x = 0; x < a.width; ++x) {
            const std::size_t k = std::size_t(y) * std::size_t(a.width) + std::size_t(x);
            glm::dvec3 colour;
            if (selected[k]) {
                const glm::dvec3 va(a.pixels[k]), vb(b.pixels[k]);
                const double error = glm::length(vb - va) / std::max(glm::length(va), floor);
                const double ratio = error / full_scale;  // NaN (a NaN scale or texel) shows as full scale
                const double position = (std::isnan(ratio) ? 1.0 : std::clamp(ratio, 0.0, 1.0)) * 4.0;
                const int segment = std::min(int(position), 3);
                const double f = position - segment;
                colour = (1.0 - f) * ramp[segment] + f * ramp[segment + 1];
            } else {
                double luminance = 0.2126 * a.pixels[k].r + 0.7152 * a.pixels[k].g + 0.0722 * a.pixels[k].b;
                if (!std::isfinite(luminance)) luminance = 0.0;
                colour = glm::dvec3(0.15 + 0.2 * std::clamp(luminance / (1.0 + luminance), 0.0, 1.0));
            }
            std::uint8_t* p = out.at(x, y);
            for (int c = 0; c < 3; ++c) p[c] = std::uint8_t(std::lround(255.0 * std::clamp(colour[c], 0.0, 1.0)));
            p[3] = 255;
        }
    }
    return out;
}

}  // namespace envshadow::reference
