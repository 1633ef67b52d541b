#pragma once
// `envshadow compare` (docs/DESIGN.md §6): how far an image B is from a reference A over the pixels covered
// by objects. Over those pixels and the three colour channels:
//   rel_rmse = sqrt(sum (B - A)^2 / sum A^2)    (RMS error relative to the reference's RMS value)
//   psnr     = 10 log10(peak^2 / mean (B - A)^2), peak = the largest channel value of A there
// so B = (1 + e) A gives rel_rmse = e exactly, whatever A is.
#include <string>

#include "core/image.h"

namespace envshadow::reference {

struct Comparison {
    double rel_rmse = 0.0;
    double psnr = 0.0;     // +inf when the images are equal
    long long pixels = 0;  // pixels compared
};

// Pixels compared: alpha > 0.5 in `a`, or, with a mask, the mask's pixels whose first channel and alpha
// are both above 127 (white on black). Throws InputError (naming `what`) on a size mismatch or when
// no pixel is selected.
Comparison compare_images(const Image& a, const Image& b, const Image8* mask = nullptr, const std::string& what = "");

// False colour of the per-pixel relative error |B - A| / max(|A|, 1e-3 mean |A|) (|.| the RGB length):
// black at 0, through blue, green and yellow to red at `full_scale` and above; pixels not compared
// show A's luminance, tone-mapped and dimmed to a grey backdrop.
Image8 relative_error_image(const Image& a, const Image& b, const Image8* mask = nullptr, double full_scale = 0.1);

}  // namespace envshadow::reference
