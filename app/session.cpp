#include "session.h"

#include <chrono>
#include <cstdio>

#include "options.h"
#include "prefiltering.h"
#include "progress.h"

namespace envshadow::app {
namespace {

// renderer.set_scene(scene), with a progress line on a terminal for a million triangles or more (the
// shadow-caster LOD takes seconds per million).
void upload_scene(render::Renderer& renderer, const Scene& scene, Report report) {
    constexpr std::size_t kShownFrom = 1'000'000;  // triangles: below, it takes well under a second
    const auto start = std::chrono::steady_clock::now();
    ProgressLine line("preparing the meshes", "triangles");
    renderer.set_scene(scene, [&](std::size_t done, std::size_t total) {
        if (total >= kShownFrom) line.update((long long)done, (long long)total);
    });
    line.finish();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (report == Report::print)
        std::printf("meshes: %zu triangles, prepared (caster LOD, upload) in %.3f s\n", scene.triangle_count(),
                    seconds);
}

}  // namespace

RenderSession::RenderSession(const Inputs& inputs, const render::RenderSettings& settings, gl::PassTiming timing,
                             Report report)
    : inputs_(inputs), report_(report), renderer_(settings) {
    renderer_.set_pass_timing(timing);
    upload_scene(renderer_, inputs_.scene, report_);
    renderer_.set_environment(inputs_.map);
    prefilter_if_needed();
}

void RenderSession::set_settings(const render::RenderSettings& settings) {
    renderer_.set_settings(settings);
    prefilter_if_needed();
}

render::FrameStats RenderSession::render(render::LightSource& lights, double time, const render::CameraView& view) {
    lights.update(renderer_);
    return renderer_.render(time, view);
}

// One prefiltering serves every frame: the map is fixed (fs-gpu samples the same map every frame).
void RenderSession::prefilter_if_needed() {
    if (prefiltered_ || renderer_.settings().shading != render::ShadingMode::ratio) return;
    const Hemisphere hemisphere = visible_hemisphere(inputs_.scene);
    const PrefilteredMaps maps = prefilter_maps(inputs_.map, hemisphere, has_metallic_roughness(inputs_.scene));
    upload(renderer_, maps);
    prefiltered_ = true;
    if (report_ == Report::print) print_prefiltering(maps, hemisphere);
}

}  // namespace envshadow::app
