#pragma once
// Differences of 8-bit (tone-mapped) pictures for the regression screenshots: mean and max absolute
// difference and the share of pixels over a per-pixel threshold, checked against a Tolerance (never
// exact bytes). Accuracy against ground truth (linear HDR) is engine/reference/image_compare.h.
#include <string>

#include "core/image.h"

namespace envshadow {

struct Tolerance {
    double max_mean = 1.0;             // mean |a - b| over all channels, in 8-bit levels
    int pixel_threshold = 24;          // a pixel "differs" when any channel differs by more than this
    double max_differing_share = 0.002;  // share of pixels allowed to differ
};

struct ImageDifference {
    double mean = 0.0;        // mean |a - b| over RGB, 8-bit levels
    int max = 0;              // largest channel difference
    long differing = 0;       // pixels over Tolerance::pixel_threshold
    long pixels = 0;
    double psnr = 0.0;        // dB, RGB; infinity for identical images

    bool within(const Tolerance& t) const {
        return mean <= t.max_mean && double(differing) <= t.max_differing_share * double(pixels);
    }
    std::string summary() const;  // "mean=0.12 max=9 differing=3/49152 (0.006%) psnr=51.2 dB"
};

// Throws InputError when the sizes differ.
ImageDifference compare_images(const Image8& a, const Image8& b, int pixel_threshold = Tolerance{}.pixel_threshold);

// [a | b | |a - b| amplified] for a person to look at when a comparison fails.
Image8 side_by_side(const Image8& a, const Image8& b);

}  // namespace envshadow
