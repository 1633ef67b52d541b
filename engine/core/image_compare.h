#pragma once
// Image differences, two ways:
//   - for regression screenshots (8-bit, tone-mapped): mean and max absolute difference and the
//     share of pixels over a per-pixel threshold, checked against a Tolerance (never exact bytes);
//   - for accuracy (linear HDR): relative RMSE and PSNR over a mask of object pixels.
#include <optional>
#include <string>
#include <vector>

#include "core/image.h"

namespace envshadow {

struct Tolerance {
    double max_mean = 1.0;               // mean |a - b| over all channels, in 8-bit levels
    int pixel_threshold = 24;            // a pixel "differs" when any channel differs by more than this
    double max_differing_share = 0.002;  // share of pixels allowed to differ
};

struct ImageDifference {
    double mean = 0.0;   // mean |a - b| over RGB, 8-bit levels
    int max = 0;         // largest channel difference
    long differing = 0;  // pixels over Tolerance::pixel_threshold
    long pixels = 0;
    double psnr = 0.0;  // dB, RGB; infinity for identical images

    bool within(const Tolerance& t) const {
        return mean <= t.max_mean && double(differing) <= t.max_differing_share * double(pixels);
    }
    std::string summary() const;  // "mean=0.12 max=9 differing=3/49152 (0.006%) psnr=51.2 dB"
};

// Throws InputError when the sizes differ.
ImageDifference compare_images(const Image8& a, const Image8& b, int pixel_threshold = Tolerance{}.pixel_threshold);

// [a | b | |a - b| amplified] for a person to look at when a comparison fails.
Image8 side_by_side(const Image8& a, const Image8& b);

struct HdrDifference {
    double relative_rmse = 0.0;  // sqrt(mean |image - reference|^2) / sqrt(mean |reference|^2) over masked RGB
    double psnr = 0.0;           // dB, peak = max of the reference over the mask
    long pixels = 0;             // pixels in the mask
};

// Over pixels where mask[i] is true (all pixels when the mask is empty). The reference comes first, as in
// reference::compare_images and `envshadow compare A B`. Throws InputError on size mismatch.
HdrDifference compare_hdr(const Image& reference, const Image& image, const std::vector<bool>& mask = {});

}  // namespace envshadow
