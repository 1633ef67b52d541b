#include "render/renderer.h"

#include <algorithm>
#include <array>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <glm/matrix.hpp>

#include "core/error.h"
#include "core/log.h"
#include "env/dfg_table.h"
#include "env/latlong.h"
#include "env/orientation.h"
#include "gl/readback.h"
#include "render/embedded_shaders.h"
#include "render/gpu_texture.h"
#include "render/shader_interface.h"

namespace envshadow::render {

using namespace shader;  // loc::, unit::, binding::, size::

namespace {
// Whether a setting whose change has `effect` differs between `a` and `b` (render::setting_table()).
bool changes(SettingEffect effect, const RenderSettings& a, const RenderSettings& b) {
    for (const SettingInfo& setting : setting_table())
        if (setting.effect == effect && setting.format(a) != setting.format(b)) return true;
    return false;
}

// Viewports used per batch in AtlasMode::viewport_array (GL_MAX_VIEWPORTS is 16 on most drivers).
constexpr int kMaxViewports = 64;

// A framebuffer drawing into `colours` (attachments 0, 1, ...) over `depth`; `what` names it in errors.
gl::Framebuffer colour_target(std::initializer_list<const gl::Texture*> colours, const gl::Texture& depth,
                              const char* what) {
    gl::Framebuffer target = gl::Framebuffer::create();
    std::vector<GLenum> draw_buffers;
    for (const gl::Texture* colour : colours) {
        draw_buffers.push_back(GLenum(GL_COLOR_ATTACHMENT0 + draw_buffers.size()));
        target.attach(draw_buffers.back(), *colour);
    }
    glNamedFramebufferDrawBuffers(target.id(), GLsizei(draw_buffers.size()), draw_buffers.data());
    target.attach(GL_DEPTH_ATTACHMENT, depth);
    target.check_complete(what);
    return target;
}

// A fraction target before its pass: fraction 1 and alpha 0 (no object), no normal, no sun (share 0, V 1;
// a target without the sun's attachment ignores it), the far depth.
void clear_fraction_target(const gl::Framebuffer& target) {
    const float lit_nothing[4] = {1.0f, 1.0f, 1.0f, 0.0f};
    const float no_normal[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    const float no_sun[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    const float clear_depth = 1.0f;
    glDepthMask(GL_TRUE);
    glClearNamedFramebufferfv(target.id(), GL_COLOR, 0, lit_nothing);
    glClearNamedFramebufferfv(target.id(), GL_COLOR, 1, no_normal);
    glClearNamedFramebufferfv(target.id(), GL_COLOR, 2, no_sun);
    glClearNamedFramebufferfv(target.id(), GL_DEPTH, 0, &clear_depth);
}

}  // namespace

Renderer::Renderer(const RenderSettings& settings) : settings_(settings), library_(embedded_shaders()) {
    validate(settings_);
    glGetIntegerv(GL_MAX_VIEWPORTS, &max_viewports_);
    GLint max_block = 0;
    glGetIntegerv(GL_MAX_UNIFORM_BLOCK_SIZE, &max_block);
    support_.uniform_block_fits = std::size_t(max_block) >= std::size_t(size::max_lights) * sizeof(LightRecord);
    support_.viewport_layer_array = GLAD_GL_ARB_shader_viewport_layer_array;
    max_viewports_ = std::clamp(max_viewports_, 1, kMaxViewports);
    GLint color_samples = 1, depth_samples = 1, samples = 1;
    glGetIntegerv(GL_MAX_COLOR_TEXTURE_SAMPLES, &color_samples);
    glGetIntegerv(GL_MAX_DEPTH_TEXTURE_SAMPLES, &depth_samples);
    glGetIntegerv(GL_MAX_SAMPLES, &samples);
    max_samples_ = std::max(1, std::min({color_samples, depth_samples, samples}));
    samples_ = drawn_samples();
    empty_vertex_array_ = gl::VertexArray::create();
    // The atlas read as depths: the shading compares them with the receiver's plane itself (plane_pcf,
    // docs/DESIGN.md §5.3) and the soft shadows search them for blockers (§5.9).
    atlas_depth_sampler_ = gl::Sampler::create(
        {.min_filter = GL_NEAREST, .mag_filter = GL_NEAREST, .wrap_s = GL_CLAMP_TO_EDGE, .wrap_t = GL_CLAMP_TO_EDGE});
    // Room for every record the shaders may index: a uniform block's bound range must cover its
    // whole declared array (MAX_LIGHTS). Made once: set_lights() and render() only upload.
    light_buffer_ = gl::Buffer::create(std::size_t(size::max_lights) * sizeof(LightRecord));
    // shade.vert's gl_Position is invariant: the shading pass's depths equal the pre-pass's.
    prepass_program_ = library_.build({{GL_VERTEX_SHADER, "shade.vert"}, {GL_FRAGMENT_SHADER, "depth_prepass.frag"}});
    background_program_ =
        library_.build({{GL_VERTEX_SHADER, "background.vert"}, {GL_FRAGMENT_SHADER, "background.frag"}});
    fraction_filter_program_ =
        library_.build({{GL_VERTEX_SHADER, "present.vert"}, {GL_FRAGMENT_SHADER, "fraction_filter.frag"}});
    select_programs();
}

Renderer::~Renderer() = default;

void Renderer::select_programs() {
    variant_ = render::shader_variant(settings_, support_);
    variant_.translucent_shadows = translucent_casters_;
    auto it = programs_.find(variant_);
    if (it == programs_.end()) {
        if (variant_.atlas != settings_.atlas)
            log::warn("GL_ARB_shader_viewport_layer_array is missing: drawing the shadow atlas with clip distances");
        VariantPrograms programs;
        programs.atlas = library_.build({{GL_VERTEX_SHADER, "shadow_atlas.vert"}}, atlas_defines(variant_));
        const std::vector<gl::ShaderStage> shade_stages = {{GL_VERTEX_SHADER, "shade.vert"},
                                                           {GL_FRAGMENT_SHADER, "shade.frag"}};
        std::vector<std::string> defines = shade_defines(variant_);
        programs.shade = library_.build(shade_stages, defines);
        defines.push_back("DIFFUSE_ONLY");
        programs.shade_diffuse = library_.build(shade_stages, defines);
        defines.push_back("FLAT_RECEIVER");
        programs.shade_flat = library_.build(shade_stages, defines);
        it = programs_.emplace(variant_, std::move(programs)).first;
    }
    programs_now_ = &it->second;
}

// shadow_tiles.comp for the samples drawn now, built once per sample count: the viewer drops to one
// sample while the view moves (docs/DESIGN.md §5.10) and changes back without a compile.
const gl::Program& Renderer::tiles_program(int samples) {
    auto [it, added] = tiles_programs_.try_emplace(std::pair(variant_.lights_uniform_block, samples));
    if (added) {
        std::vector<std::string> defines;
        if (variant_.lights_uniform_block) defines.push_back("LIGHTS_UNIFORM_BLOCK");
        if (samples > 1) defines.push_back("DEPTH_SAMPLES " + std::to_string(samples));  // a sampler2DMS
        it->second = library_.build({{GL_COMPUTE_SHADER, "shadow_tiles.comp"}}, defines);
    }
    return it->second;
}

// The shading with the fraction pass's output: no shadows, so of the variant's key only the alpha test
// matters, and for glTF's BRDF how it reads the lights (its compact lights' correction); with the sun per
// pixel, which looks the sun's shadow up, the whole variant.
const gl::Program& Renderer::fraction_shading_program(bool metallic_roughness) {
    if (variant_.sun_per_pixel) {  // it looks the sun's shadow up: the variant's visibility, per variant
        gl::Program& program = metallic_roughness ? programs_now_->shade_sun_gltf : programs_now_->shade_sun;
        if (!program) {
            std::vector<std::string> defines = shade_defines(variant_);
            defines.push_back("SHADOWED_FRACTION_IN");
            if (metallic_roughness) defines.push_back("METALLIC_ROUGHNESS");
            program = library_.build({{GL_VERTEX_SHADER, "shade.vert"}, {GL_FRAGMENT_SHADER, "shade.frag"}}, defines);
        }
        return program;
    }
    const bool lights_block = metallic_roughness && variant_.lights_uniform_block;
    gl::Program& program = fraction_shading_programs_[{metallic_roughness, variant_.alpha_test, lights_block}];
    if (!program) {
        std::vector<std::string> defines = {"SHADOWED_FRACTION_IN"};
        if (metallic_roughness) defines.insert(defines.end(), {"METALLIC_ROUGHNESS", "SHADING_RATIO"});
        if (lights_block) defines.push_back("LIGHTS_UNIFORM_BLOCK");
        if (variant_.alpha_test) defines.push_back("ALPHA_TEST");
        program = library_.build({{GL_VERTEX_SHADER, "shade.vert"}, {GL_FRAGMENT_SHADER, "shade.frag"}}, defines);
    }
    return program;
}

void Renderer::set_settings(const RenderSettings& settings) {
    validate(settings);
    const RenderSettings old = settings_;
    settings_ = settings;
    samples_ = drawn_samples();  // only the screen-tile program depends on it: tiles_program()
    select_programs();
    if (changes(SettingEffect::lights, old, settings_)) select_lights();
}

void Renderer::set_scene(const Scene& scene, const std::function<void(std::size_t done, std::size_t total)>& progress) {
    std::size_t total = 0, done = 0;  // triangles of the meshes to upload, and of those uploaded
    {
        std::set<const Mesh*> seen;
        for (const Object& object : scene.objects)
            if (object.mesh && seen.insert(object.mesh.get()).second) total += object.mesh->triangle_count();
    }
    meshes_.clear();
    deforming_.clear();
    instance_meshes_.clear();
    instance_of_object_.clear();
    textures_.clear();
    instance_textures_.clear();
    instance_emission_textures_.clear();
    instance_occlusion_textures_.clear();
    instance_metallic_roughness_textures_.clear();
    instance_normal_textures_.clear();
    instance_front_only_.clear();
    if (!white_texture_) white_texture_ = white_texture();
    std::vector<PlannedObject> planned;
    std::map<const Mesh*, const GpuMesh*> uploaded;
    // One upload per image and sampler state.
    std::map<std::tuple<const TextureImage*, TextureWrap, TextureWrap, bool, bool>, const gl::Texture*>
        uploaded_textures;
    for (const Object& object : scene.objects) {
        instance_of_object_.push_back(-1);
        if (!object.mesh || object.mesh->indices.empty()) continue;
        instance_of_object_.back() = int(instance_meshes_.size());
        if (object.deforms()) {  // glTF skins and morphs: a mesh of its own, posed every frame (render())
            meshes_.push_back(std::make_unique<GpuMesh>(*object.mesh, GpuMesh::Deforming{}));
            deforming_.push_back({instance_meshes_.size(), meshes_.back().get(), object});
            done += object.mesh->triangle_count();
            if (progress) progress(done, total);
        }
        auto [it, added] =
            object.deforms() ? std::pair{uploaded.end(), false} : uploaded.emplace(object.mesh.get(), nullptr);
        if (added) {
            const std::size_t triangles = object.mesh->triangle_count();
            std::function<void(double)> mesh_progress;
            if (progress)
                mesh_progress = [&](double fraction) {
                    progress(done + std::size_t(fraction * double(triangles)), total);
                };
            meshes_.push_back(std::make_unique<GpuMesh>(*object.mesh, mesh_progress));
            it->second = meshes_.back().get();
            done += triangles;
        }
        const GpuMesh& mesh = object.deforms() ? *deforming_.back().mesh : *it->second;
        instance_meshes_.push_back(&mesh);
        // The material's texture, uploaded once per image and sampler state; white without one.
        const auto texture = [&](const std::optional<MaterialTexture>& t) -> const gl::Texture* {
            if (!t || object.mesh->texcoords.empty()) return &white_texture_;
            auto [tex, new_texture] = uploaded_textures.emplace(
                std::tuple(t->image.get(), t->wrap_s, t->wrap_t, t->nearest, t->srgb), nullptr);
            if (new_texture) {
                textures_.push_back(std::make_unique<gl::Texture>(upload_material_texture(*t)));
                tex->second = textures_.back().get();
            }
            return tex->second;
        };
        instance_textures_.push_back(texture(object.material.base_color_texture));
        instance_emission_textures_.push_back(texture(object.material.emission_texture));
        instance_occlusion_textures_.push_back(texture(object.material.occlusion_texture));
        instance_metallic_roughness_textures_.push_back(texture(object.material.metallic_roughness_texture));
        instance_normal_textures_.push_back(object.mesh->tangents.empty() ? &white_texture_
                                                                          : texture(object.material.normal_texture));
        instance_front_only_.push_back(!object.material.double_sided && mesh.caster_lod().levels[0].closed);
        PlannedObject& object_plan = planned.emplace_back();
        object_plan.object = object;
        object_plan.object.mesh.reset();  // the GPU copy is enough
        object_plan.bounds_min = mesh.bounds_min();
        object_plan.bounds_max = mesh.bounds_max();
        object_plan.flat_normal = mesh.flat_normal();
    }
    planner_.set_objects(std::move(planned));
    ++content_version_;  // the shadow cache's layers hold the old scene's casters
    has_ground_ = scene.has_ground;
    rotation_degrees_ = scene.environment.rotation_degrees;
    select_lights();
}

namespace {

// Whether two materials give their caster the same depths in the opaque atlas: drawn there or not (blended
// casters go to the translucent layer), and cut out alike.
bool casts_alike(const Material& a, const Material& b) {
    return a.masked() == b.masked() && a.blended() == b.blended() &&
           (!a.masked() || (a.alpha_cutoff == b.alpha_cutoff && a.base_alpha == b.base_alpha));
}

}  // namespace

void Renderer::set_material(std::size_t object, const Material& material) {
    if (object >= instance_of_object_.size() || instance_of_object_[object] < 0) return;
    const auto instance = std::size_t(instance_of_object_[object]);
    const Material& old = planner_.objects()[instance].object.material;
    if (!casts_alike(old, material)) ++content_version_;  // the shadow cache holds the caster as it was cut
    if ((old.blended() || material.blended()) && old.base_alpha != material.base_alpha)
        ++translucent_version_;  // the translucent layer holds its transmittance
    planner_.set_material(instance, material);
}

namespace {

// An RGB32F (glm::vec3 texels) or RGBA32F (glm::vec4) table, bilinear, clamped in v. A prefiltered level repeats
// in u (lat-long, as the map: u wraps, v stops at the poles); the DFG table clamps in both (texel centres at
// (i + 0.5) / size, as DfgTable::lookup).
template <typename Texel>
gl::Texture upload_float_texels(int width, int height, const Texel* texels, GLenum wrap_s = GL_REPEAT) {
    constexpr bool rgba = Texel::length() == 4;
    gl::Texture texture = gl::Texture::create_2d(rgba ? GL_RGBA32F : GL_RGB32F, width, height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage2D(texture.id(), 0, 0, 0, width, height, rgba ? GL_RGBA : GL_RGB, GL_FLOAT, texels);
    texture.set_filter(GL_LINEAR, GL_LINEAR);
    texture.set_wrap(wrap_s, GL_CLAMP_TO_EDGE);
    return texture;
}

// Texels of the split sum's DFG table: 32 x 32 keeps its bilinear lookup within 2e-3 of the integrals.
constexpr int kDfgTableSize = 32;

}  // namespace

void Renderer::set_environment(const EnvironmentMap& map) {
    environment_ = upload_float_texels(map.width, map.height, map.texels.data());  // u wraps around the sphere
}

void Renderer::set_prefiltered(const PrefilteredEnvironment& prefiltered) {
    prefiltered_.clear();
    prefiltered_levels_ = {};
    for (const PrefilteredLevel& level : prefiltered.levels) {
        prefiltered_.push_back(upload_float_texels(level.width, level.height, level.texels.data()));
        PrefilteredLevel& kept = prefiltered_levels_.levels.emplace_back();
        kept.shininess = level.shininess;
        kept.width = level.width;
        kept.height = level.height;
    }
}

void Renderer::set_ggx_prefiltered(const GgxPrefilteredEnvironment& prefiltered, const CompactSourceSplit& split) {
    if (prefiltered.levels.size() != std::size_t(kGgxPrefilterLevels))
        throw std::invalid_argument("renderer: " + std::to_string(prefiltered.levels.size()) + " GGX levels given, " +
                                    std::to_string(kGgxPrefilterLevels) + " expected");
    // The levels one above the other in one texture, so that each pixel reads those about its own roughness
    // (glsl/shade_ratio.glsl ggx_level): level k's rows from ggx_level_rows_[k].x, each with a copy of its last
    // texel before it and of its first after it, for GL_LINEAR to wrap in u.
    ggx_hemisphere_ = prefiltered.hemisphere;
    int width = 0, height = 0;
    for (std::size_t k = 0; k < prefiltered.levels.size(); ++k) {
        const GgxPrefilteredLevel& level = prefiltered.levels[k];
        ggx_level_rows_[k] = {height, level.width, level.height};
        width = std::max(width, level.width + 2);
        height += level.height;
    }
    ggx_level_texels_ = gl::Texture::create_2d(GL_RGB32F, width, height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    std::vector<glm::vec3> wrapped;
    for (std::size_t k = 0; k < prefiltered.levels.size(); ++k) {
        const GgxPrefilteredLevel& level = prefiltered.levels[k];
        const auto w = std::size_t(level.width);
        wrapped.resize((w + 2) * std::size_t(level.height));
        for (std::size_t j = 0; j < std::size_t(level.height); ++j) {
            const glm::vec3* row = level.texels.data() + j * w;
            glm::vec3* out = wrapped.data() + j * (w + 2);
            out[0] = row[w - 1];
            std::copy(row, row + w, out + 1);
            out[w + 1] = row[0];
        }
        glTextureSubImage2D(ggx_level_texels_.id(), 0, 0, ggx_level_rows_[k].x, level.width + 2, level.height, GL_RGB,
                            GL_FLOAT, wrapped.data());
    }
    ggx_level_texels_.set_filter(GL_LINEAR, GL_LINEAR);
    ggx_level_texels_.set_wrap(GL_CLAMP_TO_EDGE, GL_CLAMP_TO_EDGE);  // never reached: each level's rows wrap
    // The split sum's mirror: the map without its sources; a map without any is its own (environment_).
    ggx_mirror_ = split.sources.empty()
                      ? gl::Texture{}
                      : upload_float_texels(split.rest.width, split.rest.height, split.rest.texels.data());
    compact_sources_ = split.sources;
    if (!dfg_) {
        const DfgTable table = compute_dfg_table(kDfgTableSize);
        dfg_ = upload_float_texels(table.size, table.size, table.texels.data(), GL_CLAMP_TO_EDGE);
    }
}

void Renderer::set_environment_rotation(float degrees) {
    rotation_degrees_ = degrees;
    select_lights();
}

void Renderer::set_lights(std::vector<Cell> cells, CellSpace space, LightLifetime lifetime) {
    if (cells.size() > std::size_t(kMaxLights))  // the light buffer, the atlas and MAX_LIGHTS hold that many
        throw std::invalid_argument("renderer: " + std::to_string(cells.size()) + " lights given, at most " +
                                    std::to_string(kMaxLights) + " fit");
    cells_ = std::move(cells);
    cell_space_ = space;
    light_lifetime_ = lifetime;
    select_lights();
}

void Renderer::select_lights() {
    const glm::mat3 rotation = cell_space_ == CellSpace::map ? world_from_map(rotation_degrees_) : glm::mat3(1.0f);
    lights_ = render::select_lights(cells_, rotation, has_ground_, settings_.skip_lights);
    planner_.set_lights(lights_.kept);
    layout_stale_ = true;  // the tile count, and sized tiles' sizes, follow the lights
}

void Renderer::ensure_atlas() {
    // Per-frame lights keep uniform tiles: sized ones would change size (and the atlas its shape)
    // from frame to frame.
    const TileSizing sizing =
        light_lifetime_ == LightLifetime::every_frame ? TileSizing::uniform : settings_.tile_sizing;
    // Uniform tiles depend on the count alone; sized ones on every light's luminance.
    const bool same_lights =
        !layout_stale_ || (sizing == TileSizing::uniform && layout_.tile_count == std::max(light_count(), 1));
    if (atlas_depth_ && same_lights && layout_.requested_tile_size == settings_.tile_size && layout_.sizing == sizing &&
        atlas_depth_bits_ == settings_.depth_bits)
        return;
    GLint max_texture = 0, max_viewport[2] = {0, 0};
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_texture);
    glGetIntegerv(GL_MAX_VIEWPORT_DIMS, max_viewport);
    luminance_.clear();
    for (const WorldLight& light : lights_.kept) luminance_.push_back(latlong::luminance(glm::dvec3(light.radiance)));
    const int old_width = layout_.width(), old_height = layout_.height();
    layout_ =
        plan_atlas(luminance_, sizing, settings_.tile_size, std::min({max_texture, max_viewport[0], max_viewport[1]}));
    layout_stale_ = false;
    if (atlas_depth_ && old_width == layout_.width() && old_height == layout_.height() &&
        atlas_depth_bits_ == settings_.depth_bits)
        return;  // the same texture holds the new tiles
    if (layout_.tile_size != layout_.requested_tile_size)
        log::warn("shadow atlas: " + std::to_string(layout_.tile_count) + " tiles of " +
                  std::to_string(settings_.tile_size) + "^2 exceed the GL limit; using " +
                  std::to_string(layout_.tile_size) + "^2 tiles" +
                  (sizing == TileSizing::uniform ? "" : " (the budget of the sized tiles)"));
    atlas_depth_bits_ = settings_.depth_bits;
    ++content_version_;  // a new atlas holds no depths yet
    atlas_depth_ = gl::Texture::create_2d(settings_.depth_bits == 16 ? GL_DEPTH_COMPONENT16 : GL_DEPTH_COMPONENT32F,
                                          layout_.width(), layout_.height());
    atlas_ = gl::Framebuffer::create();
    atlas_.attach(GL_DEPTH_ATTACHMENT, atlas_depth_);
    atlas_transmittance_ = {};  // ensure_translucent_layer attaches the new depths
    glNamedFramebufferDrawBuffer(atlas_.id(), GL_NONE);
    glNamedFramebufferReadBuffer(atlas_.id(), GL_NONE);
    atlas_.check_complete("shadow atlas");
}

int Renderer::drawn_samples() const {
    if (settings_.msaa > max_samples_ && !warned_samples_) {
        log::warn("MSAA: " + std::to_string(settings_.msaa) + " samples asked for, the driver's maximum is " +
                  std::to_string(max_samples_) + "; using " + std::to_string(max_samples_));
        warned_samples_ = true;
    }
    return std::min(settings_.msaa, max_samples_);
}

namespace {

// The framebuffer's sample positions in the pixel ([0, 1]^2; GL's positions are implementation-defined).
std::vector<glm::vec2> query_sample_positions(const gl::Framebuffer& framebuffer, int samples) {
    std::vector<glm::vec2> positions(std::size_t(std::max(samples, 0)));
    framebuffer.bind();
    for (int k = 0; k < samples; ++k) glGetMultisamplefv(GL_SAMPLE_POSITION, GLuint(k), &positions[std::size_t(k)].x);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return positions;
}

// Which of the pixel's quarters each sample position lies in; a quarter holding none takes the bit of the
// sample nearest its centre, so that a fragment covering that sample covers it.
std::array<GLuint, 4> sample_quarters(std::span<const glm::vec2> positions) {
    const int count = std::min(int(positions.size()), 32);
    std::array<GLuint, 4> masks{};
    for (int k = 0; k < count; ++k) {
        const glm::vec2 p = positions[std::size_t(k)];
        masks[std::size_t((p.x >= 0.5f ? 1 : 0) + (p.y >= 0.5f ? 2 : 0))] |= 1u << k;
    }
    for (int q = 0; q < 4; ++q) {
        if (masks[std::size_t(q)] != 0) continue;
        const glm::vec2 centre(0.25f + 0.5f * float(q & 1), 0.25f + 0.5f * float(q >> 1));
        int nearest = 0;
        for (int k = 1; k < count; ++k)
            if (glm::length(positions[std::size_t(k)] - centre) < glm::length(positions[std::size_t(nearest)] - centre))
                nearest = k;
        masks[std::size_t(q)] = 1u << nearest;
    }
    return masks;
}

// A render target's name in errors: what it is, its size and samples.
std::string target_name(int width, int height, int samples, const char* what) {
    return std::string(what) + " of " + std::to_string(width) + "x" + std::to_string(height) +
           (samples > 1 ? " at " + std::to_string(samples) + " samples" : "");
}

}  // namespace

void Renderer::ensure_target(int width, int height) {
    if (color_ && color_.width() == width && color_.height() == height && depth_.samples() == samples_) return;
    color_ = gl::Texture::create_2d(GL_RGBA32F, width, height);
    target_ = gl::Framebuffer::create();
    if (samples_ > 1) {
        multisample_color_ = gl::Texture::create_2d_multisample(GL_RGBA32F, width, height, samples_);
        depth_ = gl::Texture::create_2d_multisample(GL_DEPTH_COMPONENT32F, width, height, samples_);
        target_.attach(GL_COLOR_ATTACHMENT0, multisample_color_);
        resolved_ = gl::Framebuffer::create();
        resolved_.attach(GL_COLOR_ATTACHMENT0, color_);
        resolved_.check_complete(target_name(width, height, 1, "resolved render target"));
    } else {
        multisample_color_ = {};
        resolved_ = {};
        depth_ = gl::Texture::create_2d(GL_DEPTH_COMPONENT32F, width, height);
        depth_.set_filter(GL_NEAREST, GL_NEAREST);  // read by shadow_tiles.comp
        target_.attach(GL_COLOR_ATTACHMENT0, color_);
    }
    screen_tiles_ = glm::ivec2((width + size::screen_tile - 1) / size::screen_tile,
                               (height + size::screen_tile - 1) / size::screen_tile);
    tile_lists_ = gl::Buffer::create(std::size_t(screen_tiles_.x) * std::size_t(screen_tiles_.y) *
                                     std::size_t(size::max_lights + 1) * sizeof(std::uint32_t));
    target_.attach(GL_DEPTH_ATTACHMENT, depth_);
    target_.check_complete(target_name(width, height, samples_, "render target"));
    // At one sample that sample stands for the whole pixel, and sits at its centre.
    const std::vector<glm::vec2> positions =
        samples_ > 1 ? query_sample_positions(target_, samples_) : std::vector<glm::vec2>{glm::vec2(0.5f)};
    sample_quarters_ = samples_ > 1 ? sample_quarters(positions) : std::array<GLuint, 4>{1, 1, 1, 1};
    sample_margin_ = sample_margin(positions);
}

Renderer::FractionTarget Renderer::FractionTarget::create(int width, int height, bool sun, const char* what) {
    FractionTarget target;
    target.fraction = gl::Texture::create_2d(GL_RGBA32F, width, height);
    target.normal = gl::Texture::create_2d(GL_RGBA16F, width, height);
    target.depth = gl::Texture::create_2d(GL_DEPTH_COMPONENT32F, width, height);  // read by shadow_tiles.comp
    for (gl::Texture* t : {&target.fraction, &target.normal, &target.depth}) t->set_filter(GL_NEAREST, GL_NEAREST);
    if (!sun) {
        target.framebuffer = colour_target({&target.fraction, &target.normal}, target.depth, what);
        return target;
    }
    target.sun = gl::Texture::create_2d(GL_RGBA16F, width, height);
    target.sun.set_filter(GL_NEAREST, GL_NEAREST);
    target.framebuffer = colour_target({&target.fraction, &target.normal, &target.sun}, target.depth, what);
    return target;
}

void Renderer::ensure_fraction_target(int width, int height) {
    if (settings_.shadow_rate == ShadowRate::adaptive && !refined_.fits(width, height, false))
        refined_ = FractionTarget::create(width, height, false, "refined-fraction target");
    const int divisor = settings_.shadow_rate == ShadowRate::pixel ? 1 : 2;
    width = (width + divisor - 1) / divisor;
    height = (height + divisor - 1) / divisor;
    if (!fraction_.fits(width, height, variant_.sun_per_pixel)) {
        fraction_ = FractionTarget::create(width, height, variant_.sun_per_pixel, "shadowed-fraction target");
        fraction_tiles_ = glm::ivec2((width + size::screen_tile - 1) / size::screen_tile,
                                     (height + size::screen_tile - 1) / size::screen_tile);
        fraction_tile_lists_ = gl::Buffer::create(std::size_t(fraction_tiles_.x) * std::size_t(fraction_tiles_.y) *
                                                  std::size_t(size::max_lights + 1) * sizeof(std::uint32_t));
    }
    const bool filtered_fits =
        fraction_filtered_ && fraction_filtered_.width() == width && fraction_filtered_.height() == height;
    if (!settings_.fraction_filter || filtered_fits) return;
    fraction_filtered_ = gl::Texture::create_2d(GL_RGBA32F, width, height);
    fraction_filtered_.set_filter(GL_NEAREST, GL_NEAREST);
    fraction_filter_target_ = gl::Framebuffer::create();
    fraction_filter_target_.attach(GL_COLOR_ATTACHMENT0, fraction_filtered_);
    fraction_filter_target_.check_complete("filtered-fraction target");
}

void Renderer::upload(const FramePlan& plan) {
    caster_rect_buffer_.upload_resizing(plan.caster_rects.data(), plan.caster_rects.size() * sizeof(glm::vec4));
    light_buffer_.upload(plan.lights.data(), plan.lights.size() * sizeof(LightRecord));
    sun_cell_ = sun_light(plan.lights);
}

void Renderer::draw_atlas(const FramePlan& plan, FrameStats& stats) {
    draw_opaque_atlas(plan, stats);
    if (!variant_.translucent_shadows) return;
    // Its depth test reads the opaque layer: kept while that is kept whole (nothing moves) and no blended
    // caster's alpha changed.
    ensure_translucent_layer();
    std::optional<TranslucentKey> key;
    if (atlas_holds_static_) key = TranslucentKey{*atlas_holds_static_, translucent_version_};
    if (key && translucent_holds_ == key) return;
    gl::ScopedPass pass(&timer_, "translucent atlas");
    draw_casters(
        plan, [](std::size_t) { return true; }, AtlasStart::cleared, CasterLayer::translucent);
    translucent_holds_ = key;
}

void Renderer::ensure_translucent_layer() {
    if (atlas_transmittance_ && atlas_transmittance_.width() == atlas_depth_.width() &&
        atlas_transmittance_.height() == atlas_depth_.height())
        return;
    translucent_holds_.reset();  // new textures hold nothing yet
    atlas_transmittance_ = gl::Texture::create_2d(GL_R8, atlas_depth_.width(), atlas_depth_.height());
    atlas_translucent_depth_ = gl::Texture::create_2d(GL_R16, atlas_depth_.width(), atlas_depth_.height());
    for (gl::Texture* t : {&atlas_transmittance_, &atlas_translucent_depth_}) t->set_filter(GL_NEAREST, GL_NEAREST);
    atlas_translucent_ =
        colour_target({&atlas_transmittance_, &atlas_translucent_depth_}, atlas_depth_, "translucent shadow layer");
}

void Renderer::draw_opaque_atlas(const FramePlan& plan, FrameStats& stats) {
    const auto moves = [&](std::size_t i) { return planner_.objects()[i].object.moves(); };
    const auto every = [](std::size_t) { return true; };
    atlas_triangles_ = 0;
    int moving = 0;
    for (std::size_t i = 0; i < plan.objects.size(); ++i) moving += plan.objects[i].casts_shadows && moves(i);
    const AtlasKey key{plan.fit_version,
                       content_version_,
                       settings_.caster_lod,
                       settings_.caster_lod_per_tile,
                       settings_.cull_back_faces,
                       settings_.base_color_texture,
                       variant_.atlas};
    const std::optional<AtlasKey> last = std::exchange(last_key_, key);
    if (!settings_.shadow_cache || plan.lights.empty()) {
        atlas_holds_static_.reset();
        static_layer_holds_.reset();
        static_depth_ = {};
        gl::ScopedPass pass(&timer_, "shadow atlas");
        draw_casters(plan, every, AtlasStart::cleared);
        stats.atlas_passes = 1;
        return;
    }
    if (moving == 0) {
        if (atlas_holds_static_ == key) return;  // the depths of the last frame are this frame's
        gl::ScopedPass pass(&timer_, "shadow atlas");
        draw_casters(plan, every, AtlasStart::cleared);
        atlas_holds_static_ = key;
        stats.atlas_passes = 1;
        return;
    }
    atlas_holds_static_.reset();  // the moving casters go into the atlas
    gl::ScopedPass pass(&timer_, "shadow atlas");
    stats.atlas_passes = 1;
    if (static_layer_holds_ != key) {
        if (last != key) {  // fits that changed since the last frame may change again: no layer kept yet
            draw_casters(plan, every, AtlasStart::cleared);
            return;
        }
        draw_casters(plan, std::not_fn(moves), AtlasStart::cleared);
        if (!static_depth_ || static_depth_.width() != atlas_depth_.width() ||
            static_depth_.height() != atlas_depth_.height() || static_depth_.format() != atlas_depth_.format())
            static_depth_ = gl::Texture::create_2d(atlas_depth_.format(), atlas_depth_.width(), atlas_depth_.height());
        glCopyImageSubData(atlas_depth_.id(), GL_TEXTURE_2D, 0, 0, 0, 0, static_depth_.id(), GL_TEXTURE_2D, 0, 0, 0, 0,
                           atlas_depth_.width(), atlas_depth_.height(), 1);
        static_layer_holds_ = key;
        stats.static_layer_renders = 1;
    } else {
        glCopyImageSubData(static_depth_.id(), GL_TEXTURE_2D, 0, 0, 0, 0, atlas_depth_.id(), GL_TEXTURE_2D, 0, 0, 0, 0,
                           atlas_depth_.width(), atlas_depth_.height(), 1);
    }
    draw_casters(plan, moves, AtlasStart::as_it_is);
    stats.moving_casters_drawn = moving;
}

void Renderer::draw_casters(const FramePlan& plan, const std::function<bool(std::size_t)>& which, AtlasStart start,
                            CasterLayer layer) {
    const bool translucent = layer == CasterLayer::translucent;
    const float far_depth = 1.0f;
    if (translucent) {
        // Over the opaque casters' depths, writing none: the blended casters' transmittance (a product, cleared
        // to 1) and their nearest depth (a minimum, cleared to 1), both faces of each (a closed blended object
        // passes light through two surfaces).
        glBindFramebuffer(GL_FRAMEBUFFER, atlas_translucent_.id());
        const float nothing[4] = {1.0f, 1.0f, 1.0f, 1.0f};
        glClearNamedFramebufferfv(atlas_translucent_.id(), GL_COLOR, 0, nothing);
        glClearNamedFramebufferfv(atlas_translucent_.id(), GL_COLOR, 1, nothing);
    } else {
        glBindFramebuffer(GL_FRAMEBUFFER, atlas_.id());
        glDepthMask(GL_TRUE);
        if (start == AtlasStart::cleared) glClearNamedFramebufferfv(atlas_.id(), GL_DEPTH, 0, &far_depth);
    }
    if (plan.lights.empty()) return;
    if (translucent) {
        glDepthMask(GL_FALSE);
        glEnable(GL_BLEND);
        glBlendFunci(0, GL_ZERO, GL_ONE_MINUS_SRC_COLOR);
        glBlendEquationi(1, GL_MIN);
    }
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_CULL_FACE);  // both faces cast: open meshes and thin parts stay in the map
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(0.0f, 1.0f);  // the map's depth precision; the rest of the bias is the receiver's (§5.3)
    VariantPrograms& programs = *programs_now_;
    const auto build_alpha_program = [&](gl::Program& program, const char* fragment) {
        if (program) return;
        std::vector<std::string> defines = atlas_defines(variant_);
        defines.push_back("ALPHA_MASK");
        program = library_.build({{GL_VERTEX_SHADER, "shadow_atlas.vert"}, {GL_FRAGMENT_SHADER, fragment}}, defines);
    };
    if (translucent) build_alpha_program(programs.atlas_translucent, "shadow_atlas_translucent.frag");
    if (!translucent && std::ranges::any_of(plan.objects, &ObjectFrame::masked))
        build_alpha_program(programs.atlas_masked, "shadow_atlas_mask.frag");
    // Masked casters cut out what their alpha cuts (shadow_atlas_mask.frag), blended ones weigh their light by it
    // (shadow_atlas_translucent.frag), both at level 0: the simplified levels carry no texture coordinates.
    const auto caster_program = [&](std::size_t i) -> const gl::Program& {
        return translucent                ? programs.atlas_translucent
               : plan.objects[i].masked() ? programs.atlas_masked
                                          : programs.atlas;
    };
    const auto set_first_tile = [&](GLint first) {
        for (const gl::Program* p : {&programs.atlas, &programs.atlas_masked, &programs.atlas_translucent})
            if (*p) glProgramUniform1i(p->id(), loc::first_tile, first);
    };
    const int tiles = int(plan.lights.size());

    // Each caster at the coarsest level of detail within settings_.caster_lod of the texels it is drawn
    // into: each tile's own (caster_lod_per_tile), else the frame's smallest (level 0, the full mesh,
    // with caster_lod = 0).
    const std::span<const float> texel_world(plan.texel_world);
    const auto texels_of = [&](int first, int count, std::vector<float>& texels) {
        texels.assign(texel_world.begin() + first, texel_world.begin() + first + count);
        if (!settings_.caster_lod_per_tile) std::fill(texels.begin(), texels.end(), plan.min_texel_world);
    };
    const auto set_caster = [&](std::size_t i, int level) {
        const ObjectFrame& object = plan.objects[i];
        const GpuMesh& mesh = *instance_meshes_[i];
        const gl::Program& program = caster_program(i);
        program.use();
        glProgramUniformMatrix4fv(program.id(), loc::world_from_object, 1, GL_FALSE, &object.world_from_object[0][0]);
        if (object.alpha_in_atlas()) bind_alpha_mask(program.id(), object, i);
        // Closed casters: front faces only (the light frame keeps the winding: right x up = toward,
        // so faces turned to the light are counter-clockwise in the tile; a mirroring transform
        // turns them clockwise).
        if (settings_.cull_back_faces && !translucent && mesh.caster_lod().levels[std::size_t(level)].closed) {
            glEnable(GL_CULL_FACE);
            glCullFace(GL_BACK);
            glFrontFace(glm::determinant(glm::mat3(object.world_from_object)) < 0.0f ? GL_CW : GL_CCW);
        } else {
            glDisable(GL_CULL_FACE);
        }
        mesh.bind_caster(level);
    };
    const auto draws_caster = [&](std::size_t i) {
        return plan.objects[i].casts_shadows && plan.objects[i].blended == translucent && which(i);
    };
    std::vector<float> texels;
    // Tiles first .. first + count - 1 of every caster, each caster's tiles grouped by level: the runs
    // of caster i are caster_tiles_.runs[run_begin[i] .. run_begin[i + 1]).
    std::vector<std::size_t> run_begin(instance_meshes_.size() + 1, 0);
    auto group_tiles = [&](int first, int count) {
        caster_tiles_.tiles.clear();
        caster_tiles_.runs.clear();
        texels_of(first, count, texels);
        for (std::size_t i = 0; i < instance_meshes_.size(); ++i) {
            run_begin[i] = caster_tiles_.runs.size();
            if (!draws_caster(i)) continue;
            const CasterLod& lod = instance_meshes_[i]->caster_lod();
            append_caster_tiles(lod, plan.objects[i].world_from_object, texels, settings_.caster_lod, caster_tiles_);
            if (plan.objects[i].alpha_in_atlas())
                for (std::size_t r = run_begin[i]; r < caster_tiles_.runs.size(); ++r) caster_tiles_.runs[r].level = 0;
            for (std::size_t r = run_begin[i]; r < caster_tiles_.runs.size(); ++r)
                atlas_triangles_ += std::size_t(lod.levels[std::size_t(caster_tiles_.runs[r].level)].index_count / 3) *
                                    std::size_t(caster_tiles_.runs[r].count);
        }
        run_begin.back() = caster_tiles_.runs.size();
    };
    switch (variant_.atlas) {
        case AtlasMode::clip_distances: {
            // One instanced draw per caster and level, its instances' tiles read from atlas_tile_buffer_.
            group_tiles(0, tiles);
            atlas_tile_buffer_.upload_resizing(
                caster_tiles_.tiles.data(),
                std::max<std::size_t>(caster_tiles_.tiles.size(), 1) * sizeof(std::int32_t));
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::atlas_tiles, atlas_tile_buffer_.id());
            for (GLenum plane = 0; plane < 4; ++plane) glEnable(GL_CLIP_DISTANCE0 + plane);
            glViewport(0, 0, layout_.width(), layout_.height());
            for (std::size_t i = 0; i < instance_meshes_.size(); ++i)
                for (std::size_t r = run_begin[i]; r < run_begin[i + 1]; ++r) {
                    const CasterTileRun& run = caster_tiles_.runs[r];
                    set_caster(i, run.level);
                    glProgramUniform1i(caster_program(i).id(), loc::first_tile, GLint(run.first));
                    instance_meshes_[i]->draw_caster(run.level, GLsizei(run.count));
                }
            for (GLenum plane = 0; plane < 4; ++plane) glDisable(GL_CLIP_DISTANCE0 + plane);
            break;
        }
        case AtlasMode::viewport_array:
            // Instance k of a batch goes to viewport k: one level per caster and batch, the finest its
            // tiles need.
            for (int first = 0; first < tiles; first += max_viewports_) {
                const int batch = std::min(max_viewports_, tiles - first);
                std::array<float, 4 * kMaxViewports> rects{};
                for (int i = 0; i < batch; ++i) {
                    const TileRect& tile = layout_.tiles[std::size_t(first + i)];
                    rects[4 * i + 0] = float(tile.x);
                    rects[4 * i + 1] = float(tile.y);
                    rects[4 * i + 2] = rects[4 * i + 3] = float(tile.size);
                }
                glViewportArrayv(0, batch, rects.data());
                set_first_tile(first);
                texels_of(first, batch, texels);
                const float smallest = *std::min_element(texels.begin(), texels.end());
                for (std::size_t i = 0; i < instance_meshes_.size(); ++i) {
                    if (!draws_caster(i)) continue;
                    const CasterLod& lod = instance_meshes_[i]->caster_lod();
                    const int level =
                        plan.objects[i].alpha_in_atlas()
                            ? 0
                            : choose_caster_level(lod, caster_error_budget(plan.objects[i].world_from_object, smallest,
                                                                           settings_.caster_lod));
                    atlas_triangles_ +=
                        std::size_t(lod.levels[std::size_t(level)].index_count / 3) * std::size_t(batch);
                    set_caster(i, level);
                    instance_meshes_[i]->draw_caster(level, batch);
                }
            }
            break;
        case AtlasMode::per_tile:
            for (int k = 0; k < tiles; ++k) {
                const TileRect& tile = layout_.tiles[std::size_t(k)];
                glViewport(tile.x, tile.y, tile.size, tile.size);
                set_first_tile(k);
                group_tiles(k, 1);
                for (std::size_t i = 0; i < instance_meshes_.size(); ++i)
                    for (std::size_t r = run_begin[i]; r < run_begin[i + 1]; ++r) {
                        set_caster(i, caster_tiles_.runs[r].level);
                        instance_meshes_[i]->draw_caster(caster_tiles_.runs[r].level);
                    }
            }
            break;
    }
    glDisable(GL_POLYGON_OFFSET_FILL);
    glDisable(GL_CULL_FACE);
    glFrontFace(GL_CCW);
    if (translucent) {
        glDisable(GL_BLEND);
        glBlendEquation(GL_FUNC_ADD);
        glBlendFunc(GL_ONE, GL_ZERO);
        glDepthMask(GL_TRUE);
    }
}

void Renderer::draw_depth_prepass(const FramePlan& plan, const CameraView& view, int samples, const char* pass_name) {
    gl::ScopedPass pass(&timer_, pass_name);
    const glm::mat4 clip_from_world = view.clip_from_view * view.view_from_world;
    const GLuint program = prepass_program_.id();
    prepass_program_.use();
    glProgramUniformMatrix4fv(program, loc::clip_from_world, 1, GL_FALSE, &clip_from_world[0][0]);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_CULL_FACE);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    const bool any_masked = std::ranges::any_of(plan.objects, &ObjectFrame::masked);
    if (any_masked && !masked_prepass_program_)
        masked_prepass_program_ = library_.build(
            {{GL_VERTEX_SHADER, "shade.vert"}, {GL_FRAGMENT_SHADER, "depth_prepass.frag"}}, {"ALPHA_MASK"});
    // Masked surfaces' cut edges anti-aliased within the pixel where it has samples to cover.
    const bool alpha_to_coverage = samples > 1;
    if (any_masked) {
        glProgramUniformMatrix4fv(masked_prepass_program_.id(), loc::clip_from_world, 1, GL_FALSE,
                                  &clip_from_world[0][0]);
        glProgramUniform1i(masked_prepass_program_.id(), loc::alpha_to_coverage, alpha_to_coverage ? 1 : 0);
    }
    for (const std::size_t i : opaque_objects_) {
        const ObjectFrame& object = plan.objects[i];
        const gl::Program& prepass = object.masked() ? masked_prepass_program_ : prepass_program_;
        prepass.use();
        glProgramUniformMatrix4fv(prepass.id(), loc::world_from_object, 1, GL_FALSE, &object.world_from_object[0][0]);
        if (object.masked()) bind_alpha_mask(prepass.id(), object, i);
        if (object.masked() && alpha_to_coverage) glEnable(GL_SAMPLE_ALPHA_TO_COVERAGE);
        set_sides(object, i);
        instance_meshes_[i]->bind();
        instance_meshes_[i]->draw();
        glDisable(GL_SAMPLE_ALPHA_TO_COVERAGE);
    }
    glDisable(GL_CULL_FACE);
    glFrontFace(GL_CCW);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
}

void Renderer::build_tile_lists(const FramePlan& plan, const CameraView& view, const gl::Texture& depth, int samples,
                                const gl::Buffer& lists, glm::ivec2 tiles_xy, const char* pass_name) {
    gl::ScopedPass pass(&timer_, pass_name);
    const glm::mat4 world_from_clip = glm::inverse(view.clip_from_view * view.view_from_world);
    const gl::Program& tiles = tiles_program(samples);
    const GLuint program = tiles.id();
    tiles.use();
    glProgramUniformMatrix4fv(program, loc::world_from_clip, 1, GL_FALSE, &world_from_clip[0][0]);
    glProgramUniform1i(program, loc::light_count, int(plan.lights.size()));
    glProgramUniform1f(program, loc::pad, plan.receiver_pad);
    glProgramUniform1i(program, loc::caster_count, plan.caster_rects_per_light);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::caster_rects, caster_rect_buffer_.id());
    depth.bind(unit::depth);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::tile_lists, lists.id());
    glDispatchCompute(GLuint(tiles_xy.x), GLuint(tiles_xy.y), 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    glBindTextureUnit(unit::depth, 0);
}

// Whether some object is drawn with glTF's BRDF this frame (its program needs the GGX levels).
bool Renderer::draws_metallic_roughness(const FramePlan& plan) const {
    return ggx_level_texels_ && std::ranges::any_of(plan.objects, [](const ObjectFrame& o) {
               return o.program == ShadeProgram::metallic_roughness;
           });
}

void Renderer::draw_objects(const FramePlan& plan, const CameraView& view) {
    if (variant_.fraction_pass) draw_shadowed_fraction(plan, view);
    if (variant_.fraction_pass && settings_.fraction_filter) filter_fraction(view);
    if (variant_.fraction_pass && settings_.shadow_rate == ShadowRate::adaptive) draw_refined_fraction(plan, view);
    if (settings_.depth_prepass) draw_depth_prepass(plan, view, samples_, "depth pre-pass");
    if (variant_.fraction_pass) {
        gl::ScopedPass pass(&timer_, "shading");
        const gl::Program& shade = fraction_shading_program(false);
        const gl::Program& shade_gltf = draws_metallic_roughness(plan) ? fraction_shading_program(true) : shade;
        bind_fraction_input(shading_fraction(), {&shade, &shade_gltf}, view);
        shade_objects(plan, view, {&shade, &shade, &shade, &shade_gltf}, screen_tiles_.x, opaque_objects_);
        unbind_fraction_input();
        return;
    }
    if (uses_tile_lists(settings_))
        build_tile_lists(plan, view, depth_, samples_, tile_lists_, screen_tiles_, "shadow tile lists");
    gl::ScopedPass pass(&timer_, "shading");
    const VariantPrograms& programs = *programs_now_;
    shade_objects(plan, view,
                  {&programs.shade, &programs.shade_diffuse, &programs.shade_flat, &metallic_roughness_program(plan)},
                  screen_tiles_.x, opaque_objects_);
}

// The variant's program for glTF's BRDF (METALLIC_ROUGHNESS), built once a frame draws such a material; the
// variant's full program where none does.
const gl::Program& Renderer::metallic_roughness_program(const FramePlan& plan) {
    VariantPrograms& programs = *programs_now_;
    if (!draws_metallic_roughness(plan)) return programs.shade;
    if (!programs.shade_gltf) {
        std::vector<std::string> defines = shade_defines(variant_);
        defines.push_back("METALLIC_ROUGHNESS");
        programs.shade_gltf =
            library_.build({{GL_VERTEX_SHADER, "shade.vert"}, {GL_FRAGMENT_SHADER, "shade.frag"}}, defines);
    }
    return programs.shade_gltf;
}

// The fraction pass (docs/DESIGN.md §5.14): the variant's programs (SHADOWED_FRACTION_OUT) at one sample per
// texel of fraction_, after a pre-pass and tile lists of its own.
void Renderer::draw_shadowed_fraction(const FramePlan& plan, const CameraView& view) {
    glBindFramebuffer(GL_FRAMEBUFFER, fraction_.framebuffer.id());
    glViewport(0, 0, fraction_.fraction.width(), fraction_.fraction.height());
    clear_fraction_target(fraction_.framebuffer);
    if (settings_.depth_prepass) draw_depth_prepass(plan, view, 1, "fraction pre-pass");
    if (uses_tile_lists(settings_))
        build_tile_lists(plan, view, fraction_.depth, 1, fraction_tile_lists_, fraction_tiles_, "fraction tile lists");
    {
        gl::ScopedPass pass(&timer_, "shadowed fraction");
        const VariantPrograms& programs = *programs_now_;
        // glTF's materials weigh the cells by their own BRDF (docs/DESIGN.md §11).
        shade_objects(
            plan, view,
            {&programs.shade, &programs.shade_diffuse, &programs.shade_flat, &metallic_roughness_program(plan)},
            fraction_tiles_.x, opaque_objects_);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, target_.id());
    glViewport(0, 0, view.width, view.height);
}

// The refinement (docs/DESIGN.md §5.14): at one sample per pixel into refined_, the per-2x2 fraction looked up
// as the shading would, and the cells' loop run again where the texels on the fragment's surface disagree.
void Renderer::draw_refined_fraction(const FramePlan& plan, const CameraView& view) {
    VariantPrograms& programs = *programs_now_;
    const bool gltf = draws_metallic_roughness(plan);
    if (!programs.refine || (gltf && !programs.refine_gltf)) {
        std::vector<std::string> defines = shade_defines(variant_);
        defines.insert(defines.end(), {"SHADOWED_FRACTION_IN", "SHADOWED_FRACTION_REFINE"});
        const std::vector<gl::ShaderStage> stages = {{GL_VERTEX_SHADER, "shade.vert"},
                                                     {GL_FRAGMENT_SHADER, "shade.frag"}};
        if (gltf && !programs.refine_gltf) {
            std::vector<std::string> gltf_defines = defines;
            gltf_defines.push_back("METALLIC_ROUGHNESS");
            programs.refine_gltf = library_.build(stages, gltf_defines);
        }
        if (!programs.refine) {
            programs.refine = library_.build(stages, defines);
            defines.push_back("DIFFUSE_ONLY");
            programs.refine_diffuse = library_.build(stages, defines);
            defines.push_back("FLAT_RECEIVER");
            programs.refine_flat = library_.build(stages, defines);
        }
    }
    glBindFramebuffer(GL_FRAMEBUFFER, refined_.framebuffer.id());
    clear_fraction_target(refined_.framebuffer);
    if (settings_.depth_prepass) draw_depth_prepass(plan, view, 1, "refined pre-pass");
    if (uses_tile_lists(settings_))
        build_tile_lists(plan, view, refined_.depth, 1, tile_lists_, screen_tiles_, "refined tile lists");
    gl::ScopedPass pass(&timer_, "refined fraction");
    const gl::Program& refine_gltf = gltf ? programs.refine_gltf : programs.refine;
    bind_fraction_input({settings_.fraction_filter ? fraction_filtered_ : fraction_.fraction, fraction_.normal},
                        {&programs.refine, &programs.refine_diffuse, &programs.refine_flat, &refine_gltf}, view);
    shade_objects(plan, view, {&programs.refine, &programs.refine_diffuse, &programs.refine_flat, &refine_gltf},
                  screen_tiles_.x, opaque_objects_);
    unbind_fraction_input();
    glBindFramebuffer(GL_FRAMEBUFFER, target_.id());
}

// The filter (docs/DESIGN.md §5.14): each texel of fraction_ the mean of the 3x3 about it on its surface, which
// averages the soft shadows' per-texel disc rotations.
void Renderer::filter_fraction(const CameraView& view) {
    gl::ScopedPass pass(&timer_, "fraction filter");
    glBindFramebuffer(GL_FRAMEBUFFER, fraction_filter_target_.id());
    glViewport(0, 0, fraction_filtered_.width(), fraction_filtered_.height());
    glDisable(GL_DEPTH_TEST);
    fraction_filter_program_.use();
    fraction_.fraction.bind(unit::fraction);
    fraction_.normal.bind(unit::fraction_normal);
    empty_vertex_array_.bind();
    glDrawArrays(GL_TRIANGLES, 0, 3);
    unbind_fraction_input();
    glEnable(GL_DEPTH_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, target_.id());
    glViewport(0, 0, view.width, view.height);
}

Renderer::FractionInput Renderer::shading_fraction() const {
    if (settings_.shadow_rate == ShadowRate::adaptive) return {refined_.fraction, refined_.normal};
    return {settings_.fraction_filter ? fraction_filtered_ : fraction_.fraction, fraction_.normal,
            variant_.sun_per_pixel ? &fraction_.sun : nullptr};
}

void Renderer::bind_fraction_input(FractionInput input, std::initializer_list<const gl::Program*> programs,
                                   const CameraView& view) {
    for (const gl::Program* program : programs)
        glProgramUniform2f(program->id(), loc::fraction_scale, float(input.fraction.width()) / float(view.width),
                           float(input.fraction.height()) / float(view.height));
    input.fraction.bind(unit::fraction);
    input.normal.bind(unit::fraction_normal);
    if (input.sun) input.sun->bind(unit::fraction_sun);
}

void Renderer::unbind_fraction_input() {
    glBindTextureUnit(unit::fraction, 0);
    glBindTextureUnit(unit::fraction_normal, 0);
    glBindTextureUnit(unit::fraction_sun, 0);
}

void Renderer::shade_objects(const FramePlan& plan, const CameraView& view, const ShadePrograms& programs, int tiles_x,
                             std::span<const std::size_t> objects, bool blending) {
    const glm::mat4 clip_from_world = view.clip_from_view * view.view_from_world;
    for (const gl::Program* shade :
         {programs.full, programs.diffuse_only, programs.flat_receiver, programs.metallic_roughness}) {
        const GLuint program = shade->id();
        glProgramUniformMatrix4fv(program, loc::clip_from_world, 1, GL_FALSE, &clip_from_world[0][0]);
        glProgramUniform3f(program, loc::eye, view.eye.x, view.eye.y, view.eye.z);
        glProgramUniform1i(program, loc::light_count, int(plan.lights.size()));
        glProgramUniform2f(program, loc::atlas_texel, 1.0f / float(layout_.width()), 1.0f / float(layout_.height()));
        glProgramUniform1f(program, loc::slope_bias, settings_.slope_bias);
        glProgramUniform1ui(program, loc::tiles_x, GLuint(tiles_x));
        if (variant_.sun_per_pixel && !blending) glProgramUniform1i(program, loc::sun_cell, sun_cell_);
    }
    atlas_depth_.bind(unit::atlas_depth);
    atlas_depth_sampler_.bind(unit::atlas_depth);
    if (variant_.translucent_shadows) {
        atlas_transmittance_.bind(unit::atlas_transmittance);
        atlas_translucent_depth_.bind(unit::atlas_translucent_depth);
    }
    const bool ratio = settings_.shading == ShadingMode::ratio;
    if (ratio) {
        const glm::mat3 env_from_world = map_from_world(rotation_degrees_);
        for (const gl::Program* shade :
             {programs.full, programs.diffuse_only, programs.flat_receiver, programs.metallic_roughness})
            glProgramUniformMatrix3fv(shade->id(), loc::env_from_world, 1, GL_FALSE, &env_from_world[0][0]);
        if (!prefiltered_.empty()) prefiltered_[0].bind(unit::irradiance);
        if (draws_metallic_roughness(plan)) {
            set_compact_sources(programs.metallic_roughness->id());
            glProgramUniform3iv(programs.metallic_roughness->id(), loc::ggx_levels, kGgxPrefilterLevels,
                                &ggx_level_rows_[0][0]);
        }
    }
    glEnable(GL_DEPTH_TEST);
    // After the pre-pass only the visible fragment of each pixel passes (bit-identical depths:
    // shade.vert's gl_Position is invariant), so the light loop runs once per pixel. Blended surfaces are
    // in no pre-pass: tested against the opaque depths, written nowhere.
    glDepthFunc(settings_.depth_prepass && !blending ? GL_EQUAL : GL_LESS);
    glDepthMask(settings_.depth_prepass || blending ? GL_FALSE : GL_TRUE);
    // Two-sided but for closed single-sided objects (set_sides): shade.frag turns the normal by
    // gl_FrontFacing (docs/DESIGN.md §5.4).
    for (const std::size_t i : objects) {
        const ObjectFrame& object = plan.objects[i];
        // glTF's BRDF needs the GGX levels; without them its Phong stand-in.
        const bool gltf = object.program == ShadeProgram::metallic_roughness && ggx_level_texels_;
        const gl::Program& shade = object.program == ShadeProgram::flat_receiver  ? *programs.flat_receiver
                                   : object.program == ShadeProgram::diffuse_only ? *programs.diffuse_only
                                   : gltf                                         ? *programs.metallic_roughness
                                                                                  : *programs.full;
        const GLuint program = shade.id();
        shade.use();
        if (object.program == ShadeProgram::flat_receiver)
            glProgramUniform3f(program, loc::unshadowed, object.unshadowed.x, object.unshadowed.y, object.unshadowed.z);
        glProgramUniformMatrix4fv(program, loc::world_from_object, 1, GL_FALSE, &object.world_from_object[0][0]);
        glProgramUniformMatrix3fv(program, loc::world_normal_from_object, 1, GL_FALSE,
                                  &object.world_normal_from_object[0][0]);
        set_sides(object, i);
        glProgramUniform3f(program, loc::k_d, object.k_d.r, object.k_d.g, object.k_d.b);
        glProgramUniform1f(program, loc::k_s, object.k_s);
        glProgramUniform1f(program, loc::shininess, object.shininess);
        if (ratio) bind_unshadowed_levels(program, object, i, gltf);
        (settings_.base_color_texture ? *instance_textures_[i] : white_texture_).bind(unit::base_color);
        glProgramUniform3f(program, loc::emission, object.emission.r, object.emission.g, object.emission.b);
        if (variant_.alpha_test && !blending) bind_alpha_mask(program, object, i);
        if (blending) glProgramUniform1f(program, loc::base_alpha, object.base_alpha);
        (settings_.emission_texture ? *instance_emission_textures_[i] : white_texture_).bind(unit::emission_texture);
        glProgramUniform1f(program, loc::occlusion_strength, object.occlusion_strength);
        (settings_.occlusion_texture ? *instance_occlusion_textures_[i] : white_texture_).bind(unit::occlusion_texture);
        glProgramUniform1f(program, loc::normal_scale, object.normal_scale);
        instance_normal_textures_[i]->bind(unit::normal_texture);
        instance_meshes_[i]->bind();
        instance_meshes_[i]->draw();
    }
    glDisable(GL_CULL_FACE);
    glFrontFace(GL_CCW);
    glBindSampler(unit::atlas_depth, 0);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
}

void Renderer::set_compact_sources(GLuint program) const {
    std::array<glm::vec4, kMaxCompactSources> directions{}, radiances{};
    const int count = std::min(int(compact_sources_.size()), kMaxCompactSources);
    const glm::mat3 world_from_map = glm::transpose(map_from_world(rotation_degrees_));
    for (int k = 0; k < count; ++k) {
        const CompactSource& source = compact_sources_[std::size_t(k)];
        directions[std::size_t(k)] = glm::vec4(world_from_map * source.direction, source.cos_radius);
        radiances[std::size_t(k)] = glm::vec4(source.radiance, 0.0f);
    }
    glProgramUniform1i(program, loc::compact_light_count, count);
    glProgramUniform4fv(program, loc::compact_directions, kMaxCompactSources, &directions[0][0]);
    glProgramUniform4fv(program, loc::compact_radiances, kMaxCompactSources, &radiances[0][0]);
}

void Renderer::set_sides(const ObjectFrame& object, std::size_t i) const {
    // Counter-clockwise in object space is the front (the vertex normals' side); a mirroring transform
    // turns it clockwise on screen.
    glFrontFace(glm::determinant(glm::mat3(object.world_from_object)) < 0.0f ? GL_CW : GL_CCW);
    if (instance_front_only_[i])
        glEnable(GL_CULL_FACE);
    else
        glDisable(GL_CULL_FACE);
}

void Renderer::bind_alpha_mask(GLuint program, const ObjectFrame& object, std::size_t i) const {
    glProgramUniform1f(program, loc::base_alpha, object.base_alpha);
    glProgramUniform1f(program, loc::alpha_cutoff, object.alpha_cutoff);
    (settings_.base_color_texture ? *instance_textures_[i] : white_texture_).bind(unit::base_color);
}

void Renderer::bind_unshadowed_levels(GLuint program, const ObjectFrame& object, std::size_t i, bool gltf) const {
    // With multisampling both BRDFs read their lobes over the pixel's footprint. glTF's BRDF: all the GGX levels and
    // the map itself, each pixel reading those about its own roughness; else the two Phong levels about the
    // shininess, interpolated in log lobe width.
    glProgramUniform1i(program, loc::pixel_footprint, samples_ > 1 ? 1 : 0);
    glProgramUniform4uiv(program, loc::sample_quarters, 1, sample_quarters_.data());
    glProgramUniform2f(program, loc::footprint_shift, frame_shift_.x, frame_shift_.y);
    if (gltf) {
        glProgramUniform1i(program, loc::upper_only, ggx_hemisphere_ == Hemisphere::upper ? 1 : 0);
        const MetallicRoughness& m = *object.metallic_roughness;
        glProgramUniform3f(program, loc::base_color_factor, m.base_color.r, m.base_color.g, m.base_color.b);
        glProgramUniform1f(program, loc::metallic, m.metallic);
        glProgramUniform1f(program, loc::roughness, m.roughness);
        (settings_.metallic_roughness_texture ? *instance_metallic_roughness_textures_[i] : white_texture_)
            .bind(unit::metallic_roughness_texture);
        ggx_level_texels_.bind(unit::ggx_level_texels);
        (ggx_mirror_ ? ggx_mirror_ : environment_).bind(unit::ggx_mirror);
        dfg_.bind(unit::dfg);
    } else if (!prefiltered_.empty()) {
        const LevelPair pair = prefiltered_levels_.level_pair(object.shininess);
        prefiltered_[std::size_t(pair.lower)].bind(unit::specular_lower);
        prefiltered_[std::size_t(pair.upper)].bind(unit::specular_upper);
        glProgramUniform1f(program, loc::specular_weight, pair.weight);
    }
}

// The blended objects over the image (docs/DESIGN.md §5.15): farthest first by the centres of their boxes, each
// shaded per fragment (no fraction pass, no tile lists: those hold the opaque surfaces' depths), its premultiplied
// radiance laid over what is behind by its alpha.
void Renderer::draw_blended(const FramePlan& plan, const CameraView& view) {
    if (blended_objects_.empty()) return;
    gl::ScopedPass pass(&timer_, "blended");
    const auto view_z = [&](std::size_t i) {  // view space looks down -z: the farthest has the least
        const GpuMesh& mesh = *instance_meshes_[i];
        const glm::vec4 centre(0.5f * (mesh.bounds_min() + mesh.bounds_max()), 1.0f);
        return (view.view_from_world * plan.objects[i].world_from_object * centre).z;
    };
    std::ranges::stable_sort(blended_objects_, {}, view_z);

    VariantPrograms& programs = *programs_now_;
    const bool gltf = draws_metallic_roughness(plan);
    if (!programs.blend || (gltf && !programs.blend_gltf)) {
        ShaderVariant per_fragment = variant_;
        per_fragment.tile_lists = per_fragment.fraction_pass = per_fragment.alpha_test = false;
        std::vector<std::string> defines = shade_defines(per_fragment);
        defines.push_back("ALPHA_BLEND");
        const std::vector<gl::ShaderStage> stages = {{GL_VERTEX_SHADER, "shade.vert"},
                                                     {GL_FRAGMENT_SHADER, "shade.frag"}};
        if (!programs.blend) {
            programs.blend = library_.build(stages, defines);
            std::vector<std::string> diffuse = defines;
            diffuse.push_back("DIFFUSE_ONLY");
            programs.blend_diffuse = library_.build(stages, diffuse);
        }
        if (gltf && !programs.blend_gltf) {
            defines.push_back("METALLIC_ROUGHNESS");
            programs.blend_gltf = library_.build(stages, defines);
        }
    }
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    shade_objects(
        plan, view,
        {&programs.blend, &programs.blend_diffuse, &programs.blend, gltf ? &programs.blend_gltf : &programs.blend},
        screen_tiles_.x, blended_objects_, true);
    glDisable(GL_BLEND);
}

void Renderer::draw_background(const CameraView& view) {
    if (!settings_.background || !environment_) return;
    gl::ScopedPass pass(&timer_, "background");
    // Directions only: the view's rotation, not its translation.
    const glm::mat4 direction_from_clip =
        glm::inverse(view.clip_from_view * glm::mat4(glm::mat3(view.view_from_world)));
    const glm::mat3 map_from_world_matrix = map_from_world(rotation_degrees_);
    const GLuint program = background_program_.id();
    background_program_.use();
    glProgramUniformMatrix4fv(program, loc::direction_from_clip, 1, GL_FALSE, &direction_from_clip[0][0]);
    glProgramUniformMatrix3fv(program, loc::map_from_world, 1, GL_FALSE, &map_from_world_matrix[0][0]);
    environment_.bind(unit::environment);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);  // only where no object was drawn (depth still cleared to 1)
    glDepthMask(GL_FALSE);
    empty_vertex_array_.bind();
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
}

FrameStats Renderer::render(double time, const CameraView& unjittered) {
    if (unjittered.width < 1 || unjittered.height < 1) throw UsageError("render: image size must be positive");
    ensure_atlas();
    ensure_target(unjittered.width, unjittered.height);
    // The jitter moves the samples no farther than keeps each in its pixel: the resolve's mean stays the pixel's.
    const glm::vec2 shift = glm::clamp(unjittered.jitter, -sample_margin_, sample_margin_);
    const CameraView view = shifted_by_pixels(unjittered, shift);
    frame_shift_ = shift;
    if (variant_.fraction_pass) ensure_fraction_target(view.width, view.height);
    // Deforming objects (glTF skins and morphs): the pose at `time` into their vertex buffers and their
    // boxes into the plan, before the atlas and the shading draw them (both see this pose).
    for (const DeformingInstance& d : deforming_) {
        const std::shared_ptr<const Mesh> posed = d.object.mesh_at(time);
        d.mesh->update_vertices(*posed);
        planner_.set_bounds(d.instance, d.mesh->bounds_min(), d.mesh->bounds_max());
    }
    const FramePlan& plan = planner_.plan(time, view, layout_, settings_);
    if (const bool translucent =
            std::ranges::any_of(plan.objects, [](const ObjectFrame& o) { return o.casts_shadows && o.blended; });
        translucent != translucent_casters_) {
        translucent_casters_ = translucent;
        select_programs();
    }
    upload(plan);
    glBindBufferBase(variant_.lights_uniform_block ? GL_UNIFORM_BUFFER : GL_SHADER_STORAGE_BUFFER, binding::lights,
                     light_buffer_.id());
    if (!timer_warmed_up_) {
        // Mesa's llvmpipe (22.3) gives the first GL_TIME_ELAPSED query of a context that draws
        // anything a start time of 0 (it reads as the time since boot): spend it on a clear.
        timer_.begin("warm-up");
        const float far_depth = 1.0f;
        glClearNamedFramebufferfv(atlas_.id(), GL_DEPTH, 0, &far_depth);
        timer_.end();
        timer_.resolve();
        timer_warmed_up_ = true;
    }

    FrameStats stats;
    draw_atlas(plan, stats);

    glBindFramebuffer(GL_FRAMEBUFFER, target_.id());
    glViewport(0, 0, view.width, view.height);
    const float clear_color[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    const float clear_depth = 1.0f;
    glDepthMask(GL_TRUE);
    glClearNamedFramebufferfv(target_.id(), GL_COLOR, 0, clear_color);
    glClearNamedFramebufferfv(target_.id(), GL_DEPTH, 0, &clear_depth);
    opaque_objects_.clear();
    blended_objects_.clear();
    for (std::size_t i = 0; i < instance_meshes_.size(); ++i)
        (plan.objects[i].blended ? blended_objects_ : opaque_objects_).push_back(i);
    draw_objects(plan, view);
    draw_background(view);
    draw_blended(plan, view);
    if (samples_ > 1) {
        // The mean of each pixel's samples, in linear HDR (tone mapping comes after, on the resolved colour).
        gl::ScopedPass resolve(&timer_, "msaa resolve");
        glBlitNamedFramebuffer(target_.id(), resolved_.id(), 0, 0, view.width, view.height, 0, 0, view.width,
                               view.height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);

    stats.passes = timer_.resolve();
    stats.lights = int(plan.lights.size());
    stats.lights_below_ground = lights_.below_ground;
    stats.lights_negligible = lights_.negligible;
    stats.atlas_bytes = atlas_bytes();
    stats.atlas = layout_;
    stats.atlas_triangles = atlas_triangles_;
    return stats;
}

std::vector<glm::vec2> Renderer::sample_positions() const {
    if (samples_ == 1) return {glm::vec2(0.5f)};
    const gl::Texture colour = gl::Texture::create_2d_multisample(GL_RGBA32F, 1, 1, samples_);
    gl::Framebuffer framebuffer = gl::Framebuffer::create();
    framebuffer.attach(GL_COLOR_ATTACHMENT0, colour);
    framebuffer.check_complete(target_name(1, 1, samples_, "sample-position probe"));
    return query_sample_positions(framebuffer, samples_);
}

Image Renderer::read_back() const {
    return gl::read_color(framebuffer(), color_.width(), color_.height());
}

}  // namespace envshadow::render
