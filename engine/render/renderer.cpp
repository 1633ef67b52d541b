#include "render/renderer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <string>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/matrix.hpp>

#include "core/error.h"
#include "core/log.h"
#include "env/brdf.h"
#include "env/orientation.h"
#include "gl/readback.h"
#include "render/embedded_shaders.h"
#include "render/shader_interface.h"

namespace envshadow::render {

using namespace shader;  // loc::, unit::, binding::, size::

namespace {
constexpr int kMaxCasterRects = 16;  // per light; more casters share one rectangle (the tile)

// Texels between the casters and a tile's border: the wide PCF reaches 1.5 texels from its centre.
constexpr float kTileMarginTexels = 3.0f;
// Viewports used per batch in AtlasMode::viewport_array (GL_MAX_VIEWPORTS is 16 on most drivers).
constexpr int kMaxViewports = 64;

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

Renderer::Renderer(const RenderSettings& settings) : settings_(settings), library_(embedded_shaders()) {
    validate(settings_);
    glGetIntegerv(GL_MAX_VIEWPORTS, &max_viewports_);
    GLint max_block = 0;
    glGetIntegerv(GL_MAX_UNIFORM_BLOCK_SIZE, &max_block);
    uniform_block_fits_ = std::size_t(max_block) >= std::size_t(size::max_lights) * sizeof(LightRecord);
    use_uniform_block_ = settings_.lights_uniform_block && uniform_block_fits_;
    max_viewports_ = std::clamp(max_viewports_, 1, kMaxViewports);
    empty_vertex_array_ = gl::VertexArray::create();
    // Hardware depth comparison with bilinear filtering of the results: 2x2 PCF per lookup.
    shadow_sampler_ = gl::Sampler::create({.min_filter = GL_LINEAR,
                                           .mag_filter = GL_LINEAR,
                                           .wrap_s = GL_CLAMP_TO_EDGE,
                                           .wrap_t = GL_CLAMP_TO_EDGE,
                                           .compare_mode = GL_COMPARE_REF_TO_TEXTURE,
                                           .compare_func = GL_LEQUAL});
    build_programs();
}

Renderer::~Renderer() = default;

void Renderer::build_programs() {
    // Shared by the atlas, shading and screen-tile programs (MAX_LIGHTS and the other numbers of
    // render/shader_interface.h are in every stage already).
    std::vector<std::string> light_defines;
    if (use_uniform_block_) light_defines.push_back("LIGHTS_UNIFORM_BLOCK");
    tiles_program_ = library_.build({{GL_COMPUTE_SHADER, "shadow_tiles.comp"}}, light_defines);
    std::vector<std::string> atlas_defines = light_defines;
    if (settings_.atlas == AtlasMode::viewport_array && !GLAD_GL_ARB_shader_viewport_layer_array) {
        log::warn("GL_ARB_shader_viewport_layer_array is missing: drawing the shadow atlas with clip distances");
        settings_.atlas = AtlasMode::clip_distances;
    }
    if (settings_.atlas == AtlasMode::clip_distances) atlas_defines.push_back("ATLAS_CLIP_DISTANCES");
    if (settings_.atlas == AtlasMode::viewport_array) atlas_defines.push_back("ATLAS_VIEWPORT_ARRAY");
    atlas_program_ = library_.build({{GL_VERTEX_SHADER, "shadow_atlas.vert"}}, atlas_defines);

    std::vector<std::string> shade_defines = light_defines;
    if (settings_.diffuse == DiffuseMode::cap) shade_defines.push_back("DIFFUSE_CAP");
    if (settings_.specular == SpecularMode::single) shade_defines.push_back("SPECULAR_SINGLE");
    if (settings_.pcf == PcfKernel::wide) shade_defines.push_back("PCF_WIDE");
    if (tile_lists_active()) shade_defines.push_back("SHADOW_TILE_LISTS");
    shade_program_ =
        library_.build({{GL_VERTEX_SHADER, "shade.vert"}, {GL_FRAGMENT_SHADER, "shade.frag"}}, shade_defines);
    shade_defines.push_back("DIFFUSE_ONLY");
    shade_diffuse_program_ =
        library_.build({{GL_VERTEX_SHADER, "shade.vert"}, {GL_FRAGMENT_SHADER, "shade.frag"}}, shade_defines);
    shade_defines.push_back("FLAT_RECEIVER");
    shade_flat_program_ =
        library_.build({{GL_VERTEX_SHADER, "shade.vert"}, {GL_FRAGMENT_SHADER, "shade.frag"}}, shade_defines);
    if (!prepass_program_)  // shade.vert's gl_Position is invariant: the shading pass's depths equal these
        prepass_program_ =
            library_.build({{GL_VERTEX_SHADER, "shade.vert"}, {GL_FRAGMENT_SHADER, "depth_prepass.frag"}});
    if (!background_program_)
        background_program_ =
            library_.build({{GL_VERTEX_SHADER, "background.vert"}, {GL_FRAGMENT_SHADER, "background.frag"}});
}

void Renderer::set_settings(const RenderSettings& settings) {
    validate(settings);
    const RenderSettings old = settings_;
    settings_ = settings;
    use_uniform_block_ = settings_.lights_uniform_block && uniform_block_fits_;
    if (old.atlas != settings.atlas || old.diffuse != settings.diffuse || old.specular != settings.specular ||
        old.pcf != settings.pcf || old.lights_uniform_block != settings.lights_uniform_block ||
        old.shadow_tile_lists != settings.shadow_tile_lists || old.depth_prepass != settings.depth_prepass)
        build_programs();
    if (old.skip_lights != settings.skip_lights) select_lights();
}

void Renderer::set_scene(const Scene& scene) {
    meshes_.clear();
    instances_.clear();
    instance_of_object_.clear();
    std::map<const Mesh*, const GpuMesh*> uploaded;
    for (const Object& object : scene.objects) {
        instance_of_object_.push_back(-1);
        if (!object.mesh || object.mesh->indices.empty()) continue;
        instance_of_object_.back() = int(instances_.size());
        auto [it, added] = uploaded.emplace(object.mesh.get(), nullptr);
        if (added) {
            meshes_.push_back(std::make_unique<GpuMesh>(*object.mesh));
            it->second = meshes_.back().get();
        }
        Instance instance;
        instance.mesh = it->second;
        instance.object = object;
        instance.object.mesh.reset();  // the GPU copy is enough
        instances_.push_back(std::move(instance));
    }
    has_ground_ = scene.has_ground;
    rotation_degrees_ = scene.environment.rotation_degrees;
    select_lights();
}

void Renderer::set_material(std::size_t object, const Material& material) {
    if (object < instance_of_object_.size() && instance_of_object_[object] >= 0)
        instances_[std::size_t(instance_of_object_[object])].object.material = material;
}

void Renderer::set_environment(const EnvironmentMap& map) {
    environment_ = gl::Texture::create_2d(GL_RGB32F, map.width, map.height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage2D(environment_.id(), 0, 0, 0, map.width, map.height, GL_RGB, GL_FLOAT, map.texels.data());
    environment_.set_filter(GL_LINEAR, GL_LINEAR);
    environment_.set_wrap(GL_REPEAT, GL_CLAMP_TO_EDGE);  // u wraps around the sphere, v stops at the poles
}

void Renderer::set_environment_rotation(float degrees) {
    rotation_degrees_ = degrees;
    select_lights();
}

void Renderer::set_lights(std::vector<Cell> cells, CellSpace space) {
    cells_ = std::move(cells);
    cell_space_ = space;
    select_lights();
}

void Renderer::select_lights() {
    const glm::mat3 rotation = cell_space_ == CellSpace::map ? world_from_map(rotation_degrees_) : glm::mat3(1.0f);
    lights_ = render::select_lights(cells_, rotation, has_ground_, settings_.skip_lights);
    light_frames_.clear();
    for (const WorldLight& light : lights_.kept) light_frames_.push_back(light_frame(light.direction));
    records_.assign(lights_.kept.size(), LightRecord{});
    // Room for MAX_LIGHTS records: a uniform block's bound range must cover its whole declared array.
    light_buffer_ = gl::Buffer::create(std::size_t(size::max_lights) * sizeof(LightRecord));
}

void Renderer::ensure_atlas() {
    const int tiles = std::max(light_count(), 1);
    if (atlas_depth_ && layout_.tile_count == tiles && layout_.requested_tile_size == settings_.tile_size &&
        atlas_depth_bits_ == settings_.depth_bits)
        return;
    GLint max_texture = 0, max_viewport[2] = {0, 0};
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_texture);
    glGetIntegerv(GL_MAX_VIEWPORT_DIMS, max_viewport);
    layout_ = plan_atlas(tiles, settings_.tile_size, std::min({max_texture, max_viewport[0], max_viewport[1]}));
    if (layout_.tile_size != layout_.requested_tile_size)
        log::warn("shadow atlas: " + std::to_string(tiles) + " tiles of " + std::to_string(settings_.tile_size) +
                  "^2 exceed the GL limit; using " + std::to_string(layout_.tile_size) + "^2 tiles");
    atlas_depth_bits_ = settings_.depth_bits;
    atlas_depth_ = gl::Texture::create_2d(settings_.depth_bits == 16 ? GL_DEPTH_COMPONENT16 : GL_DEPTH_COMPONENT32F,
                                          layout_.width(), layout_.height());
    atlas_ = gl::Framebuffer::create();
    atlas_.attach(GL_DEPTH_ATTACHMENT, atlas_depth_);
    glNamedFramebufferDrawBuffer(atlas_.id(), GL_NONE);
    glNamedFramebufferReadBuffer(atlas_.id(), GL_NONE);
    atlas_.check_complete("shadow atlas");
}

void Renderer::ensure_target(int width, int height) {
    if (color_ && color_.width() == width && color_.height() == height) return;
    color_ = gl::Texture::create_2d(GL_RGBA32F, width, height);
    depth_ = gl::Texture::create_2d(GL_DEPTH_COMPONENT32F, width, height);
    depth_.set_filter(GL_NEAREST, GL_NEAREST);  // read by shadow_tiles.comp
    screen_tiles_ = glm::ivec2((width + size::screen_tile - 1) / size::screen_tile,
                               (height + size::screen_tile - 1) / size::screen_tile);
    tile_lists_ = gl::Buffer::create(std::size_t(screen_tiles_.x) * std::size_t(screen_tiles_.y) *
                                     std::size_t(size::max_lights + 1) * sizeof(std::uint32_t));
    target_ = gl::Framebuffer::create();
    target_.attach(GL_COLOR_ATTACHMENT0, color_);
    target_.attach(GL_DEPTH_ATTACHMENT, depth_);
    target_.check_complete("render target");
}

void Renderer::update_instances(double time) {
    caster_points_.clear();
    for (Instance& instance : instances_) {
        instance.world_from_object = instance.object.world_from_object(time);
        instance.world_normal_from_object = glm::inverseTranspose(glm::mat3(instance.world_from_object));
        if (!instance.object.casts_shadows) continue;
        // The object's box corners in the world: tighter in the light's frame than the world box.
        for (const glm::vec3& corner : box_corners(instance.mesh->bounds_min(), instance.mesh->bounds_max()))
            caster_points_.push_back(glm::vec3(instance.world_from_object * glm::vec4(corner, 1.0f)));
    }
}

void Renderer::fit_lights() {
    const glm::vec2 tile_uv(1.0f / float(layout_.columns), 1.0f / float(layout_.rows));
    const bool weighted = settings_.cap == CapKind::weighted;
    min_texel_world_ = std::numeric_limits<float>::infinity();
    for (std::size_t k = 0; k < records_.size(); ++k) {
        const WorldLight& light = lights_.kept[k];
        const OrthographicFit fit =
            fit_orthographic(light_frames_[k], caster_points_, layout_.tile_size, kTileMarginTexels);
        LightRecord& record = records_[k];
        record.direction = glm::vec4(light.direction, weighted ? light.cos_radius_weighted : light.cos_radius);
        record.radiance = glm::vec4(light.radiance, 0.0f);
        record.clip_from_world = fit.clip_from_world;
        const int column = int(k) % layout_.columns, row = int(k) / layout_.columns;
        record.tile = glm::vec4(float(column) * tile_uv.x, float(row) * tile_uv.y, tile_uv.x, tile_uv.y);
        record.bias = glm::vec4(settings_.depth_bias * fit.texel_world / fit.depth_range,
                                settings_.normal_offset * fit.texel_world, 0.0f, 0.0f);
        min_texel_world_ = std::min(min_texel_world_, fit.texel_world);
    }
    // Each caster's box in each light's clip space, widened by 2 texels (shadow_tiles.comp).
    const std::size_t casters = caster_points_.size() / 8;
    caster_rect_count_ = casters <= std::size_t(kMaxCasterRects) ? int(std::max<std::size_t>(casters, 1)) : 1;
    caster_rects_.assign(records_.size() * std::size_t(caster_rect_count_), glm::vec4(-1.0f, -1.0f, 1.0f, 1.0f));
    if (casters >= 1 && casters <= std::size_t(kMaxCasterRects)) {
        const float pad = 2.0f * 2.0f / float(layout_.tile_size);  // 2 texels in clip units
        for (std::size_t k = 0; k < records_.size(); ++k)
            for (std::size_t c = 0; c < casters; ++c) {
                glm::vec2 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
                for (std::size_t j = 0; j < 8; ++j) {
                    const glm::vec2 xy(records_[k].clip_from_world * glm::vec4(caster_points_[8 * c + j], 1.0f));
                    lo = glm::min(lo, xy);
                    hi = glm::max(hi, xy);
                }
                caster_rects_[k * casters + c] = glm::vec4(lo - pad, hi + pad);
            }
    }
    if (caster_rects_.empty()) caster_rects_.push_back(glm::vec4(0.0f));
    caster_rect_buffer_.upload_resizing(caster_rects_.data(), caster_rects_.size() * sizeof(glm::vec4));
    if (records_.empty()) min_texel_world_ = 0.0f;
    light_buffer_.upload(records_.data(), records_.size() * sizeof(LightRecord));
}

void Renderer::draw_atlas() {
    gl::ScopedPass pass(&timer_, "shadow atlas");
    glBindFramebuffer(GL_FRAMEBUFFER, atlas_.id());
    glDepthMask(GL_TRUE);
    const float far_depth = 1.0f;
    glClearNamedFramebufferfv(atlas_.id(), GL_DEPTH, 0, &far_depth);
    if (records_.empty()) return;
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_CULL_FACE);  // both faces cast: open meshes and thin parts stay in the map
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(settings_.slope_bias, 1.0f);
    atlas_program_.use();
    glProgramUniform2i(atlas_program_.id(), loc::atlas_tiles, layout_.columns, layout_.rows);
    const int tiles = int(records_.size());
    const int tile_size = layout_.tile_size;

    // Each caster at the coarsest level of detail within settings_.caster_lod of the smallest texel
    // of this frame's tiles (level 0, the full mesh, with caster_lod = 0).
    atlas_triangles_ = 0;
    auto for_each_caster = [&](int tiles_per_draw, auto&& draw) {
        for (const Instance& instance : instances_) {
            if (!instance.object.casts_shadows) continue;
            const CasterLod& lod = instance.mesh->caster_lod();
            const int level = choose_caster_level(
                lod, caster_error_budget(instance.world_from_object, min_texel_world_, settings_.caster_lod));
            atlas_triangles_ +=
                std::size_t(lod.levels[std::size_t(level)].index_count / 3) * std::size_t(tiles_per_draw);
            glProgramUniformMatrix4fv(atlas_program_.id(), loc::world_from_object, 1, GL_FALSE,
                                      &instance.world_from_object[0][0]);
            // Closed casters: front faces only (the light frame keeps the winding: right x up = toward,
            // so faces turned to the light are counter-clockwise in the tile; a mirroring transform
            // turns them clockwise).
            if (settings_.cull_back_faces && lod.levels[std::size_t(level)].closed) {
                glEnable(GL_CULL_FACE);
                glCullFace(GL_BACK);
                glFrontFace(glm::determinant(glm::mat3(instance.world_from_object)) < 0.0f ? GL_CW : GL_CCW);
            } else {
                glDisable(GL_CULL_FACE);
            }
            instance.mesh->bind_caster();
            draw(*instance.mesh, level);
        }
    };
    switch (settings_.atlas) {
        case AtlasMode::clip_distances:
            for (GLenum plane = 0; plane < 4; ++plane) glEnable(GL_CLIP_DISTANCE0 + plane);
            glViewport(0, 0, layout_.width(), layout_.height());
            glProgramUniform1i(atlas_program_.id(), loc::first_tile, 0);
            for_each_caster(
                tiles, [&](const GpuMesh& mesh, int level) { mesh.draw_caster(level, tiles); });  // one draw per mesh
            for (GLenum plane = 0; plane < 4; ++plane) glDisable(GL_CLIP_DISTANCE0 + plane);
            break;
        case AtlasMode::viewport_array:
            for (int first = 0; first < tiles; first += max_viewports_) {
                const int batch = std::min(max_viewports_, tiles - first);
                std::array<float, 4 * kMaxViewports> rects{};
                for (int i = 0; i < batch; ++i) {
                    const int k = first + i;
                    rects[4 * i + 0] = float((k % layout_.columns) * tile_size);
                    rects[4 * i + 1] = float((k / layout_.columns) * tile_size);
                    rects[4 * i + 2] = rects[4 * i + 3] = float(tile_size);
                }
                glViewportArrayv(0, batch, rects.data());
                glProgramUniform1i(atlas_program_.id(), loc::first_tile, first);
                for_each_caster(batch, [&](const GpuMesh& mesh, int level) { mesh.draw_caster(level, batch); });
            }
            break;
        case AtlasMode::per_tile:
            for (int k = 0; k < tiles; ++k) {
                glViewport((k % layout_.columns) * tile_size, (k / layout_.columns) * tile_size, tile_size, tile_size);
                glProgramUniform1i(atlas_program_.id(), loc::first_tile, k);
                for_each_caster(1, [&](const GpuMesh& mesh, int level) { mesh.draw_caster(level); });
            }
            break;
    }
    glDisable(GL_POLYGON_OFFSET_FILL);
    glDisable(GL_CULL_FACE);
    glFrontFace(GL_CCW);
}

void Renderer::draw_depth_prepass(const CameraView& view) {
    gl::ScopedPass pass(&timer_, "depth pre-pass");
    const glm::mat4 clip_from_world = view.clip_from_view * view.view_from_world;
    const GLuint program = prepass_program_.id();
    prepass_program_.use();
    glProgramUniformMatrix4fv(program, loc::clip_from_world, 1, GL_FALSE, &clip_from_world[0][0]);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_CULL_FACE);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    for (const Instance& instance : instances_) {
        glProgramUniformMatrix4fv(program, loc::world_from_object, 1, GL_FALSE, &instance.world_from_object[0][0]);
        instance.mesh->bind();
        instance.mesh->draw();
    }
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
}

bool Renderer::tile_lists_active() const {
    return settings_.shadow_tile_lists && settings_.depth_prepass;
}

void Renderer::build_tile_lists(const CameraView& view) {
    gl::ScopedPass pass(&timer_, "shadow tile lists");
    const glm::mat4 world_from_clip = glm::inverse(view.clip_from_view * view.view_from_world);
    float pad = min_texel_world_;  // position reconstruction and rounding; V = 1 for 2 texels inside the border anyway
    for (const LightRecord& record : records_) pad = std::max(pad, record.bias.y + min_texel_world_);
    const GLuint program = tiles_program_.id();
    tiles_program_.use();
    glProgramUniformMatrix4fv(program, loc::world_from_clip, 1, GL_FALSE, &world_from_clip[0][0]);
    glProgramUniform1i(program, loc::light_count, int(records_.size()));
    glProgramUniform1f(program, loc::pad, pad);
    glProgramUniform1i(program, loc::caster_count, caster_rect_count_);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::caster_rects, caster_rect_buffer_.id());
    depth_.bind(unit::depth);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::tile_lists, tile_lists_.id());
    glDispatchCompute(GLuint(screen_tiles_.x), GLuint(screen_tiles_.y), 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    glBindTextureUnit(unit::depth, 0);
}

void Renderer::draw_objects(const CameraView& view) {
    if (settings_.depth_prepass) draw_depth_prepass(view);
    if (tile_lists_active()) build_tile_lists(view);
    gl::ScopedPass pass(&timer_, "shading");
    const glm::mat4 clip_from_world = view.clip_from_view * view.view_from_world;
    for (const gl::Program* shade : {&shade_program_, &shade_diffuse_program_, &shade_flat_program_}) {
        const GLuint program = shade->id();
        glProgramUniformMatrix4fv(program, loc::clip_from_world, 1, GL_FALSE, &clip_from_world[0][0]);
        glProgramUniform3f(program, loc::eye, view.eye.x, view.eye.y, view.eye.z);
        glProgramUniform1i(program, loc::light_count, int(records_.size()));
        glProgramUniform2f(program, loc::atlas_texel, 1.0f / float(layout_.width()), 1.0f / float(layout_.height()));
        glProgramUniform1ui(program, loc::tiles_x, GLuint(screen_tiles_.x));
    }
    atlas_depth_.bind(unit::atlas);
    shadow_sampler_.bind(unit::atlas);
    glEnable(GL_DEPTH_TEST);
    // After the pre-pass only the visible fragment of each pixel passes (bit-identical depths:
    // shade.vert's gl_Position is invariant), so the light loop runs once per pixel.
    glDepthFunc(settings_.depth_prepass ? GL_EQUAL : GL_LESS);
    glDepthMask(settings_.depth_prepass ? GL_FALSE : GL_TRUE);
    glDisable(GL_CULL_FACE);  // two-sided (shade.frag turns the normal to the viewer)
    for (const Instance& instance : instances_) {
        const Material& material = instance.object.material;
        const glm::vec3 k_d(brdf::diffuse_coefficient(material.rho_d.r), brdf::diffuse_coefficient(material.rho_d.g),
                            brdf::diffuse_coefficient(material.rho_d.b));
        const float k_s = brdf::specular_coefficient(material.rho_s, material.shininess);
        // Materials without a specular part get the shader compiled without it (shade.frag DIFFUSE_ONLY).
        const bool diffuse_only = settings_.specialise_shaders && !(k_s > 0.0f);
        // A plane with a diffuse material (the ground): the normal the shader would use, turned to the
        // eye as shade.frag turns it, gives every a_i once for all its pixels.
        glm::vec3 flat_normal(0.0f);
        bool flat = false;
        if (diffuse_only && settings_.flat_receivers && tile_lists_active() &&
            settings_.diffuse == DiffuseMode::center && instance.mesh->flat_normal()) {
            const glm::vec3 n = glm::normalize(instance.world_normal_from_object * *instance.mesh->flat_normal());
            const glm::vec3 point(instance.world_from_object * glm::vec4(instance.mesh->bounds_min(), 1.0f));
            const float side = glm::dot(n, view.eye - point);
            if (std::isfinite(side) && std::abs(side) > 1e-4f) {
                flat = true;
                flat_normal = side < 0.0f ? -n : n;
            }
        }
        const gl::Program& shade = flat ? shade_flat_program_ : diffuse_only ? shade_diffuse_program_ : shade_program_;
        const GLuint program = shade.id();
        shade.use();
        if (flat) {
            glm::dvec3 sum(0.0);
            for (const LightRecord& record : records_)
                sum += glm::dvec3(record.radiance) *
                       (glm::dvec3(k_d) * double(std::max(glm::dot(flat_normal, glm::vec3(record.direction)), 0.0f)));
            glProgramUniform3f(program, loc::unshadowed, float(sum.x), float(sum.y), float(sum.z));
        }
        glProgramUniformMatrix4fv(program, loc::world_from_object, 1, GL_FALSE, &instance.world_from_object[0][0]);
        glProgramUniformMatrix3fv(program, loc::world_normal_from_object, 1, GL_FALSE,
                                  &instance.world_normal_from_object[0][0]);
        glProgramUniform3f(program, loc::k_d, k_d.r, k_d.g, k_d.b);
        glProgramUniform1f(program, loc::k_s, k_s);
        glProgramUniform1f(program, loc::shininess, material.shininess);
        instance.mesh->bind();
        instance.mesh->draw();
    }
    glBindSampler(unit::atlas, 0);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
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

FrameStats Renderer::render(double time, const CameraView& view) {
    if (view.width < 1 || view.height < 1) throw UsageError("render: image size must be positive");
    ensure_atlas();
    ensure_target(view.width, view.height);
    update_instances(time);
    fit_lights();
    glBindBufferBase(use_uniform_block_ ? GL_UNIFORM_BUFFER : GL_SHADER_STORAGE_BUFFER, binding::lights,
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

    draw_atlas();

    glBindFramebuffer(GL_FRAMEBUFFER, target_.id());
    glViewport(0, 0, view.width, view.height);
    const float clear_color[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    const float clear_depth = 1.0f;
    glDepthMask(GL_TRUE);
    glClearNamedFramebufferfv(target_.id(), GL_COLOR, 0, clear_color);
    glClearNamedFramebufferfv(target_.id(), GL_DEPTH, 0, &clear_depth);
    draw_objects(view);
    draw_background(view);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);

    FrameStats stats;
    stats.passes = timer_.resolve();
    stats.lights = int(records_.size());
    stats.lights_below_ground = lights_.below_ground;
    stats.lights_negligible = lights_.negligible;
    stats.atlas_bytes = atlas_bytes();
    stats.atlas = layout_;
    stats.atlas_triangles = atlas_triangles_;
    return stats;
}

Image Renderer::read_back() const {
    return gl::read_color(target_, color_.width(), color_.height());
}

}  // namespace envshadow::render
