// `envshadow reference`: the ground truth of a scene (engine/reference), as linear EXR and optional PNG.
// Parse, load the scene and its map, render, report the standard errors, write.
#include <tbb/info.h>

#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

#include "commands.h"
#include "core/image.h"
#include "inputs.h"
#include "progress.h"
#include "reference/reference.h"

namespace envshadow::app {
namespace {

struct ReferenceCommandOptions {
    CommonOptions common;  // --scene, --env, --seed, --width, --height
    std::string exr, png, error_exr, tonemap = "aces", pixel_filter = "box";
    reference::ReferenceOptions render;
};

void print_statistics(const reference::ReferenceOptions& options, const reference::ReferenceStatistics& s) {
    std::printf("reference: %dx%d, %lld object pixels, %d threads\n", options.width, options.height, s.object_pixels,
                tbb::info::default_concurrency());
    std::printf(
        "standard error / value: mean %.3f%%, p99 %.3f%%, max %.3f%% (%lld pixels over 0.5%%; %lld dark pixels left "
        "out)\n",
        100.0 * s.mean_relative_error, 100.0 * s.p99_relative_error, 100.0 * s.max_relative_error,
        s.pixels_over_half_percent, s.dark_pixels);
    std::printf("samples per object pixel: %.0f; shadow rays: %lld; %.1f s (%.2f M rays/s)\n", s.mean_samples,
                s.shadow_rays, s.seconds, s.seconds > 0.0 ? double(s.shadow_rays) / s.seconds * 1e-6 : 0.0);
}

}  // namespace

Command add_reference_command(CLI::App& parent) {
    auto o = std::make_shared<ReferenceCommandOptions>();
    CLI::App* app = parent.add_subcommand("reference", "Render the ground truth with Embree (CPU)");
    o->common.width = o->render.width;
    o->common.height = o->render.height;
    o->common.seed = o->render.seed;
    CommonOptionSet set;
    set.hemisphere = false;  // the reference integrates the whole environment, hiding what the ground hides
    set.lights = false;      // nor --method: the reference integrates the map itself
    set.backend = false;
    add_common_options(app, &o->common, set);
    add_time_option(app, &o->render.time);
    app->add_option("--exr", o->exr,
                    "Linear EXR to write (alpha: the share of each pixel that objects cover; the rest shows the map)")
        ->required();
    app->add_option("--pixel-filter", o->pixel_filter,
                    "box (default): each pixel's mean over its square, as render's --msaa resolve; point: the "
                    "value at each pixel's centre, as render --msaa 1")
        ->check(CLI::IsMember({"box", "point"}));
    app->add_option("--png", o->png, "Tone-mapped PNG to write (the scene's exposure, --tonemap)");
    add_tonemap_option(app, &o->tonemap);
    app->add_option("--samples", o->render.max_samples, "Most samples per pixel (a pixel stops earlier at --error)")
        ->check(CLI::Range(1LL, 1LL << 40));
    app->add_option("--error", o->render.target_error,
                    "Relative standard error at which a pixel stops (default 0.0025, half the 0.5% promised)")
        ->check(CLI::Range(1e-6, 1.0))
        ->check(finite_number());  // a NaN target is never met and every pixel would take --samples
    app->add_option("--error-exr", o->error_exr, "EXR of the per-pixel standard error (alpha: samples taken)");
    return {app, [o] {
                o->render.width = o->common.width;
                o->render.height = o->common.height;
                o->render.seed = o->common.seed;
                o->render.pixel_filter =
                    o->pixel_filter == "point" ? reference::PixelFilter::point : reference::PixelFilter::box;
                // The map at --time, as `render` lights it: builtin:sky's sun moves with the animation.
                const Inputs inputs = load_inputs(o->common.scene, o->common.env, o->render.time);
                const Scene& scene = inputs.scene;
                // Ctrl-C stops the render and nothing is written; once the render is done, the files
                // are written whole (a Ctrl-C then waits for them).
                const StopOnInterrupt stop_on_interrupt;
                reference::ReferenceImage result;
                {
                    ProgressLine progress("reference", "rows");
                    o->render.stop = StopOnInterrupt::flag();
                    o->render.on_row_done = [&](int done, int total) { progress.update(done, total); };
                    result = reference::render_reference(scene, inputs.map, o->render);
                }
                print_statistics(o->render, result.statistics);
                write_exr(o->exr, result.image);
                std::printf("wrote %s\n", o->exr.c_str());
                if (!o->png.empty()) {
                    Image opaque = result.image;  // the PNG shows the background too; the EXR's alpha is the mask
                    for (glm::vec4& p : opaque.pixels) p.a = 1.0f;
                    write_png(o->png,
                              tonemap_to_srgb8(opaque, scene.environment.exposure_stops, tone_map_option(o->tonemap)));
                    std::printf("wrote %s\n", o->png.c_str());
                }
                if (!o->error_exr.empty()) {
                    write_exr(o->error_exr, result.standard_error);
                    std::printf("wrote %s\n", o->error_exr.c_str());
                }
                return 0;
            }};
}

}  // namespace envshadow::app
