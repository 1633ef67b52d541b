#pragma once
// What `render` and `bench` hold to draw frames of a scene: one renderer with the scene's meshes uploaded,
// its environment behind them and, for ratio shading, that map prefiltered over the directions the
// objects see. A frame reads: session.set_settings(s); session.render(lights, time, view).
#include "env/environment.h"
#include "gl/timer.h"
#include "inputs.h"
#include "render/light_source.h"
#include "render/renderer.h"

namespace envshadow::app {

// Whether the session's steps print a line each (the meshes' preparation, the prefiltering).
enum class Report { quiet, print };

class RenderSession {
public:
    // A GL context must be current. `inputs` must outlive the session.
    RenderSession(const Inputs& inputs, const render::RenderSettings& settings, gl::PassTiming timing, Report report);

    // The settings of the next frames; the map is prefiltered the first time they ask for ratio shading.
    void set_settings(const render::RenderSettings& settings);
    // One frame at animation time `time`: `lights` handed over (a per-frame source samples again), drawn.
    render::FrameStats render(render::LightSource& lights, double time, const render::CameraView& view);

    render::Renderer& renderer() { return renderer_; }
    const Scene& scene() const { return inputs_.scene; }
    const EnvironmentMap& map() const { return inputs_.map; }

private:
    void prefilter_if_needed();

    const Inputs& inputs_;
    Report report_;
    render::Renderer renderer_;
    bool prefiltered_ = false;
};

}  // namespace envshadow::app
