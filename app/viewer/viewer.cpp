// The interactive viewer: the scene rendered every frame by render::Renderer into the window, with
// Dear ImGui panels for every setting, the shadow atlas, the cells over the environment and live
// GPU timings. Loading and decomposing run off the render thread (viewer/jobs.h).
#include "viewer/viewer.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <deque>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gl/gl.h"  // before GLFW
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/image.h"
#include "core/log.h"
#include "env/cell_overlay.h"
#include "env/cells.h"
#include "env/environment.h"
#include "env/latlong.h"
#include "gl/context.h"
#include "gl/readback.h"
#include "render/display.h"
#include "render/embedded_shaders.h"
#include "render/fs_sampler.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "viewer/jobs.h"
#include "viewer/orbit_camera.h"

namespace envshadow::app {
namespace {

namespace fs = std::filesystem;

constexpr std::array<Method, 5> kMethods = {Method::lloyd, Method::ccvt, Method::mediancut, Method::random, Method::fs};
constexpr int kHistory = 240;  // frames kept for the timing plots

// Where the lights come from: the cells of the load-time decomposition, or Floyd-Steinberg samples
// drawn on the GPU every frame (docs/FS_GPU.md), which follow a rotated, swapped or animated map at once.
enum class LightSource { cells, gpu_fs };

struct LoadedEnvironment {
    std::shared_ptr<const EnvironmentMap> map;
    Decomposition decomposition;
    Image8 cells_picture;  // the map tone-mapped with cell borders (env/cell_overlay.h)
    Image8 map_picture;    // the map tone-mapped alone (under the GPU sampler's lights)
};

struct LoadedModel {
    Scene scene;
};

struct AnimatedSky {
    std::string source;  // the spec it animates
    EnvironmentMap map;
    Image8 picture;     // draw_map(map)
    double time = 0.0;  // the animation time (seconds) it was made for
};

// Files dropped onto the window, collected by GLFW's callback and handled by the frame loop.
struct DropQueue {
    std::mutex mutex;
    std::vector<std::string> paths;
};

LoadedEnvironment load_and_decompose(std::shared_ptr<const EnvironmentMap> map, DecomposeOptions options) {
    LoadedEnvironment result;
    result.decomposition = decompose(*map, options);
    result.cells_picture = draw_cells(*map, result.decomposition);
    result.map_picture = draw_map(*map);
    result.map = std::move(map);
    return result;
}

std::string timestamp() {
    const std::time_t now = std::time(nullptr);
    char text[32];
    std::strftime(text, sizeof text, "%Y%m%d-%H%M%S", std::localtime(&now));
    return text;
}

class Viewer {
public:
    explicit Viewer(const ViewerOptions& options) : options_(options) {
        context_ = gl::create_context(
            gl::Backend::window, gl::ContextOptions{options.width, options.height, false, true, true, "envshadow"});
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
        renderer_ = std::make_unique<render::Renderer>(settings_);
        renderer_->set_pass_timing(
            gl::parse_pass_timing(options.pass_timing, context_->is_software(), "--pass-timing"));

        lights_ = options.lights;
        if (options.method == "fs-gpu")
            light_source_ = LightSource::gpu_fs;
        else
            method_ = parse_method(options.method);
        seed_ = options.seed;
        speed_ = options.speed;
        time_ = options.time;
        set_scene(load_scene(options.scene));
        const std::string source = options.environment.empty() ? scene_.environment.source : options.environment;
        start_environment(source);
    }

    ~Viewer() {
        ImGui_ImplOpenGL3_Shutdown();
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
    }

    int run() {
        auto last = std::chrono::steady_clock::now();
        for (int frame = 0; !glfwWindowShouldClose(window_); ++frame) {
            glfwPollEvents();
            const auto now = std::chrono::steady_clock::now();
            const double dt = std::chrono::duration<double>(now - last).count();
            last = now;
            if (playing_) time_ += dt * speed_;
            last_frame_ = options_.frames > 0 && frame + 1 >= options_.frames;

            handle_drops();
            finish_jobs();
            handle_input();

            int width = 0, height = 0;
            glfwGetFramebufferSize(window_, &width, &height);
            if (width > 0 && height > 0) draw_frame(width, height, dt);

            if (last_frame_ && !options_.screenshot.empty()) save_window(options_.screenshot, width, height);
            context_->swap_buffers();
            if (last_frame_) break;
        }
        if (light_source_ == LightSource::gpu_fs) log_fs_lights();
        return 0;
    }

private:
    // --- scene, environment, lights -------------------------------------------------------------

    void set_scene(Scene scene) {
        scene_ = std::move(scene);
        renderer_->set_scene(scene_);
        rotation_ = scene_.environment.rotation_degrees;
        exposure_ = scene_.environment.exposure_stops;
        renderer_->set_environment_rotation(rotation_);
        orbit_.reset(scene_.camera);
        selected_object_ = 0;
    }

    // A ground hides every direction below the horizon: only the upper hemisphere is decomposed.
    Hemisphere visible_hemisphere() const { return scene_.has_ground ? Hemisphere::upper : Hemisphere::full; }

    void start_environment(const std::string& source) {
        const DecomposeOptions decompose_options{
            .method = method_, .lights = lights_, .seed = seed_, .hemisphere = visible_hemisphere()};
        environment_job_.start("loading " + source, [source, decompose_options] {
            EnvironmentLoadReport report;
            auto map = std::make_shared<const EnvironmentMap>(load_environment(source, {}, &report));
            return load_and_decompose(std::move(map), decompose_options);
        });
    }

    void start_decomposition() {
        if (!environment_) return;
        const DecomposeOptions decompose_options{
            .method = method_, .lights = lights_, .seed = seed_, .hemisphere = visible_hemisphere()};
        environment_job_.start(
            std::string("decomposing (") + std::string(to_string(method_)) + ", N = " + std::to_string(lights_) + ")",
            [map = environment_->map, decompose_options] { return load_and_decompose(map, decompose_options); });
    }

    void finish_jobs() {
        // The last frame of an automated run shows the map it was given, however slow the machine.
        if (auto loaded = last_frame_ ? environment_job_.wait(error_) : environment_job_.poll(error_)) {
            const bool new_map = !environment_ || environment_->map != loaded->map;
            environment_ = std::make_unique<LoadedEnvironment>(std::move(*loaded));
            if (new_map) renderer_->set_environment(*environment_->map), animated_sky_time_.reset();
            if (light_source_ == LightSource::cells) renderer_->set_lights(environment_->decomposition.cells);
            cells_texture_ = render::Display::upload(environment_->cells_picture);
            map_texture_ = render::Display::upload(environment_->map_picture);
            selected_cell_ = std::min(selected_cell_, int(environment_->decomposition.cells.size()) - 1);
            error_.clear();
        }
        if (auto sky = sky_job_.poll(error_)) show_sky(*sky);
        if (auto model = model_job_.poll(error_)) {
            Scene scene = std::move(model->scene);
            scene.environment = scene_.environment;  // a dropped model keeps the current environment
            const bool ground_changed = scene.has_ground != scene_.has_ground;
            set_scene(std::move(scene));
            if (ground_changed) start_decomposition();  // the other hemisphere
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
        if (ImGui::IsKeyPressed(GLFW_KEY_SPACE)) playing_ = !playing_;
        if (ImGui::IsKeyPressed(GLFW_KEY_R)) orbit_.reset(scene_.camera);
        if (ImGui::IsKeyPressed(GLFW_KEY_B)) settings_.background = !settings_.background, apply_settings();
        if (ImGui::IsKeyPressed(GLFW_KEY_S)) {
            settings_.specular = settings_.specular == render::SpecularMode::blended ? render::SpecularMode::single
                                                                                     : render::SpecularMode::blended;
            apply_settings();
        }
        if (ImGui::IsKeyPressed(GLFW_KEY_G))
            set_light_source(light_source_ == LightSource::cells ? LightSource::gpu_fs : LightSource::cells);
        if (ImGui::IsKeyPressed(GLFW_KEY_H) || ImGui::IsKeyPressed(GLFW_KEY_F1)) show_help_ = !show_help_;
        if (ImGui::IsKeyPressed(GLFW_KEY_F12) || ImGui::IsKeyPressed(GLFW_KEY_P)) screenshot_requested_ = true;
        if (ImGui::IsKeyPressed(GLFW_KEY_ESCAPE)) glfwSetWindowShouldClose(window_, GLFW_TRUE);
    }

    void apply_settings() {
        try {
            renderer_->set_settings(settings_);
        } catch (const std::exception& e) {
            error_ = e.what();
            settings_ = renderer_->settings();
        }
    }

    // --- frame ----------------------------------------------------------------------------------

    void draw_frame(int width, int height, double dt) {
        Scene framed = scene_;
        framed.camera = orbit_.camera();
        if (light_source_ == LightSource::gpu_fs) sample_lights_on_the_gpu();
        const render::FrameStats stats = renderer_->render(time_, render::camera_view(framed, width, height, time_));
        record(stats, dt);
        if (screenshot_requested_) save_screenshot();

        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glViewport(0, 0, width, height);
        display_->present(renderer_->color_texture(), exposure_);

        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        draw_settings_panel(stats);
        draw_timings_panel(stats);
        draw_atlas_panel();
        draw_cells_panel();
        if (show_help_) draw_help();
        ImGui::Render();
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    }

    void record(const render::FrameStats& stats, double dt) {
        auto push = [](std::deque<float>& history, float value) {
            history.push_back(value);
            if (history.size() > kHistory) history.pop_front();
        };
        push(frame_ms_, float(dt * 1000.0));
        for (const gl::PassTime& pass : stats.passes) push(pass_ms_[pass.pass], float(pass.milliseconds));
        if (light_source_ == LightSource::gpu_fs) push(pass_ms_[render::kFsSamplingPass], float(fs_sampling_ms_));
    }

    // --- lights sampled on the GPU ---------------------------------------------------------------

    // What automated runs check: the last frame's lights and the sky they were sampled from.
    void log_fs_lights() const {
        const auto brightest = std::max_element(fs_lights_.begin(), fs_lights_.end(), [](const Cell& a, const Cell& b) {
            return a.radiance.r + a.radiance.g + a.radiance.b < b.radiance.r + b.radiance.g + b.radiance.b;
        });
        if (brightest == fs_lights_.end()) return log::info("fs-gpu: no lights sampled");
        char text[200];
        std::snprintf(text, sizeof text,
                      "fs-gpu: %zu lights in the last frame, the brightest toward (%.4f, %.4f, %.4f) in map space",
                      fs_lights_.size(), double(brightest->direction.x), double(brightest->direction.y),
                      double(brightest->direction.z));
        std::string line = text;
        if (animated_sky_time_) line += "; the sky at animation time " + std::to_string(*animated_sky_time_) + " s";
        log::info(line);
    }

    void set_light_source(LightSource source) {
        light_source_ = source;
        if (source == LightSource::cells && environment_) {
            renderer_->set_lights(environment_->decomposition.cells);
            if (animated_sky_time_) {
                renderer_->set_environment(*environment_->map);
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
            if (!fs_sampler_) fs_sampler_.emplace(render::embedded_shaders());
            const auto start = std::chrono::steady_clock::now();
            fs_sampler_->sample(renderer_->environment_texture(),
                                render::FsSampleRequest{.samples = lights_, .upper_hemisphere = scene_.has_ground});
            fs_lights_ = fs_sampler_->read_lights();
            renderer_->set_lights(fs_lights_);
            fs_sampling_ms_ =
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        } catch (const std::exception& e) {  // e.g. a GL without storage blocks in geometry shaders
            error_ = e.what();
            set_light_source(LightSource::cells);
        }
    }

    void show_sky(const AnimatedSky& sky) {
        // Unless the cells came back or a new map came in meanwhile.
        if (light_source_ != LightSource::gpu_fs || !environment_ || sky.source != environment_->map->source) return;
        renderer_->set_environment(sky.map);
        map_texture_ = render::Display::upload(sky.picture);
        animated_sky_time_ = sky.time;
    }

    // builtin:sky's sun follows the animation time (one hour per second, engine/env environment_at_time).
    // The map is made off the render thread; each finished one is shown and the next started, so
    // the sky moves as fast as the CPU makes maps without slowing the frame.
    void follow_the_clock() {
        if (!sun_follows_time_ || sky_job_.running()) return;
        const std::string& source = environment_->map->source;
        const std::string spec = environment_at_time(source, time_);
        if (spec == source && !animated_sky_time_) return;  // not a sky, or a sky at its own time
        if (animated_sky_time_ == time_) return;
        sky_job_.start("sky at " + std::to_string(time_) + " s", [source, spec, time = time_] {
            AnimatedSky sky{source, load_environment(spec), {}, time};
            sky.picture = draw_map(sky.map);
            return sky;
        });
    }

    // --- panels ---------------------------------------------------------------------------------

    void draw_settings_panel(const render::FrameStats& stats) {
        ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
        ImGui::SetNextWindowSize(ImVec2(330, 0), ImGuiCond_FirstUseEver);
        ImGui::Begin("envshadow", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
        ImGui::TextUnformatted(scene_.file.filename().string().c_str());
        if (!error_.empty()) ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.3f, 1.0f), "%s", error_.c_str());
        if (environment_job_.running()) {
            ImGui::ProgressBar(
                -1.0f * float(ImGui::GetTime()), ImVec2(-1, 0),
                (environment_job_.what() + " " + std::to_string(int(environment_job_.seconds() * 1000)) + " ms")
                    .c_str());
        }
        if (model_job_.running()) ImGui::TextUnformatted(model_job_.what().c_str());

        if (ImGui::CollapsingHeader("Lights", ImGuiTreeNodeFlags_DefaultOpen)) {
            int source = int(light_source_);
            if (ImGui::RadioButton("cells (load time)", &source, int(LightSource::cells)))
                set_light_source(LightSource::cells);
            ImGui::SameLine();
            if (ImGui::RadioButton("GPU FS (every frame)", &source, int(LightSource::gpu_fs)))
                set_light_source(LightSource::gpu_fs);
            // Decompose when the slider is let go, not on every step of the drag.
            ImGui::SliderInt("cells N", &lights_, 1, kMaxLights, "%d", ImGuiSliderFlags_AlwaysClamp);
            bool redo = ImGui::IsItemDeactivatedAfterEdit();
            if (light_source_ == LightSource::cells) {
                int method_index = int(std::find(kMethods.begin(), kMethods.end(), method_) - kMethods.begin());
                const char* names[] = {"lloyd", "ccvt", "mediancut", "random", "fs"};
                if (ImGui::Combo("method", &method_index, names, int(kMethods.size()))) {
                    method_ = kMethods[size_t(method_index)];
                    redo = true;
                }
                if (redo) start_decomposition();
            }
            if (light_source_ == LightSource::gpu_fs) {
                ImGui::Checkbox("sun follows time (builtin:sky)", &sun_follows_time_);
                if (fs_sampler_) {
                    const render::FsCounts counts = fs_sampler_->read_counts();
                    ImGui::Text("GPU FS: %u lights from %u samples of a %dx%d importance map, %.2f ms",
                                counts.light_count, counts.samples, fs_sampler_->importance_size().x,
                                fs_sampler_->importance_size().y, fs_sampling_ms_);
                }
            } else if (environment_) {
                const Decomposition& d = environment_->decomposition;
                ImGui::Text("%zu cells of the %s, decomposed in %.1f ms (%d iterations)", d.cells.size(),
                            d.hemisphere == Hemisphere::upper ? "upper hemisphere" : "full sphere", d.seconds * 1000.0,
                            d.iterations);
            }
            if (environment_) {
                ImGui::Text("%d lights drawn, %d below ground, %d negligible", stats.lights, stats.lights_below_ground,
                            stats.lights_negligible);
            }
        }

        if (ImGui::CollapsingHeader("Shadows")) {
            bool changed = false;
            const int tiles[] = {128, 256, 512, 1024, 2048};
            int tile_index =
                int(std::find(std::begin(tiles), std::end(tiles), settings_.tile_size) - std::begin(tiles));
            const char* tile_names[] = {"128", "256", "512", "1024", "2048"};
            if (ImGui::Combo("tile size", &tile_index, tile_names, 5))
                settings_.tile_size = tiles[tile_index], changed = true;
            int depth = settings_.depth_bits == 16 ? 0 : 1;
            if (ImGui::Combo("depth", &depth,
                             "16 bit\0"
                             "32 bit float\0"))
                settings_.depth_bits = depth ? 32 : 16, changed = true;
            int pcf = int(settings_.pcf);
            if (ImGui::Combo("PCF", &pcf, "2x2 hardware\0wide\0"))
                settings_.pcf = render::PcfKernel(pcf), changed = true;
            changed |= ImGui::SliderFloat("slope bias", &settings_.slope_bias, 0.0f, 8.0f);
            changed |= ImGui::SliderFloat("depth bias", &settings_.depth_bias, 0.0f, 8.0f);
            changed |= ImGui::SliderFloat("normal offset", &settings_.normal_offset, 0.0f, 4.0f);
            int atlas = int(settings_.atlas);
            if (ImGui::Combo("atlas draw", &atlas, "one draw (clip distances)\0viewport arrays\0per tile (baseline)\0"))
                settings_.atlas = render::AtlasMode(atlas), changed = true;
            changed |= ImGui::Checkbox("skip hidden/negligible lights", &settings_.skip_lights);
            if (changed) apply_settings();
            ImGui::Text("atlas %dx%d, %.1f MB", stats.atlas.width(), stats.atlas.height(),
                        double(stats.atlas_bytes) / (1 << 20));
        }

        if (ImGui::CollapsingHeader("Shading", ImGuiTreeNodeFlags_DefaultOpen)) {
            bool changed = false;
            int specular = int(settings_.specular);
            if (ImGui::Combo("specular", &specular, "blended (Barsi)\0single sample\0"))
                settings_.specular = render::SpecularMode(specular), changed = true;
            int cap = int(settings_.cap);
            if (ImGui::Combo("cap radius", &cap, "solid angle\0radiance weighted\0"))
                settings_.cap = render::CapKind(cap), changed = true;
            int diffuse = int(settings_.diffuse);
            if (ImGui::Combo("diffuse", &diffuse, "centre sample\0cap integral\0"))
                settings_.diffuse = render::DiffuseMode(diffuse), changed = true;
            changed |= ImGui::Checkbox("background", &settings_.background);
            if (changed) apply_settings();
            ImGui::SliderFloat("exposure", &exposure_, -6.0f, 6.0f, "%.2f stops");
            if (ImGui::SliderFloat("env rotation", &rotation_, -180.0f, 180.0f, "%.0f deg"))
                renderer_->set_environment_rotation(rotation_);
        }

        if (!scene_.objects.empty() && ImGui::CollapsingHeader("Material")) {
            selected_object_ = std::min(selected_object_, int(scene_.objects.size()) - 1);
            if (ImGui::BeginCombo("object", scene_.objects[size_t(selected_object_)].name.c_str())) {
                for (int i = 0; i < int(scene_.objects.size()); ++i)
                    if (ImGui::Selectable(scene_.objects[size_t(i)].name.c_str(), i == selected_object_))
                        selected_object_ = i;
                ImGui::EndCombo();
            }
            Material& m = scene_.objects[size_t(selected_object_)].material;
            bool changed = ImGui::ColorEdit3("rho_d", &m.rho_d.x);
            changed |= ImGui::SliderFloat("rho_s", &m.rho_s, 0.0f, 1.0f);
            changed |=
                ImGui::SliderFloat("shininess n", &m.shininess, 1.0f, 10000.0f, "%.0f", ImGuiSliderFlags_Logarithmic);
            if (changed) renderer_->set_material(size_t(selected_object_), m);
        }

        if (ImGui::CollapsingHeader("Animation")) {
            ImGui::Checkbox("play", &playing_);
            ImGui::SameLine();
            ImGui::SliderFloat("speed", &speed_, 0.0f, 4.0f);
            float t = float(time_);
            if (ImGui::SliderFloat("time", &t, 0.0f, 60.0f, "%.2f s")) time_ = t;
        }
        if (ImGui::Button("screenshot (F12)")) screenshot_requested_ = true;
        ImGui::SameLine();
        if (ImGui::Button("help (H)")) show_help_ = !show_help_;
        if (!last_screenshot_.empty()) ImGui::TextWrapped("saved %s", last_screenshot_.c_str());
        ImGui::End();
    }

    void draw_timings_panel(const render::FrameStats& stats) {
        const ImVec2 display = ImGui::GetIO().DisplaySize;
        ImGui::SetNextWindowPos(ImVec2(display.x - 388, 8), ImGuiCond_FirstUseEver);
        ImGui::SetNextWindowSize(ImVec2(380, 0), ImGuiCond_FirstUseEver);
        ImGui::Begin("GPU time per pass", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
        auto plot = [](const char* label, const std::deque<float>& history) {
            if (history.empty()) return;
            std::vector<float> values(history.begin(), history.end());
            const float peak = *std::max_element(values.begin(), values.end());
            char overlay[64];
            std::snprintf(overlay, sizeof overlay, "%.2f ms", double(values.back()));
            ImGui::PlotLines(label, values.data(), int(values.size()), 0, overlay, 0.0f, peak * 1.1f, ImVec2(0, 40));
        };
        const float frame = frame_ms_.empty() ? 0.0f : frame_ms_.back();
        ImGui::Text("%.1f FPS (%.2f ms per frame)", frame > 0.0f ? 1000.0 / double(frame) : 0.0, double(frame));
        plot("frame", frame_ms_);
        bool synchronous = renderer_->pass_timing() == gl::PassTiming::synchronous;
        if (ImGui::Checkbox("wait for each pass", &synchronous))
            renderer_->set_pass_timing(synchronous ? gl::PassTiming::synchronous : gl::PassTiming::queries);
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip(
                "Times each pass by the clock between glFinish calls: exact on a software\n"
                "rasteriser, whose GL_TIME_ELAPSED queries misplace the work (on by default\n"
                "there); on a GPU the queries are exact and waiting costs the overlap.");
        for (const gl::PassTime& pass : stats.passes) plot(pass.pass.c_str(), pass_ms_[pass.pass]);
        if (light_source_ == LightSource::gpu_fs) plot(render::kFsSamplingPass, pass_ms_[render::kFsSamplingPass]);
        ImGui::End();
    }

    void draw_atlas_panel() {
        ImGui::SetNextWindowPos(ImVec2(346, 8), ImGuiCond_FirstUseEver);
        ImGui::SetNextWindowSize(ImVec2(420, 228), ImGuiCond_FirstUseEver);
        ImGui::SetNextWindowCollapsed(true, ImGuiCond_FirstUseEver);
        if (ImGui::Begin("Shadow atlas")) {
            const gl::Texture& atlas = renderer_->atlas_texture();
            if (atlas) {
                const gl::Texture& preview = display_->atlas_preview(atlas, 1024);
                const float w = std::min(ImGui::GetContentRegionAvail().x, float(preview.width()));
                const float h = w * float(preview.height()) / float(preview.width());
                // GL textures start at the bottom row: flip v.
                ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(preview.id())), ImVec2(w, h),
                             ImVec2(0, 1), ImVec2(1, 0));
                ImGui::Text("%d tiles of %d^2", renderer_->light_count(), settings_.tile_size);
            }
        }
        ImGui::End();
    }

    void draw_cells_panel() {
        const ImVec2 display = ImGui::GetIO().DisplaySize;
        ImGui::SetNextWindowPos(ImVec2(display.x - 388, display.y - 292), ImGuiCond_FirstUseEver);
        ImGui::SetNextWindowSize(ImVec2(380, 284), ImGuiCond_FirstUseEver);
        if (light_source_ == LightSource::gpu_fs) {
            draw_fs_lights_panel();
            return;
        }
        if (ImGui::Begin("Environment cells") && environment_ && cells_texture_) {
            const Decomposition& d = environment_->decomposition;
            const float w = ImGui::GetContentRegionAvail().x, h = w * 0.5f;
            const ImVec2 origin = ImGui::GetCursorScreenPos();
            ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(cells_texture_.id())), ImVec2(w, h));
            if (ImGui::IsItemHovered() && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
                const ImVec2 mouse = ImGui::GetMousePos();
                const int i = std::clamp(int((mouse.x - origin.x) / w * float(d.width)), 0, d.width - 1);
                const int j = std::clamp(int((mouse.y - origin.y) / h * float(d.height)), 0, d.height - 1);
                const std::uint16_t cell = d.texel_cell[size_t(j) * size_t(d.width) + size_t(i)];
                if (cell != kNoCell) selected_cell_ = cell;  // below the horizon of an upper-hemisphere decomposition
            }
            if (!d.cells.empty()) {
                ImGui::SliderInt("cell", &selected_cell_, 0, int(d.cells.size()) - 1);
                const Cell& c = d.cells[size_t(selected_cell_)];
                const glm::dvec2 uv = latlong::uv(glm::dvec3(c.direction));
                const ImVec2 centre(origin.x + float(uv.x) * w, origin.y + float(uv.y) * h);
                ImGui::GetWindowDrawList()->AddCircle(centre, 9.0f, IM_COL32(255, 230, 0, 255), 16, 2.5f);
                ImGui::Text("L~ = (%.4g, %.4g, %.4g)  solid angle %.4g sr", double(c.radiance.r), double(c.radiance.g),
                            double(c.radiance.b), double(c.solid_angle));
                ImGui::Text("cos r = %.5f (solid angle), %.5f (radiance weighted)", double(c.cos_radius),
                            double(c.cos_radius_weighted));
            }
        }
        ImGui::End();
    }

    // The GPU sampler's lights of this frame as dots over the map on screen, brighter lights larger.
    void draw_fs_lights_panel() {
        if (ImGui::Begin("Environment cells") && environment_ && map_texture_) {
            const float w = ImGui::GetContentRegionAvail().x, h = w * 0.5f;
            const ImVec2 origin = ImGui::GetCursorScreenPos();
            ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(map_texture_.id())), ImVec2(w, h));
            float brightest = 0.0f;
            for (const Cell& c : fs_lights_)
                brightest = std::max(brightest, c.radiance.r + c.radiance.g + c.radiance.b);
            for (const Cell& c : fs_lights_) {
                const glm::dvec2 uv = latlong::uv(glm::dvec3(c.direction));
                const float share = (c.radiance.r + c.radiance.g + c.radiance.b) / std::max(brightest, 1e-30f);
                ImGui::GetWindowDrawList()->AddCircleFilled(
                    ImVec2(origin.x + float(uv.x) * w, origin.y + float(uv.y) * h), 2.0f + 4.0f * std::sqrt(share),
                    IM_COL32(255, 60, 40, 255));
            }
            ImGui::Text("%zu lights sampled on the GPU this frame (dots)", fs_lights_.size());
        }
        ImGui::End();
    }

    void draw_help() {
        ImGui::SetNextWindowPos(ImVec2(400, 300), ImGuiCond_FirstUseEver);
        ImGui::Begin("Help", &show_help_, ImGuiWindowFlags_AlwaysAutoResize);
        ImGui::TextUnformatted(
            "Left drag        orbit\n"
            "Right/mid drag   pan\n"
            "Wheel            zoom\n"
            "Space            play / pause the animation\n"
            "R                reset the camera\n"
            "B                background on / off\n"
            "S                blended / single-sample specular\n"
            "G                lights: load-time cells / GPU Floyd-Steinberg\n"
            "F12 or P         screenshot to screenshots/ (PNG, EXR, JSON)\n"
            "H or F1          this help\n"
            "Esc              quit\n"
            "Drop an .exr/.hdr onto the window for a new environment,\n"
            "a .gltf/.glb for a new model, a .json for a new scene.");
        ImGui::End();
    }

    // --- output ---------------------------------------------------------------------------------

    // The frame without the UI: linear EXR, tone-mapped PNG, and the settings beside them.
    void save_screenshot() {
        screenshot_requested_ = false;
        try {
            fs::create_directories("screenshots");
            const std::string stem = "screenshots/view_" + scene_.file.stem().string() + "_" + method_name() + "_N" +
                                     std::to_string(lights_) + "_" + timestamp();
            const Image linear = renderer_->read_back();
            write_exr(stem + ".exr", linear);
            write_png(stem + ".png", tonemap_to_srgb8(linear, exposure_));
            const Camera camera = orbit_.camera();
            nlohmann::json settings = {
                {"scene", scene_.file.string()},
                {"environment", environment_ ? environment_->map->source : ""},
                {"method", method_name()},
                {"lights", lights_},
                {"seed", seed_},
                {"time", time_},
                {"exposure", exposure_},
                {"rotation_degrees", rotation_},
                {"camera",
                 {{"position", {camera.position.x, camera.position.y, camera.position.z}},
                  {"target", {camera.target.x, camera.target.y, camera.target.z}},
                  {"fov_y_degrees", camera.fov_y_degrees}}},
                {"tile", settings_.tile_size},
                {"depth_bits", settings_.depth_bits},
                {"pcf", render::to_string(settings_.pcf)},
                {"specular", render::to_string(settings_.specular)},
                {"cap", render::to_string(settings_.cap)},
                {"diffuse", render::to_string(settings_.diffuse)},
                {"slope_bias", settings_.slope_bias},
                {"depth_bias", settings_.depth_bias},
                {"normal_offset", settings_.normal_offset},
            };
            write_file_atomically(stem + ".json", settings.dump(2) + "\n");
            last_screenshot_ = stem + ".png";
            log::info("wrote " + stem + ".{png,exr,json}");
        } catch (const std::exception& e) {
            error_ = e.what();
        }
    }

    std::string method_name() const {
        return light_source_ == LightSource::gpu_fs ? "fs-gpu" : std::string(to_string(method_));
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
    std::unique_ptr<render::Renderer> renderer_;
    render::RenderSettings settings_;

    Scene scene_;
    OrbitCamera orbit_;
    std::unique_ptr<LoadedEnvironment> environment_;
    gl::Texture cells_texture_, map_texture_;
    BackgroundJob<LoadedEnvironment> environment_job_;
    BackgroundJob<LoadedModel> model_job_;
    BackgroundJob<AnimatedSky> sky_job_;
    std::optional<double> animated_sky_time_;  // the animation time of the sky on screen, when animated
    bool sun_follows_time_ = true;
    LightSource light_source_ = LightSource::cells;
    std::optional<render::FsSampler> fs_sampler_;
    std::vector<Cell> fs_lights_;  // this frame's, in map space
    double fs_sampling_ms_ = 0.0;

    int lights_ = 128;
    Method method_ = Method::lloyd;
    std::uint64_t seed_ = 1;
    float exposure_ = 0.0f;
    float rotation_ = 0.0f;
    double time_ = 0.0;
    float speed_ = 1.0f;  // animation seconds per second
    bool playing_ = true;
    int selected_object_ = 0;
    int selected_cell_ = 0;
    bool show_help_ = false;
    bool screenshot_requested_ = false;
    bool last_frame_ = false;  // of an automated run (--frames)
    std::string last_screenshot_;
    std::string error_;

    std::deque<float> frame_ms_;
    std::map<std::string, std::deque<float>> pass_ms_;
};

}  // namespace

int run_viewer(const ViewerOptions& options) {
    Viewer viewer(options);
    return viewer.run();
}

}  // namespace envshadow::app
