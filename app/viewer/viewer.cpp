// The interactive viewer: the scene rendered every frame by render::Renderer into the window, with
// Dear ImGui panels for every setting, the shadow atlas, the cells over the environment and live
// GPU timings (viewer/panels.h). Loading and decomposing run off the render thread (viewer/jobs.h).
#include "viewer/viewer.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "gl/gl.h"  // before GLFW
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include "core/error.h"
#include "core/image.h"
#include "core/log.h"
#include "env/cell_overlay.h"
#include "env/cells.h"
#include "env/environment.h"
#include "gl/context.h"
#include "gl/readback.h"
#include "inputs.h"
#include "prefiltering.h"
#include "render/display.h"
#include "render/light_source.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "viewer/dynamic_resolution.h"
#include "viewer/jobs.h"
#include "viewer/motion_log.h"
#include "viewer/orbit_camera.h"
#include "viewer/panels.h"
#include "viewer/screenshot.h"

namespace envshadow::app {
namespace {

namespace fs = std::filesystem;

struct LoadedEnvironment {
    std::string spec;                           // as given, before the animation time was applied
    std::shared_ptr<const EnvironmentMap> map;  // spec at the time it was loaded for
    render::LightSource cells;                  // its load-time decomposition
    Image8 cells_picture;                       // the map tone-mapped with cell borders (env/cell_overlay.h)
    Image8 map_picture;                         // the map tone-mapped alone (under the GPU sampler's lights)
    // For --shading ratio: the map prefiltered over the directions the scene's objects see
    // (visible_hemisphere: upper with a ground), for glTF's BRDF too where the scene has its materials; made
    // with every new map or ground, off the render thread; a new N or method keeps it.
    std::shared_ptr<const PrefilteredMaps> prefiltered;
    Hemisphere prefiltered_hemisphere = Hemisphere::full;
};

struct LoadedModel {
    Scene scene;
};

struct AnimatedSky {
    std::string source;  // the spec it animates
    EnvironmentMap map;
    std::shared_ptr<const PrefilteredMaps> prefiltered;  // of map: ratio shading follows the sun too
    Image8 picture;                                      // draw_map(map)
    double time = 0.0;                                   // the animation time (seconds) it was made for
};

bool same_view(const Camera& a, const Camera& b) {
    return a.position == b.position && a.target == b.target && a.up == b.up && a.fov_y_degrees == b.fov_y_degrees;
}

// Pixels per frame of --orbit-frames' synthetic drag: a brisk turn, 0.5 degree per pixel.
constexpr float kSyntheticDragPixels = 6.0f;

// Files dropped onto the window, collected by GLFW's callback and handled by the frame loop.
struct DropQueue {
    std::mutex mutex;
    std::vector<std::string> paths;
};

LoadedEnvironment load_and_decompose(std::string spec, std::shared_ptr<const EnvironmentMap> map,
                                     DecomposeOptions options, Hemisphere visible, bool ggx,
                                     std::shared_ptr<const PrefilteredMaps> prefiltered = nullptr) {
    Decomposition decomposition = decompose(*map, options);
    Image8 cells_picture = draw_cells(*map, decomposition);
    Image8 map_picture = draw_map(*map);
    if (!prefiltered) prefiltered = std::make_shared<const PrefilteredMaps>(prefilter_maps(*map, visible, ggx));
    return {std::move(spec),
            std::move(map),
            render::LightSource(std::move(decomposition)),
            std::move(cells_picture),
            std::move(map_picture),
            std::move(prefiltered),
            visible};
}

JobStatus status_of(const auto& job) {
    return {job.running(), job.what(), job.seconds()};
}

class Viewer {
public:
    explicit Viewer(const ViewerOptions& options) : options_(options) {
        context_ = gl::create_context(
            gl::Backend::window,
            gl::ContextOptions{options.common.width, options.common.height, false, true, true, "envshadow"});
        window_ = static_cast<GLFWwindow*>(context_->native_window());
        glfwSetWindowUserPointer(window_, &drops_);
        glfwSetDropCallback(window_, [](GLFWwindow* w, int count, const char** paths) {
            auto* queue = static_cast<DropQueue*>(glfwGetWindowUserPointer(w));
            std::lock_guard lock(queue->mutex);
            for (int i = 0; i < count; ++i) queue->paths.emplace_back(paths[i]);
        });

        IMGUI_CHECKVERSION();
        ImGui::CreateContext();
        ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left in the working folder
        ImGui::StyleColorsDark();
        ImGui_ImplGlfw_InitForOpenGL(window_, true);
        ImGui_ImplOpenGL3_Init("#version 450 core");

        display_ = std::make_unique<render::Display>();
        panels_ = std::make_unique<Panels>(*display_);
        controls_.settings = settings_from(options.settings, command_defaults());
        controls_.tone_map = tone_map_option(options.tonemap);
        renderer_ = std::make_unique<render::Renderer>(controls_.settings);
        renderer_->set_pass_timing(pass_timing(options.pass_timing, context_->is_software()));

        const render::LightMethod& method = render::light_method(options.common.method);
        controls_.light_source = method.kind;
        if (method.kind == render::LightSourceKind::cells) controls_.method = method.decomposition;
        controls_.lights = options.common.lights;
        controls_.seed = options.common.seed;
        controls_.speed = options.speed;
        controls_.time = options.time;
        controls_.dynamic_resolution.enabled = options.target_ms > 0.0;
        if (options.target_ms > 0.0) controls_.dynamic_resolution.target_ms = options.target_ms;
        set_scene(load_scene_with_environment(options.common.scene, options.common.env));
        start_environment(scene_.environment.source);
    }

    ~Viewer() {
        ImGui_ImplOpenGL3_Shutdown();
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
    }

    int run() {
        const auto start = std::chrono::steady_clock::now();
        auto last = start;
        for (int frame = 0; !glfwWindowShouldClose(window_); ++frame) {
            glfwPollEvents();
            const auto now = std::chrono::steady_clock::now();
            const double dt = std::chrono::duration<double>(now - last).count();
            last = now;
            now_seconds_ = std::chrono::duration<double>(now - start).count();
            if (frame > 0) {  // dt is the last frame's, start to start
                resolution_.record(drawn_.scale, dt * 1000.0);
                motion_.record(drawn_, dt * 1000.0, now_seconds_);
            }
            if (controls_.playing) controls_.time += dt * controls_.speed;
            last_frame_ = options_.frames > 0 && frame + 1 >= options_.frames;

            handle_drops();
            finish_jobs();
            handle_input();
            if (frame < options_.orbit_frames) orbit_.orbit(kSyntheticDragPixels, 0.0f);

            int width = 0, height = 0;
            glfwGetFramebufferSize(window_, &width, &height);
            if (width > 0 && height > 0) draw_frame(width, height, dt);

            if (last_frame_ && !options_.screenshot.empty()) save_window(options_.screenshot, width, height);
            context_->swap_buffers();
            if (last_frame_) {  // its time too: it may be the first at full size
                const double end = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
                motion_.record(drawn_, (end - now_seconds_) * 1000.0, end);
                break;
            }
        }
        if (controls_.light_source == render::LightSourceKind::gpu_fs) log_sampled_lights();
        log_motion();
        return 0;
    }

private:
    // --- scene, environment, lights -------------------------------------------------------------

    void set_scene(Scene scene) {
        scene_ = std::move(scene);
        renderer_->set_scene(scene_);
        controls_.rotation = scene_.environment.rotation_degrees;
        controls_.exposure = scene_.environment.exposure_stops;
        renderer_->set_environment_rotation(controls_.rotation);
        orbit_.reset(scene_.camera);
        controls_.selected_object = 0;
    }

    // Whether the map's prefiltering suits the scene on screen: its hemisphere, and GGX levels where it needs them.
    bool prefiltering_serves_scene() const {
        return environment_->prefiltered_hemisphere == visible_hemisphere(scene_) &&
               (environment_->prefiltered->ggx || !has_metallic_roughness(scene_));
    }

    // The directions the lights come from for the scene on screen (--hemisphere).
    Hemisphere hemisphere() const { return hemisphere_for(options_.common.hemisphere, scene_); }

    // The decomposition the controls ask for.
    DecomposeOptions current_decompose_options() const {
        return {
            .method = controls_.method, .lights = controls_.lights, .seed = controls_.seed, .hemisphere = hemisphere()};
    }

    // The map of `spec` at the animation time now, and its cells.
    void start_environment(const std::string& spec) {
        const DecomposeOptions decompose_options = current_decompose_options();
        environment_job_.start("loading " + spec,
                               [spec, time = controls_.time, decompose_options, visible = visible_hemisphere(scene_),
                                ggx = has_metallic_roughness(scene_)] {
                                   auto map = std::make_shared<const EnvironmentMap>(load_environment_at(spec, time));
                                   return load_and_decompose(spec, std::move(map), decompose_options, visible, ggx);
                               });
    }

    void start_decomposition() {
        if (!environment_) return;
        const DecomposeOptions decompose_options = current_decompose_options();
        environment_job_.start(std::string("decomposing (") + std::string(to_string(controls_.method)) +
                                   ", N = " + std::to_string(controls_.lights) + ")",
                               [spec = environment_->spec, map = environment_->map, decompose_options,
                                visible = visible_hemisphere(scene_), ggx = has_metallic_roughness(scene_),
                                prefiltered = prefiltering_serves_scene() ? environment_->prefiltered : nullptr] {
                                   return load_and_decompose(spec, map, decompose_options, visible, ggx, prefiltered);
                               });
    }

    void finish_jobs() {
        // The last frame of an automated run shows the map it was given, however slow the machine,
        // and a synthetic drag moves over the scene lit, not over frames still waiting for the cells.
        const bool wait = last_frame_ || (options_.orbit_frames > 0 && !environment_);
        if (auto loaded = wait ? environment_job_.wait(error_) : environment_job_.poll(error_)) {
            const bool new_map = !environment_ || environment_->map != loaded->map;
            const bool new_prefiltered = !environment_ || environment_->prefiltered != loaded->prefiltered;
            environment_ = std::make_unique<LoadedEnvironment>(std::move(*loaded));
            if (new_map) renderer_->set_environment(*environment_->map), animated_sky_time_.reset();
            if (new_map || new_prefiltered) upload(*renderer_, *environment_->prefiltered);
            if (controls_.light_source == render::LightSourceKind::cells) environment_->cells.attach(*renderer_);
            cells_texture_ = render::Display::upload(environment_->cells_picture);
            map_texture_ = render::Display::upload(environment_->map_picture);
            error_.clear();
        }
        if (auto sky = sky_job_.poll(error_)) show_sky(*sky);
        if (auto model = model_job_.poll(error_)) {
            Scene scene = std::move(model->scene);
            scene.environment = scene_.environment;  // a dropped model keeps the current environment
            set_scene(std::move(scene));
            if (environment_ && !prefiltering_serves_scene()) start_decomposition();  // the other hemisphere, or GGX
            error_.clear();
        }
    }

    void handle_drops() {
        std::vector<std::string> paths;
        {
            std::lock_guard lock(drops_.mutex);
            paths.swap(drops_.paths);
        }
        for (const std::string& path : paths) {
            std::string extension = fs::path(path).extension().string();
            std::transform(extension.begin(), extension.end(), extension.begin(), ::tolower);
            if (extension == ".exr" || extension == ".hdr") {
                start_environment(path);
            } else if (extension == ".gltf" || extension == ".glb" || extension == ".json") {
                model_job_.start("loading " + path, [path] { return LoadedModel{load_scene(path)}; });
            } else {
                error_ = path + ": not an environment (.exr, .hdr) or a model (.gltf, .glb) or a scene (.json)";
            }
        }
    }

    // --- input ----------------------------------------------------------------------------------

    // Dear ImGui 1.86 (Debian's) indexes keys by the GLFW backend's native key codes.
    void handle_input() {
        ImGuiIO& io = ImGui::GetIO();
        if (!io.WantCaptureMouse) {
            const ImVec2 delta = io.MouseDelta;
            if (ImGui::IsMouseDown(ImGuiMouseButton_Left)) orbit_.orbit(delta.x, delta.y);
            if (ImGui::IsMouseDown(ImGuiMouseButton_Right) || ImGui::IsMouseDown(ImGuiMouseButton_Middle))
                orbit_.pan(delta.x, delta.y, io.DisplaySize.y);
            if (io.MouseWheel != 0.0f) orbit_.zoom(io.MouseWheel);
        }
        if (io.WantCaptureKeyboard) return;
        render::RenderSettings& settings = controls_.settings;
        if (ImGui::IsKeyPressed(GLFW_KEY_SPACE)) controls_.playing = !controls_.playing;
        if (ImGui::IsKeyPressed(GLFW_KEY_R)) orbit_.reset(scene_.camera);
        if (ImGui::IsKeyPressed(GLFW_KEY_B)) settings.background = !settings.background, apply_settings();
        if (ImGui::IsKeyPressed(GLFW_KEY_S)) {
            settings.specular = settings.specular == render::SpecularMode::blended ? render::SpecularMode::single
                                                                                   : render::SpecularMode::blended;
            apply_settings();
        }
        if (ImGui::IsKeyPressed(GLFW_KEY_G))
            set_light_source(controls_.light_source == render::LightSourceKind::cells ? render::LightSourceKind::gpu_fs
                                                                                      : render::LightSourceKind::cells);
        if (ImGui::IsKeyPressed(GLFW_KEY_H) || ImGui::IsKeyPressed(GLFW_KEY_F1))
            controls_.show_help = !controls_.show_help;
        if (ImGui::IsKeyPressed(GLFW_KEY_F12) || ImGui::IsKeyPressed(GLFW_KEY_P)) controls_.screenshot_requested = true;
        if (ImGui::IsKeyPressed(GLFW_KEY_ESCAPE)) glfwSetWindowShouldClose(window_, GLFW_TRUE);
    }

    void apply_settings() {
        try {
            render::RenderSettings settings = controls_.settings;
            // draw_frame sets these two: fewer samples and hard shadows while the view moves.
            settings.msaa = renderer_->settings().msaa;
            settings.shadows = renderer_->settings().shadows;
            renderer_->set_settings(settings);
        } catch (const std::exception& e) {
            error_ = e.what();
            const int msaa = controls_.settings.msaa;
            const render::ShadowMode shadows = controls_.settings.shadows;
            controls_.settings = renderer_->settings();
            controls_.settings.msaa = msaa;
            controls_.settings.shadows = shadows;
        }
    }

    // What the panels changed.
    void apply(const PanelChanges& changes) {
        if (changes.light_source) set_light_source(controls_.light_source);
        if (changes.decompose) start_decomposition();
        if (changes.settings) apply_settings();
        if (changes.rotation) renderer_->set_environment_rotation(controls_.rotation);
        if (changes.material) {
            const auto& [object, material] = *changes.material;
            scene_.objects[object].material = material;
            renderer_->set_material(object, material);
        }
        if (changes.pass_timing) renderer_->set_pass_timing(*changes.pass_timing);
    }

    // --- frame ----------------------------------------------------------------------------------

    // An object moves when the clock runs.
    bool animation_playing() const {
        return controls_.playing && controls_.speed > 0.0f &&
               std::any_of(scene_.objects.begin(), scene_.objects.end(),
                           [](const Object& o) { return o.animation.kind != Animation::Kind::none; });
    }

    // The size to shade this frame at: the window's, or a fraction of it while the view changes
    // (docs/DESIGN.md §5.10).
    DrawnFrame plan_frame(const Camera& camera, int width, int height) {
        DrawnFrame frame;
        frame.changing = !last_camera_ || !same_view(*last_camera_, camera) || animation_playing();
        last_camera_ = camera;
        resolution_.set_options(controls_.dynamic_resolution);
        frame.scale = resolution_.scale_for_frame(frame.changing, now_seconds_);
        frame.width = std::max(1, int(std::lround(float(width) * frame.scale)));
        frame.height = std::max(1, int(std::lround(float(height) * frame.scale)));
        const bool moving = !resolution_.at_full_quality();
        frame.samples = moving && controls_.dynamic_resolution.one_sample_while_moving ? 1 : controls_.settings.msaa;
        frame.shadows = moving && controls_.dynamic_resolution.hard_shadows_while_moving ? render::ShadowMode::hard
                                                                                         : controls_.settings.shadows;
        return frame;
    }

    void draw_frame(int width, int height, double dt) {
        Scene framed = scene_;
        framed.camera = orbit_.camera();
        drawn_ = plan_frame(framed.camera, width, height);
        // Samples: the shaders do not change; shadows: the programs of each mode are built once and kept.
        if (renderer_->settings().msaa != drawn_.samples || renderer_->settings().shadows != drawn_.shadows) {
            render::RenderSettings settings = renderer_->settings();
            settings.msaa = drawn_.samples;
            settings.shadows = drawn_.shadows;
            renderer_->set_settings(settings);
        }
        if (controls_.light_source == render::LightSourceKind::gpu_fs) sample_lights_on_the_gpu();
        const auto render_start = std::chrono::steady_clock::now();
        const render::FrameStats stats =
            renderer_->render(controls_.time, render::camera_view(framed, drawn_.width, drawn_.height, controls_.time));
        drawn_.render_ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - render_start).count();
        drawn_.atlas_passes = stats.atlas_passes;
        drawn_.passes = stats.passes;
        const render::LightSource* lights = light_source();
        panels_->record(stats, dt,
                        lights && lights->per_frame() ? std::optional<double>(lights->sampling_ms()) : std::nullopt);
        if (controls_.screenshot_requested) save_screenshot();

        display_->present(renderer_->color_texture(), controls_.exposure, controls_.tone_map, width, height);

        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        PanelInputs in;
        in.stats = &stats;
        in.scene = &scene_;
        in.renderer = renderer_.get();
        in.lights = lights;
        in.cells = environment_ ? &environment_->cells.decomposition() : nullptr;
        in.cells_picture = &cells_texture_;
        in.map_picture = &map_texture_;
        in.environment_job = status_of(environment_job_);
        in.model_job = status_of(model_job_);
        in.error = error_;
        in.last_screenshot = last_screenshot_;
        in.shaded_scale = drawn_.scale;
        in.shaded_width = drawn_.width;
        in.shaded_height = drawn_.height;
        apply(panels_->draw(controls_, in));
        ImGui::Render();
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    }

    // The source lighting the frame: the GPU sampler once made, else the cells once decomposed.
    const render::LightSource* light_source() const {
        if (controls_.light_source == render::LightSourceKind::gpu_fs) return gpu_fs_ ? &*gpu_fs_ : nullptr;
        return environment_ ? &environment_->cells : nullptr;
    }

    // The frames while the view changed: the line automated runs (--orbit-frames) read.
    void log_motion() const {
        if (!motion_.frame_ms.empty()) log::info(motion_.summary(controls_.dynamic_resolution));
    }

    // --- lights sampled on the GPU ---------------------------------------------------------------

    // What automated runs check: the last frame's lights and the sky they were sampled from.
    void log_sampled_lights() const {
        const std::vector<Cell> none;
        const std::vector<Cell>& lights = gpu_fs_ ? gpu_fs_->lights() : none;
        const auto brightest = std::max_element(lights.begin(), lights.end(), [](const Cell& a, const Cell& b) {
            return a.radiance.r + a.radiance.g + a.radiance.b < b.radiance.r + b.radiance.g + b.radiance.b;
        });
        const std::string name(render::light_method(render::LightSourceKind::gpu_fs, Method::fs).name());
        if (brightest == lights.end()) return log::info(name + ": no lights sampled");
        char text[200];
        std::snprintf(text, sizeof text,
                      "%s: %zu lights in the last frame, the brightest toward (%.4f, %.4f, %.4f) in map space",
                      name.c_str(), lights.size(), double(brightest->direction.x), double(brightest->direction.y),
                      double(brightest->direction.z));
        std::string line = text;
        if (animated_sky_time_) line += "; the sky at animation time " + std::to_string(*animated_sky_time_) + " s";
        log::info(line);
    }

    void set_light_source(render::LightSourceKind source) {
        controls_.light_source = source;
        if (source == render::LightSourceKind::cells && environment_) {
            environment_->cells.attach(*renderer_);
            if (animated_sky_time_) {
                renderer_->set_environment(*environment_->map);
                upload(*renderer_, *environment_->prefiltered);
                map_texture_ = render::Display::upload(environment_->map_picture);
                animated_sky_time_.reset();
            }
        }
    }

    // Lights from the environment texture as it is this frame. The read-back waits for the sampler
    // (a fraction of a millisecond on a GPU), which keeps the renderer's light list on the CPU.
    void sample_lights_on_the_gpu() {
        if (!environment_) return;  // the first map is still loading
        follow_the_clock();
        if (last_frame_) {  // an automated run shows the sky it asked for, however slow the machine
            if (auto sky = sky_job_.wait(error_)) show_sky(*sky);
        }
        try {
            if (!gpu_fs_ || gpu_fs_->hemisphere() != hemisphere())
                gpu_fs_.emplace(controls_.lights, fs_sampler_options(options_.common.fs_importance, *environment_->map),
                                hemisphere());
            gpu_fs_->set_requested_lights(controls_.lights);
            gpu_fs_->update(*renderer_);
        } catch (const std::exception& e) {  // e.g. a GL without storage blocks in geometry shaders
            error_ = e.what();
            set_light_source(render::LightSourceKind::cells);
        }
    }

    void show_sky(const AnimatedSky& sky) {
        // Unless the cells came back or a new map came in meanwhile.
        if (controls_.light_source != render::LightSourceKind::gpu_fs || !environment_ ||
            sky.source != environment_->spec)
            return;
        renderer_->set_environment(sky.map);
        upload(*renderer_, *sky.prefiltered);
        map_texture_ = render::Display::upload(sky.picture);
        animated_sky_time_ = sky.time;
    }

    // builtin:sky's sun follows the animation time (one hour per second, engine/env environment_at_time).
    // The map is made off the render thread; each finished one is shown and the next started, so
    // the sky moves as fast as the CPU makes maps without slowing the frame.
    void follow_the_clock() {
        if (!controls_.sun_follows_time || sky_job_.running()) return;
        const std::string& source = environment_->spec;
        const double time = controls_.time;
        const std::string spec = environment_at_time(source, time);
        if (spec == environment_->map->source && !animated_sky_time_) return;  // not a sky, or still at its time
        if (animated_sky_time_ == time) return;
        sky_job_.start(
            "sky at " + std::to_string(time) + " s",
            [source, spec, time, hemisphere = visible_hemisphere(scene_), ggx = has_metallic_roughness(scene_)] {
                AnimatedSky sky{source, load_environment(spec), nullptr, {}, time};
                sky.prefiltered = std::make_shared<const PrefilteredMaps>(prefilter_maps(sky.map, hemisphere, ggx));
                sky.picture = draw_map(sky.map);
                return sky;
            });
    }

    // --- output ---------------------------------------------------------------------------------

    // The frame without the UI: linear EXR, tone-mapped PNG, and the settings beside them.
    void save_screenshot() {
        controls_.screenshot_requested = false;
        try {
            const std::string stem = write_screenshot(
                renderer_->read_back(), {scene_, controls_, orbit_.camera(),
                                         environment_ ? environment_->map->source : std::string(), method_name()});
            last_screenshot_ = stem + ".png";
            log::info("wrote " + stem + ".{png,exr,json}");
        } catch (const std::exception& e) {
            error_ = e.what();
        }
    }

    std::string method_name() const {
        return std::string(render::light_method(controls_.light_source, controls_.method).name());
    }

    // The window as a person sees it, UI included (for automated runs).
    void save_window(const std::string& path, int width, int height) {
        write_png(path, gl::read_default_framebuffer(width, height));
        log::info("wrote " + path);
    }

    ViewerOptions options_;
    std::unique_ptr<gl::Context> context_;
    GLFWwindow* window_ = nullptr;
    DropQueue drops_;
    std::unique_ptr<render::Display> display_;
    std::unique_ptr<Panels> panels_;
    std::unique_ptr<render::Renderer> renderer_;
    ViewerControls controls_;

    Scene scene_;
    OrbitCamera orbit_;
    std::unique_ptr<LoadedEnvironment> environment_;
    gl::Texture cells_texture_, map_texture_;
    BackgroundJob<LoadedEnvironment> environment_job_;
    BackgroundJob<LoadedModel> model_job_;
    BackgroundJob<AnimatedSky> sky_job_;
    std::optional<double> animated_sky_time_;    // the animation time of the sky on screen, when animated
    std::optional<render::LightSource> gpu_fs_;  // made the first time the GPU sampler lights a frame

    DynamicResolution resolution_;
    std::optional<Camera> last_camera_;
    DrawnFrame drawn_;
    MotionLog motion_;
    double now_seconds_ = 0.0;  // since the viewer started, at the start of this frame

    bool last_frame_ = false;  // of an automated run (--frames)
    std::string last_screenshot_;
    std::string error_;
};

}  // namespace

int run_viewer(const ViewerOptions& options) {
    Viewer viewer(options);
    return viewer.run();
}

}  // namespace envshadow::app
