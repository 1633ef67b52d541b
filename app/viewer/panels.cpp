#include "viewer/panels.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iterator>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <imgui.h>

#include "env/latlong.h"
#include "options.h"
#include "scene/gltf_material.h"

namespace envshadow::app {
namespace {

constexpr std::size_t kHistory = 240;  // frames kept for the timing plots

ImTextureID texture_id(const gl::Texture& texture) {
    return reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(texture.id()));
}

float radiance_sum(const Cell& c) {
    return c.radiance.r + c.radiance.g + c.radiance.b;
}

// A combo of `values`, `current` shown; the value picked (other than `current`), if any.
std::optional<std::string> value_combo(const char* label, const std::string& current,
                                       std::span<const std::string> values) {
    std::optional<std::string> picked;
    if (ImGui::BeginCombo(label, current.c_str())) {
        for (const std::string& value : values)
            if (ImGui::Selectable(value.c_str(), value == current) && value != current) picked = value;
        ImGui::EndCombo();
    }
    return picked;
}

// A combo of the values of the setting called `name` in render::setting_table() (its choices, or for an
// integer range the powers of two in it), as the command line spells them; true when one was picked.
bool setting_combo(const char* label, std::string_view name, render::RenderSettings& settings) {
    const render::SettingInfo* row = render::find_setting(name);
    if (!row) throw std::logic_error("no setting " + std::string(name));
    std::vector<std::string> values = row->choices;
    if (values.empty())
        for (double value = std::max(row->min, 1.0); value <= row->max; value *= 2.0)
            values.push_back(std::to_string(int(value)));
    const std::optional<std::string> picked = value_combo(label, row->format(settings), values);
    if (picked) row->parse(settings, *picked);
    return picked.has_value();
}

}  // namespace

void Panels::record(const render::FrameStats& stats, double frame_seconds, std::optional<double> sampling_ms) {
    auto push = [](std::deque<float>& history, float value) {
        history.push_back(value);
        if (history.size() > kHistory) history.pop_front();
    };
    push(frame_ms_, float(frame_seconds * 1000.0));
    for (const gl::PassTime& pass : stats.passes) push(pass_ms_[pass.pass], float(pass.milliseconds));
    if (sampling_ms) push(pass_ms_[render::kFsSamplingPass], float(*sampling_ms));
}

PanelChanges Panels::draw(ViewerControls& controls, const PanelInputs& in) {
    PanelChanges changes;
    settings_panel(controls, in, changes);
    timings_panel(controls, in, changes);
    atlas_panel(controls, in);
    cells_panel(controls, in);
    if (controls.show_help) help_panel(controls);
    return changes;
}

void Panels::settings_panel(ViewerControls& controls, const PanelInputs& in, PanelChanges& changes) {
    render::RenderSettings& settings = controls.settings;
    const render::FrameStats& stats = *in.stats;
    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(330, 0), ImGuiCond_FirstUseEver);
    ImGui::Begin("envshadow", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
    ImGui::TextUnformatted(in.scene->file.filename().string().c_str());
    if (!in.error.empty()) ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.3f, 1.0f), "%s", in.error.c_str());
    if (in.environment_job.running) {
        ImGui::ProgressBar(
            -1.0f * float(ImGui::GetTime()), ImVec2(-1, 0),
            (in.environment_job.what + " " + std::to_string(int(in.environment_job.seconds * 1000)) + " ms").c_str());
    }
    if (in.model_job.running) ImGui::TextUnformatted(in.model_job.what.c_str());

    if (ImGui::CollapsingHeader("Lights", ImGuiTreeNodeFlags_DefaultOpen)) {
        int source = int(controls.light_source);
        ImGui::RadioButton("cells (load time)", &source, int(render::LightSourceKind::cells));
        ImGui::SameLine();
        ImGui::RadioButton("GPU FS (every frame)", &source, int(render::LightSourceKind::gpu_fs));
        if (source != int(controls.light_source)) {
            controls.light_source = render::LightSourceKind(source);
            changes.light_source = true;
        }
        // Decompose when the slider is let go, not on every step of the drag.
        ImGui::SliderInt("cells N", &controls.lights, 1, kMaxLights, "%d", ImGuiSliderFlags_AlwaysClamp);
        bool redo = ImGui::IsItemDeactivatedAfterEdit();
        if (controls.light_source == render::LightSourceKind::cells) {
            std::vector<const render::LightMethod*> methods;
            std::vector<std::string> names;
            int method_index = 0;
            for (const render::LightMethod& method : render::light_methods())
                if (method.kind == render::LightSourceKind::cells) {
                    if (method.decomposition == controls.method) method_index = int(methods.size());
                    methods.push_back(&method);
                    names.emplace_back(method.name());
                }
            if (ImGui::BeginCombo("method", names[std::size_t(method_index)].c_str())) {
                for (std::size_t i = 0; i < methods.size(); ++i) {
                    if (ImGui::Selectable(names[i].c_str(), int(i) == method_index) && int(i) != method_index) {
                        controls.method = methods[i]->decomposition;
                        redo = true;
                    }
                    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", std::string(methods[i]->help).c_str());
                }
                ImGui::EndCombo();
            }
            changes.decompose = redo;
        }
        const render::FsSampler* sampler = in.lights ? in.lights->sampler() : nullptr;
        if (controls.light_source == render::LightSourceKind::gpu_fs) {
            ImGui::Checkbox("sun follows time (builtin:sky)", &controls.sun_follows_time);
            if (sampler) {
                const render::FsCounts counts = sampler->read_counts();
                ImGui::Text("GPU FS: %u lights from %u samples of a %dx%d importance map, %.2f ms", counts.light_count,
                            counts.samples, sampler->importance_size().x, sampler->importance_size().y,
                            in.lights->sampling_ms());
            }
        } else if (in.cells) {
            ImGui::Text("%zu cells, decomposed in %.1f ms (%d iterations)", in.cells->cells.size(),
                        in.cells->seconds * 1000.0, in.cells->iterations);
        }
        if (in.lights) {
            ImGui::Text("%d lights drawn, %d below ground, %d negligible", stats.lights, stats.lights_below_ground,
                        stats.lights_negligible);
        }
    }

    if (ImGui::CollapsingHeader("Shadows")) {
        bool changed = false;
        changed |= setting_combo("tile size", "tile", settings);
        changed |= setting_combo("tile sizes", "tile-sizes", settings);
        if (settings.tile_sizing != render::TileSizing::uniform)
            ImGui::TextDisabled("the same texels as uniform tiles of this size");
        changed |= setting_combo("depth bits", "depth-bits", settings);
        changed |= setting_combo("PCF", "pcf", settings);
        changed |= setting_combo("shadows", "shadows", settings);
        changed |= ImGui::SliderFloat("slope bias", &settings.slope_bias, 0.0f, 8.0f);
        changed |= ImGui::SliderFloat("depth bias", &settings.depth_bias, 0.0f, 8.0f);
        changed |= ImGui::SliderFloat("normal offset", &settings.normal_offset, 0.0f, 4.0f);
        changed |= setting_combo("atlas draw", "atlas", settings);
        changed |= ImGui::Checkbox("skip hidden/negligible lights", &settings.skip_lights);
        changed |= ImGui::Checkbox("cache the shadows of what stands still", &settings.shadow_cache);
        changes.settings |= changed;
        ImGui::Text("atlas %dx%d, %.1f MB", stats.atlas.width(), stats.atlas.height(),
                    double(stats.atlas_bytes) / (1 << 20));
    }

    if (ImGui::CollapsingHeader("Shading", ImGuiTreeNodeFlags_DefaultOpen)) {
        bool changed = false;
        changed |= setting_combo("shading", "shading", settings);
        if (settings.shading == render::ShadingMode::ratio) {
            changed |= setting_combo("shadowed fraction per", "shadow-rate", settings);
            if (settings.shadow_rate != render::ShadowRate::fragment)
                changed |= ImGui::Checkbox("filter the fraction's noise", &settings.fraction_filter);
            if (settings.shadow_rate == render::ShadowRate::half)
                changed |= ImGui::Checkbox("the sun's shadow per pixel", &settings.sun_per_pixel);
        }
        changed |= setting_combo("specular", "specular", settings);
        changed |= setting_combo("cap radius", "cap", settings);
        changed |= setting_combo("diffuse", "diffuse", settings);
        changed |= ImGui::Checkbox("background", &settings.background);
        changed |= setting_combo("msaa samples", "msaa", settings);
        changes.settings |= changed;
        ImGui::SliderFloat("exposure", &controls.exposure, -6.0f, 6.0f, "%.2f stops");
        const std::vector<std::string> tone_maps = enum_value_names<ToneMap>();
        if (const auto picked = value_combo("tone map", std::string(to_string(controls.tone_map)), tone_maps))
            controls.tone_map = parse_enum<ToneMap>(*picked);
        changes.rotation = ImGui::SliderFloat("env rotation", &controls.rotation, -180.0f, 180.0f, "%.0f deg");
    }

    const std::vector<Object>& objects = in.scene->objects;
    if (!objects.empty() && ImGui::CollapsingHeader("Material")) {
        controls.selected_object = std::min(controls.selected_object, int(objects.size()) - 1);
        const std::size_t selected = std::size_t(controls.selected_object);
        if (ImGui::BeginCombo("object", objects[selected].name.c_str())) {
            for (int i = 0; i < int(objects.size()); ++i)
                if (ImGui::Selectable(objects[std::size_t(i)].name.c_str(), i == controls.selected_object))
                    controls.selected_object = i;
            ImGui::EndCombo();
        }
        Material m = objects[std::size_t(controls.selected_object)].material;
        bool changed = false;
        if (m.metallic_roughness) {  // glTF's parameters; the Phong stand-in follows them
            MetallicRoughness p = *m.metallic_roughness;
            changed |= ImGui::ColorEdit3("base colour", &p.base_color.x);
            changed |= ImGui::SliderFloat("metallic", &p.metallic, 0.0f, 1.0f);
            changed |= ImGui::SliderFloat("roughness", &p.roughness, 0.0f, 1.0f);
            if (changed) m = with_metallic_roughness(m, p);
        } else {
            changed |= ImGui::ColorEdit3("rho_d", &m.rho_d.x);
            changed |= ImGui::SliderFloat("rho_s", &m.rho_s, 0.0f, 1.0f);
            changed |=
                ImGui::SliderFloat("shininess n", &m.shininess, 1.0f, 10000.0f, "%.0f", ImGuiSliderFlags_Logarithmic);
        }
        ImGui::TextDisabled("base-colour texture: %s; %s-sided", m.base_color_texture ? "yes" : "no",
                            m.double_sided ? "double" : "single");
        if (m.metallic_roughness)
            ImGui::TextDisabled("metallic-roughness texture: %s", m.metallic_roughness_texture ? "yes" : "no");
        changed |= ImGui::ColorEdit3("emission", &m.emission.x, ImGuiColorEditFlags_HDR | ImGuiColorEditFlags_Float);
        ImGui::TextDisabled("emission texture: %s", m.emission_texture ? "yes" : "no");
        if (m.occlusion_texture)
            changed |= ImGui::SliderFloat("occlusion strength", &m.occlusion_strength, 0.0f, 1.0f);
        else
            ImGui::TextDisabled("occlusion texture: no");
        if (m.normal_texture)
            changed |= ImGui::SliderFloat("normal scale", &m.normal_scale, 0.0f, 2.0f);
        else
            ImGui::TextDisabled("normal texture: no");
        if (m.alpha_mode == AlphaMode::mask)
            ImGui::TextDisabled("alpha mask: cut below %.2f (factor alpha %.2f)", m.alpha_cutoff, m.base_alpha);
        if (m.alpha_mode == AlphaMode::blend) {
            ImGui::TextDisabled("alpha blend%s", m.base_color_texture ? " (times the base-colour texture's)" : "");
            changed |= ImGui::SliderFloat("alpha", &m.base_alpha, 0.0f, 1.0f);
        }
        if (changed) changes.material.emplace(std::size_t(controls.selected_object), m);
        // Every object's textures of one kind off at once, as glTF viewers' debug views do.
        ImGui::Separator();
        ImGui::TextUnformatted("textures of all objects:");
        bool textures_changed = ImGui::Checkbox("base colour", &settings.base_color_texture);
        textures_changed |= ImGui::Checkbox("emission", &settings.emission_texture);
        textures_changed |= ImGui::Checkbox("occlusion", &settings.occlusion_texture);
        textures_changed |= ImGui::Checkbox("metallic-roughness", &settings.metallic_roughness_texture);
        textures_changed |= ImGui::Checkbox("normal", &settings.normal_texture);
        changes.settings |= textures_changed;
    }

    if (ImGui::CollapsingHeader("Animation")) {
        ImGui::Checkbox("play", &controls.playing);
        ImGui::SameLine();
        ImGui::SliderFloat("speed", &controls.speed, 0.0f, 4.0f);
        float t = float(controls.time);
        if (ImGui::SliderFloat("time", &t, 0.0f, 60.0f, "%.2f s")) controls.time = t;
    }
    if (ImGui::Button("screenshot (F12)")) controls.screenshot_requested = true;
    ImGui::SameLine();
    if (ImGui::Button("help (H)")) controls.show_help = !controls.show_help;
    if (!in.last_screenshot.empty()) ImGui::TextWrapped("saved %s", in.last_screenshot.c_str());
    ImGui::End();
}

void Panels::timings_panel(ViewerControls& controls, const PanelInputs& in, PanelChanges& changes) {
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
    DynamicResolutionOptions& resolution = controls.dynamic_resolution;
    ImGui::Checkbox("dynamic resolution", &resolution.enabled);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "While the camera moves or the animation plays, shade a fraction of the window\n"
            "that holds the target frame time; full size once the view is still.");
    if (resolution.enabled) {
        float target = float(resolution.target_ms);
        if (ImGui::SliderFloat("target ms", &target, 10.0f, 1000.0f, "%.0f", ImGuiSliderFlags_Logarithmic))
            resolution.target_ms = target;
        ImGui::Checkbox("1 sample while moving", &resolution.one_sample_while_moving);
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip(
                "No MSAA while the view changes: on a CPU rasteriser 4 samples cost about 3x the shading.");
        ImGui::Checkbox("hard shadows while moving", &resolution.hard_shadows_while_moving);
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("One lookup per cell while the view changes: soft shadows cost about 3.5x that.");
    }
    ImGui::Text("shading %dx%d (%.0f%% of the window)%s", in.shaded_width, in.shaded_height,
                double(in.shaded_scale) * 100.0, in.shaded_scale < 1.0f ? " while the view changes" : "");
    bool synchronous = in.renderer->pass_timing() == gl::PassTiming::synchronous;
    if (ImGui::Checkbox("wait for each pass", &synchronous))
        changes.pass_timing = synchronous ? gl::PassTiming::synchronous : gl::PassTiming::queries;
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "Times each pass by the clock between glFinish calls: exact on a software\n"
            "rasteriser, whose GL_TIME_ELAPSED queries misplace the work (on by default\n"
            "there); on a GPU the queries are exact and waiting costs the overlap.");
    // The shadow cache (docs/DESIGN.md §5.11): a frame that moves nothing draws no atlas pass.
    if (in.stats->atlas_passes == 0)
        ImGui::TextUnformatted("shadow atlas: kept from the last frame (nothing moved)");
    else if (in.stats->moving_casters_drawn > 0)
        ImGui::Text("shadow atlas: %d moving caster(s) over the cached layer%s", in.stats->moving_casters_drawn,
                    in.stats->static_layer_renders > 0 ? " (layer redrawn)" : "");
    for (const gl::PassTime& pass : in.stats->passes) plot(pass.pass.c_str(), pass_ms_[pass.pass]);
    if (in.lights && in.lights->per_frame()) plot(render::kFsSamplingPass, pass_ms_[render::kFsSamplingPass]);
    ImGui::End();
}

void Panels::atlas_panel(const ViewerControls& controls, const PanelInputs& in) {
    ImGui::SetNextWindowPos(ImVec2(346, 8), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(420, 228), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowCollapsed(true, ImGuiCond_FirstUseEver);
    if (ImGui::Begin("Shadow atlas")) {
        const gl::Texture& atlas = in.renderer->atlas_texture();
        if (atlas) {
            const gl::Texture& preview = display_.atlas_preview(atlas, 1024);
            const float w = std::min(ImGui::GetContentRegionAvail().x, float(preview.width()));
            const float h = w * float(preview.height()) / float(preview.width());
            // GL textures start at the bottom row: flip v.
            ImGui::Image(texture_id(preview), ImVec2(w, h), ImVec2(0, 1), ImVec2(1, 0));
            const render::AtlasLayout& layout = in.renderer->atlas_layout();
            if (layout.sizing == render::TileSizing::uniform)
                ImGui::Text("%d tiles of %d^2", in.renderer->light_count(), controls.settings.tile_size);
            else
                ImGui::Text("%d tiles, %s", in.renderer->light_count(), tile_sizes_words(layout).c_str());
        }
    }
    ImGui::End();
}

void Panels::cells_panel(ViewerControls& controls, const PanelInputs& in) {
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    ImGui::SetNextWindowPos(ImVec2(display.x - 388, display.y - 292), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(380, 284), ImGuiCond_FirstUseEver);
    if (controls.light_source == render::LightSourceKind::gpu_fs) {
        sampled_lights_panel(in);
        return;
    }
    if (ImGui::Begin("Environment cells") && in.cells && in.cells_picture && *in.cells_picture) {
        const Decomposition& d = *in.cells;
        const float w = ImGui::GetContentRegionAvail().x, h = w * 0.5f;
        const ImVec2 origin = ImGui::GetCursorScreenPos();
        ImGui::Image(texture_id(*in.cells_picture), ImVec2(w, h));
        if (ImGui::IsItemHovered() && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
            const ImVec2 mouse = ImGui::GetMousePos();
            const int i = std::clamp(int((mouse.x - origin.x) / w * float(d.width)), 0, d.width - 1);
            const int j = std::clamp(int((mouse.y - origin.y) / h * float(d.height)), 0, d.height - 1);
            const std::uint16_t cell = d.texel_cell[std::size_t(j) * std::size_t(d.width) + std::size_t(i)];
            if (cell != kNoCell) controls.selected_cell = cell;  // kNoCell: below an upper hemisphere's horizon
        }
        if (!d.cells.empty()) {
            controls.selected_cell = std::min(controls.selected_cell, int(d.cells.size()) - 1);
            ImGui::SliderInt("cell", &controls.selected_cell, 0, int(d.cells.size()) - 1);
            const Cell& c = d.cells[std::size_t(controls.selected_cell)];
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
void Panels::sampled_lights_panel(const PanelInputs& in) {
    if (ImGui::Begin("Environment cells") && in.map_picture && *in.map_picture) {
        const std::vector<Cell> none;
        const std::vector<Cell>& lights = in.lights && in.lights->per_frame() ? in.lights->lights() : none;
        const float w = ImGui::GetContentRegionAvail().x, h = w * 0.5f;
        const ImVec2 origin = ImGui::GetCursorScreenPos();
        ImGui::Image(texture_id(*in.map_picture), ImVec2(w, h));
        float brightest = 0.0f;
        for (const Cell& c : lights) brightest = std::max(brightest, radiance_sum(c));
        for (const Cell& c : lights) {
            const glm::dvec2 uv = latlong::uv(glm::dvec3(c.direction));
            const float share = radiance_sum(c) / std::max(brightest, 1e-30f);
            ImGui::GetWindowDrawList()->AddCircleFilled(ImVec2(origin.x + float(uv.x) * w, origin.y + float(uv.y) * h),
                                                        2.0f + 4.0f * std::sqrt(share), IM_COL32(255, 60, 40, 255));
        }
        ImGui::Text("%zu lights sampled on the GPU this frame (dots)", lights.size());
    }
    ImGui::End();
}

void Panels::help_panel(ViewerControls& controls) {
    ImGui::SetNextWindowPos(ImVec2(400, 300), ImGuiCond_FirstUseEver);
    ImGui::Begin("Help", &controls.show_help, ImGuiWindowFlags_AlwaysAutoResize);
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

}  // namespace envshadow::app
