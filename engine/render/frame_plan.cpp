#include "render/frame_plan.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_inverse.hpp>

#include "env/brdf.h"

namespace envshadow::render {

namespace {
std::array<glm::vec3, 8> box_corners(const glm::vec3& lo, const glm::vec3& hi) {
    return {glm::vec3(lo.x, lo.y, lo.z), glm::vec3(hi.x, lo.y, lo.z), glm::vec3(lo.x, hi.y, lo.z),
            glm::vec3(hi.x, hi.y, lo.z), glm::vec3(lo.x, lo.y, hi.z), glm::vec3(hi.x, lo.y, hi.z),
            glm::vec3(lo.x, hi.y, hi.z), glm::vec3(hi.x, hi.y, hi.z)};
}
}  // namespace

CameraView camera_view(const Scene& scene, int width, int height, double time) {
    CameraView view;
    view.width = width;
    view.height = height;
    view.eye = scene.camera.position;
    view.view_from_world = scene.camera.view_from_world();
    // Near and far planes around the scene's bounding sphere; the background is drawn at the far plane
    // whatever its distance.
    glm::vec3 lo(0.0f), hi(0.0f);
    if (!scene.objects.empty()) scene.bounds_at(time, lo, hi);
    const float radius = 0.5f * glm::length(hi - lo) + 1e-3f;
    const float distance = glm::length(0.5f * (lo + hi) - view.eye);
    const float far_plane = (distance + radius) * 1.01f;
    const float near_plane = std::max(distance - radius, far_plane * 1e-4f);
    view.clip_from_view = scene.camera.clip_from_view(float(width) / float(height), near_plane, far_plane);
    return view;
}

CameraView shifted_by_pixels(const CameraView& view, glm::vec2 pixels) {
    glm::mat4 shift(1.0f);
    shift[3][0] = 2.0f * pixels.x / float(view.width);  // clip x spans 2 over the width
    shift[3][1] = 2.0f * pixels.y / float(view.height);
    CameraView shifted = view;
    shifted.clip_from_view = shift * view.clip_from_view;
    return shifted;
}

glm::vec2 sample_margin(std::span<const glm::vec2> sample_positions) {
    glm::vec2 margin(0.5f);
    for (const glm::vec2 p : sample_positions) margin = glm::min(margin, glm::min(p, 1.0f - p));
    return glm::max(margin, glm::vec2(0.0f));
}

std::vector<glm::vec2> subpixel_jitter(int count, std::span<const glm::vec2> sample_positions) {
    if (count < 1 || sample_positions.empty()) return {};
    const glm::vec2 margin = sample_margin(sample_positions);
    // Shift k at ((k + 1/2) / count, ((g k mod count) + 1/2) / count) of the box [-margin, margin]^2, for the
    // generator g coprime to count that keeps the shifts farthest apart on its torus: a rank-1 lattice.
    const auto point = [count](int k, int g) {
        return glm::vec2((float(k) + 0.5f) / float(count), (float((g * k) % count) + 0.5f) / float(count));
    };
    int best = 1;
    float best_spacing = -1.0f;
    for (int g = 1; g < count; ++g) {
        if (std::gcd(g, count) != 1) continue;
        float spacing = std::numeric_limits<float>::max();  // a lattice: every point's nearest is as near as 0's
        for (int k = 1; k < count; ++k) {
            const glm::vec2 d = glm::abs(point(k, g) - point(0, g));
            spacing = std::min(spacing, glm::length(glm::min(d, 1.0f - d)));
        }
        if (spacing > best_spacing + 1e-6f) best = g, best_spacing = spacing;
    }
    std::vector<glm::vec2> shifts;
    for (int k = 0; k < count; ++k) shifts.push_back((2.0f * point(k, best) - 1.0f) * margin);
    return shifts;
}

glm::vec2 penumbra_texels_per_depth(const glm::mat4& clip_from_world, int tile_size, float cos_radius) {
    const float c = std::clamp(cos_radius, 1e-3f, 1.0f);
    const float tan_radius = std::sqrt(std::max(1.0f - c * c, 0.0f)) / c;
    // Rows of the orthographic projection: |row| = 1 / half-extent along that axis (clip units per world).
    auto row_length = [&](int r) {
        return glm::length(glm::vec3(clip_from_world[0][r], clip_from_world[1][r], clip_from_world[2][r]));
    };
    const float depth_range = 2.0f / row_length(2);  // world distance of depth 0..1
    const glm::vec2 texels_per_world = 0.5f * float(tile_size) * glm::vec2(row_length(0), row_length(1));
    return tan_radius * depth_range * texels_per_world;
}

bool uses_tile_lists(const RenderSettings& settings) {
    return settings.shadow_tile_lists && settings.depth_prepass;
}

glm::vec3 flat_receiver_sum(std::span<const LightRecord> lights, const glm::vec3& k_d, const glm::vec3& normal) {
    glm::dvec3 sum(0.0);
    for (const LightRecord& light : lights)
        sum += glm::dvec3(light.radiance) *
               (glm::dvec3(k_d) * double(std::max(glm::dot(normal, glm::vec3(light.direction)), 0.0f)));
    return glm::vec3(sum);
}

std::vector<glm::vec3> animation_caster_points(std::span<const PlannedObject> objects) {
    std::vector<glm::vec3> points;
    for (const PlannedObject& planned : objects) {
        const Object& object = planned.object;
        if (!object.casts_shadows) continue;
        const std::array<glm::vec3, 8> corners = box_corners(planned.bounds_min, planned.bounds_max);
        if (!object.moves()) {
            for (const glm::vec3& corner : corners)
                points.push_back(glm::vec3(object.world_from_object(0.0) * glm::vec4(corner, 1.0f)));
            continue;
        }
        // The corners at kSubsteps times per sample: the path a corner travels between two samples is
        // at most the sum of its sub-steps' chords (about its arc), and no point of the box between the
        // samples is farther than that from where it was at one of them.
        constexpr int kSubsteps = 4;
        const int steps = kAnimationFitSamples * kSubsteps;
        const double period = object.motion_period();
        std::vector<std::array<glm::vec3, 8>> at(std::size_t(steps) + 1);
        for (int s = 0; s <= steps; ++s) {
            const double t = period * double(s) / double(steps);
            const glm::mat4 world = object.world_from_object(t);
            std::array<glm::vec3, 8> box = corners;
            if (object.deforms()) {  // the pose's box at t (glTF skins and morphs)
                const std::shared_ptr<const Mesh> posed = object.mesh_at(t);
                box = box_corners(posed->bounds_min, posed->bounds_max);
            }
            for (std::size_t c = 0; c < 8; ++c) at[std::size_t(s)][c] = glm::vec3(world * glm::vec4(box[c], 1.0f));
        }
        float reach = 0.0f;  // the farthest any corner travels between two samples
        for (int sample = 0; sample < kAnimationFitSamples; ++sample)
            for (std::size_t c = 0; c < 8; ++c) {
                float path = 0.0f;
                for (int s = sample * kSubsteps; s < (sample + 1) * kSubsteps; ++s)
                    path += glm::length(at[std::size_t(s) + 1][c] - at[std::size_t(s)][c]);
                reach = std::max(reach, path);
            }
        for (int sample = 0; sample < kAnimationFitSamples; ++sample)
            for (const glm::vec3& corner : at[std::size_t(sample * kSubsteps)])
                for (const glm::vec3& offset : box_corners(glm::vec3(-reach), glm::vec3(reach)))
                    points.push_back(corner + offset);
    }
    return points;
}

void FramePlanner::set_objects(std::vector<PlannedObject> objects) {
    objects_ = std::move(objects);
    animation_points_ = animation_caster_points(objects_);
    animation_fits_.clear();
}

void FramePlanner::set_lights(std::span<const WorldLight> lights) {
    lights_.assign(lights.begin(), lights.end());
    frames_.clear();
    for (const WorldLight& light : lights_) frames_.push_back(light_frame(light.direction));
    neighbourhoods_ = light_neighbourhoods(lights_);
    animation_fits_.clear();
}

const FramePlan& FramePlanner::plan(double time, const CameraView& view, const AtlasLayout& layout,
                                    const RenderSettings& settings) {
    place_objects(time);
    fit_lights(layout, settings);
    fit_caster_rects(layout, settings);
    shade_objects(view, settings);
    return plan_;
}

void FramePlanner::place_objects(double time) {
    plan_.objects.resize(objects_.size());
    caster_points_.clear();
    for (std::size_t i = 0; i < objects_.size(); ++i) {
        const PlannedObject& planned = objects_[i];
        ObjectFrame& frame = plan_.objects[i];
        frame.world_from_object = planned.object.world_from_object(time);
        frame.world_normal_from_object = glm::inverseTranspose(glm::mat3(frame.world_from_object));
        frame.casts_shadows = planned.object.casts_shadows;
        if (!frame.casts_shadows) continue;
        // The object's box corners in the world: tighter in the light's frame than the world box.
        for (const glm::vec3& corner : box_corners(planned.bounds_min, planned.bounds_max))
            caster_points_.push_back(glm::vec3(frame.world_from_object * glm::vec4(corner, 1.0f)));
    }
}

void FramePlanner::fit_lights(const AtlasLayout& layout, const RenderSettings& settings) {
    const glm::vec2 atlas_size(float(layout.width()), float(layout.height()));
    const bool weighted = settings.cap == CapKind::weighted;
    plan_.lights.resize(lights_.size());
    plan_.texel_world.resize(lights_.size());
    plan_.min_texel_world = std::numeric_limits<float>::infinity();
    // Over the animation the fits depend on the lights and the tiles' sizes alone: made once for them.
    const bool over_animation = settings.shadow_fit == ShadowFit::animation;
    if (over_animation) {
        bool same = animation_fits_.size() == lights_.size();
        for (std::size_t k = 0; same && k < lights_.size(); ++k)
            same = animation_fit_tile_sizes_[k] == layout.tiles.at(k).size;
        if (!same) {
            animation_fits_.clear();
            animation_fit_tile_sizes_.clear();
            for (std::size_t k = 0; k < lights_.size(); ++k) {
                const int size = layout.tiles.at(k).size;
                animation_fits_.push_back(fit_orthographic(frames_[k], animation_points_, size, kTileMarginTexels));
                animation_fit_tile_sizes_.push_back(size);
            }
        }
    }
    bool fits_changed = previous_fits_.size() != lights_.size();
    previous_fits_.resize(lights_.size());
    previous_tiles_.resize(lights_.size());
    for (std::size_t k = 0; k < lights_.size(); ++k) {
        const WorldLight& light = lights_[k];
        const TileRect& tile = layout.tiles.at(k);
        const OrthographicFit fit = over_animation
                                        ? animation_fits_[k]
                                        : fit_orthographic(frames_[k], caster_points_, tile.size, kTileMarginTexels);
        LightRecord& record = plan_.lights[k];
        record.direction = glm::vec4(light.direction, weighted ? light.cos_radius_weighted : light.cos_radius);
        record.radiance = glm::vec4(light.radiance, neighbourhoods_[k].surrounded ? 1.0f : 0.0f);
        record.clip_from_world = fit.clip_from_world;
        record.tile =
            glm::vec4(glm::vec2(float(tile.x), float(tile.y)) / atlas_size, glm::vec2(float(tile.size)) / atlas_size);
        record.bias =
            glm::vec4(settings.depth_bias * fit.texel_world / fit.depth_range, settings.normal_offset * fit.texel_world,
                      penumbra_texels_per_depth(fit.clip_from_world, tile.size, record.direction.w));
        record.neighbourhood = neighbourhoods_[k].lights;
        plan_.texel_world[k] = fit.texel_world;
        plan_.min_texel_world = std::min(plan_.min_texel_world, fit.texel_world);
        if (previous_fits_[k] != record.clip_from_world || previous_tiles_[k] != record.tile) fits_changed = true;
        previous_fits_[k] = record.clip_from_world;
        previous_tiles_[k] = record.tile;
    }
    if (fits_changed) ++plan_.fit_version;
    if (plan_.lights.empty()) plan_.min_texel_world = 0.0f;
    // Position reconstruction and rounding; V = 1 for 2 texels inside the border anyway.
    plan_.receiver_pad = plan_.min_texel_world;
    for (const LightRecord& record : plan_.lights)
        plan_.receiver_pad = std::max(plan_.receiver_pad, record.bias.y + plan_.min_texel_world);
}

void FramePlanner::fit_caster_rects(const AtlasLayout& layout, const RenderSettings& settings) {
    const bool soft = settings.shadows == ShadowMode::soft;
    const std::size_t casters = caster_points_.size() / 8;
    const bool each = casters >= 1 && casters <= std::size_t(kMaxCasterRects);
    plan_.caster_rects_per_light = each ? int(casters) : 1;
    plan_.caster_rects.assign(plan_.lights.size() * std::size_t(plan_.caster_rects_per_light),
                              glm::vec4(-1.0f, -1.0f, 1.0f, 1.0f));
    if (each) {
        for (std::size_t k = 0; k < plan_.lights.size(); ++k) {
            const float pad = 2.0f * 2.0f / float(layout.tiles.at(k).size);  // 2 texels of its tile in clip units
            for (std::size_t c = 0; c < casters; ++c) {
                glm::vec2 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
                float nearest = 1.0f;  // the caster's smallest depth (0..1) in this tile
                for (std::size_t j = 0; j < 8; ++j) {
                    const glm::vec3 xyz(plan_.lights[k].clip_from_world * glm::vec4(caster_points_[8 * c + j], 1.0f));
                    lo = glm::min(lo, glm::vec2(xyz));
                    hi = glm::max(hi, glm::vec2(xyz));
                    nearest = std::min(nearest, 0.5f * xyz.z + 0.5f);
                }
                // Soft shadows reach past the caster by the widest penumbra it can cast, a receiver at the
                // far plane: (1 - nearest) times the penumbra per depth (docs/DESIGN.md §5.9).
                glm::vec2 reach(pad);
                if (soft)
                    reach += glm::vec2(plan_.lights[k].bias.z, plan_.lights[k].bias.w) *
                             std::max(1.0f - nearest, 0.0f) * (2.0f / float(layout.tiles.at(k).size));
                plan_.caster_rects[k * casters + c] = glm::vec4(lo - reach, hi + reach);
            }
        }
    }
    if (plan_.caster_rects.empty()) plan_.caster_rects.push_back(glm::vec4(0.0f));
}

void FramePlanner::shade_objects(const CameraView& view, const RenderSettings& settings) {
    for (std::size_t i = 0; i < objects_.size(); ++i) {
        const PlannedObject& planned = objects_[i];
        ObjectFrame& frame = plan_.objects[i];
        const Material& material = planned.object.material;
        frame.k_d = glm::vec3(brdf::diffuse_coefficient(material.rho_d.r), brdf::diffuse_coefficient(material.rho_d.g),
                              brdf::diffuse_coefficient(material.rho_d.b));
        frame.k_s = brdf::specular_coefficient(material.rho_s, material.shininess);
        frame.shininess = material.shininess;
        frame.unshadowed = glm::vec3(0.0f);
        frame.metallic_roughness = material.metallic_roughness;
        frame.emission = material.emission;
        frame.occlusion_strength = material.occlusion_strength;
        frame.normal_scale = material.normal_texture && settings.normal_texture ? material.normal_scale : 0.0f;
        frame.base_alpha = material.masked() || material.blended() ? material.base_alpha : 1.0f;
        frame.alpha_cutoff = material.masked() ? material.alpha_cutoff : 0.0f;
        frame.blended = material.blended();
        if (frame.metallic_roughness && settings.shading == ShadingMode::ratio) {
            frame.program = ShadeProgram::metallic_roughness;
            continue;
        }
        // Materials without a specular part get the shader compiled without it (shade.frag DIFFUSE_ONLY).
        const bool diffuse_only = settings.specialise_shaders && !(frame.k_s > 0.0f);
        frame.program = diffuse_only ? ShadeProgram::diffuse_only : ShadeProgram::full;
        if (!diffuse_only || !settings.flat_receivers || !uses_tile_lists(settings) ||
            settings.diffuse != DiffuseMode::center || !planned.flat_normal || frame.normal_scale != 0.0f ||
            frame.blended)
            continue;
        // A plane with a diffuse material (the ground): the normal the shader would use, turned to the
        // eye as shade.frag turns it, gives every a_i once for all its pixels. Seen edge-on it is
        // shaded per pixel.
        const glm::vec3 n = glm::normalize(frame.world_normal_from_object * *planned.flat_normal);
        const glm::vec3 point(frame.world_from_object * glm::vec4(planned.bounds_min, 1.0f));
        const float side = glm::dot(n, view.eye - point);
        if (!std::isfinite(side) || !(std::abs(side) > 1e-4f)) continue;
        frame.program = ShadeProgram::flat_receiver;
        frame.unshadowed = flat_receiver_sum(plan_.lights, frame.k_d, side < 0.0f ? -n : n);
    }
}

}  // namespace envshadow::render
