#include "core/image_compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include "core/error.h"

namespace envshadow {

std::string ImageDifference::summary() const {
    char text[160];
    std::snprintf(text, sizeof text, "mean=%.3f max=%d differing=%ld/%ld (%.3f%%) psnr=%.1f dB", mean, max, differing,
                  pixels, pixels ? 100.0 * double(differing) / double(pixels) : 0.0, psnr);
    return text;
}

ImageDifference compare_images(const Image8& a, const Image8& b, int pixel_threshold) {
    if (a.width != b.width || a.height != b.height)
        throw InputError("image sizes differ: " + std::to_string(a.width) + "x" + std::to_string(a.height) + " vs " +
                         std::to_string(b.width) + "x" + std::to_string(b.height));
    ImageDifference d;
    d.pixels = long(a.width) * a.height;
    double sum = 0.0, sum_sq = 0.0;
    for (long p = 0; p < d.pixels; ++p) {
        int pixel_max = 0;
        for (int c = 0; c < 3; ++c) {
            const int diff = std::abs(int(a.rgba[size_t(p) * 4 + c]) - int(b.rgba[size_t(p) * 4 + c]));
            sum += diff;
            sum_sq += double(diff) * diff;
            pixel_max = std::max(pixel_max, diff);
        }
        d.max = std::max(d.max, pixel_max);
        if (pixel_max > pixel_threshold) ++d.differing;
    }
    const double samples = 3.0 * double(std::max(d.pixels, 1L));
    d.mean = sum / samples;
    const double mse = sum_sq / samples;
    d.psnr = mse > 0.0 ? 10.0 * std::log10(255.0 * 255.0 / mse) : std::numeric_limits<double>::infinity();
    return d;
}

Image8 side_by_side(const Image8& a, const Image8& b) {
    const int w = std::max(a.width, b.width), h = std::max(a.height, b.height);
    Image8 out(3 * w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool in_a = x < a.width && y < a.height, in_b = x < b.width && y < b.height;
            for (int c = 0; c < 4; ++c) {
                const int va = in_a ? a.at(x, y)[c] : 0, vb = in_b ? b.at(x, y)[c] : 0;
                out.at(x, y)[c] = std::uint8_t(va);
                out.at(x + w, y)[c] = std::uint8_t(vb);
                // Differences amplified 4x so that small ones are visible; alpha opaque.
                out.at(x + 2 * w, y)[c] = c == 3 ? 255 : std::uint8_t(std::min(255, 4 * std::abs(va - vb)));
            }
            out.at(x, y)[3] = out.at(x + w, y)[3] = 255;
        }
    return out;
}

HdrDifference compare_hdr(const Image& reference, const Image& image, const std::vector<bool>& mask) {
    if (image.width != reference.width || image.height != reference.height)
        throw InputError("image sizes differ: " + std::to_string(reference.width) + "x" +
                         std::to_string(reference.height) + " vs " + std::to_string(image.width) + "x" +
                         std::to_string(image.height));
    if (!mask.empty() && mask.size() != reference.pixels.size()) throw InputError("mask size differs from the image");
    HdrDifference d;
    double err = 0.0, ref = 0.0, peak = 0.0;
    for (size_t i = 0; i < reference.pixels.size(); ++i) {
        if (!mask.empty() && !mask[i]) continue;
        ++d.pixels;
        for (int c = 0; c < 3; ++c) {
            const double e = double(image.pixels[i][c]) - double(reference.pixels[i][c]);
            err += e * e;
            ref += double(reference.pixels[i][c]) * reference.pixels[i][c];
            peak = std::max(peak, double(reference.pixels[i][c]));
        }
    }
    if (d.pixels == 0) return d;
    const double n = 3.0 * double(d.pixels);
    d.relative_rmse = ref > 0.0 ? std::sqrt(err / n) / std::sqrt(ref / n)
                                : (err > 0.0 ? std::numeric_limits<double>::infinity() : 0.0);
    d.psnr = err > 0.0 ? 10.0 * std::log10(peak * peak / (err / n)) : std::numeric_limits<double>::infinity();
    return d;
}

}  // namespace envshadow
