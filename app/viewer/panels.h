#pragma once
// The viewer's Dear ImGui panels: the settings, the GPU time per pass, the shadow atlas, the
// environment's cells (or the GPU sampler's lights) and the help. They show what the viewer hands
// them and edit its controls; the viewer applies what they report changed (viewer.cpp).
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>

#include "core/tonemap.h"
#include "env/cells.h"
#include "gl/objects.h"
#include "gl/timer.h"
#include "render/display.h"
#include "render/light_source.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "viewer/dynamic_resolution.h"

namespace envshadow::app {

// What the user sets through the panels and the keys.
struct ViewerControls {
    render::RenderSettings settings;
    render::LightSourceKind light_source = render::LightSourceKind::cells;
    int lights = 128;
    Method method = Method::lloyd;  // of the cells
    std::uint64_t seed = 1;
    float exposure = 0.0f;
    ToneMap tone_map = ToneMap::aces;  // of the window and the screenshot's PNG
    float rotation = 0.0f;             // of the environment, degrees
    double time = 0.0;                 // animation time, seconds
    float speed = 1.0f;                // animation seconds per second
    bool playing = true;
    bool sun_follows_time = true;  // builtin:sky under the GPU sampler
    int selected_object = 0;
    int selected_cell = 0;
    bool show_help = false;
    bool screenshot_requested = false;
    DynamicResolutionOptions dynamic_resolution;
};

// Work running in the background, as the panels report it.
struct JobStatus {
    bool running = false;
    std::string what;
    double seconds = 0.0;
};

// What the panels show this frame besides the controls. Pointers may be null while the first
// environment loads.
struct PanelInputs {
    const render::FrameStats* stats = nullptr;
    const Scene* scene = nullptr;
    const render::Renderer* renderer = nullptr;
    const render::LightSource* lights = nullptr;  // the source lighting this frame
    const Decomposition* cells = nullptr;         // the load-time cells
    const gl::Texture* cells_picture = nullptr;   // the map with the cells' borders
    const gl::Texture* map_picture = nullptr;     // the map alone (under the GPU sampler's lights)
    JobStatus environment_job, model_job;
    std::string error, last_screenshot;
    float shaded_scale = 1.0f;  // of the window, this frame (dynamic resolution)
    int shaded_width = 0, shaded_height = 0;
};

// What changed in the panels this frame, for the viewer to apply.
struct PanelChanges {
    bool settings = false;                                     // controls.settings
    bool decompose = false;                                    // controls.lights or controls.method of the cells
    bool light_source = false;                                 // controls.light_source
    bool rotation = false;                                     // controls.rotation
    std::optional<std::pair<std::size_t, Material>> material;  // an object's new material
    std::optional<gl::PassTiming> pass_timing;
};

class Panels {
public:
    explicit Panels(render::Display& display) : display_(display) {}

    // Keeps the frame's times for the plots (`sampling_ms`: the GPU sampler's, when it lit the frame).
    void record(const render::FrameStats& stats, double frame_seconds, std::optional<double> sampling_ms);
    // Draws every panel inside an ImGui frame.
    PanelChanges draw(ViewerControls& controls, const PanelInputs& in);

private:
    void settings_panel(ViewerControls& controls, const PanelInputs& in, PanelChanges& changes);
    void timings_panel(ViewerControls& controls, const PanelInputs& in, PanelChanges& changes);
    void atlas_panel(const ViewerControls& controls, const PanelInputs& in);
    void cells_panel(ViewerControls& controls, const PanelInputs& in);
    void sampled_lights_panel(const PanelInputs& in);
    void help_panel(ViewerControls& controls);

    render::Display& display_;
    std::deque<float> frame_ms_;
    std::map<std::string, std::deque<float>> pass_ms_;
};

}  // namespace envshadow::app
