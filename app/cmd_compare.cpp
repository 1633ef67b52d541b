// `envshadow compare A.exr B.exr`: rel_rmse and PSNR of B against the reference A over the object pixels
// (engine/reference/image_compare.h), and optionally a false-colour picture of the relative error.
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "commands.h"
#include "core/error.h"
#include "core/image.h"
#include "reference/image_compare.h"

namespace envshadow::app {
namespace {

struct CompareOptions {
    std::string a, b, mask, diff;
    double diff_scale = 0.1;
};

}  // namespace

Command add_compare_command(CLI::App& parent) {
    auto o = std::make_shared<CompareOptions>();
    CLI::App* app = parent.add_subcommand("compare", "Relative RMSE and PSNR of two EXR images over object pixels");
    app->add_option("a", o->a, "Reference EXR (its alpha > 0.5 marks the pixels compared)")->required();
    app->add_option("b", o->b, "EXR to judge")->required();
    app->add_option("--mask", o->mask, "PNG: white pixels are compared (instead of A's alpha)");
    app->add_option("--diff", o->diff, "PNG to write: relative error in false colour (red at --diff-scale)");
    app->add_option("--diff-scale", o->diff_scale, "Relative error shown as red (default 0.1)")
        ->check(CLI::Range(1e-6, 1e6))
        ->check(finite_number());
    return {
        app, [o] {
            const ExrContents a = read_exr(o->a), b = read_exr(o->b);
            std::optional<Image8> mask;
            if (!o->mask.empty()) mask = read_png(o->mask);
            const std::string what = o->a + " vs " + o->b + (o->mask.empty() ? "" : " (mask " + o->mask + ")");
            const reference::Comparison c = reference::compare_images(a.image, b.image, mask ? &*mask : nullptr, what);
            if (std::isinf(c.psnr)) {
                std::printf("rel_rmse=%.6g psnr=inf pixels=%lld\n", c.rel_rmse, c.pixels);
            } else {
                std::printf("rel_rmse=%.6g psnr=%.3f pixels=%lld\n", c.rel_rmse, c.psnr, c.pixels);
            }
            if (!o->diff.empty()) {
                write_png(o->diff,
                          reference::relative_error_image(a.image, b.image, mask ? &*mask : nullptr, o->diff_scale));
            }
            return 0;
        }};
}

}  // namespace envshadow::app
