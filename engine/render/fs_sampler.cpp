#include "render/fs_sampler.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <glm/vec4.hpp>

#include "core/error.h"
#include "render/shader_interface.h"

namespace envshadow::render {

using namespace shader;  // loc::, unit::, image::, binding::, size::

namespace {
constexpr int kComponentsPerSample = 1;  // fs_sampler.geom emits one uint per sample

GLint get_integer(GLenum name) {
    GLint value = 0;
    glGetIntegerv(name, &value);
    return value;
}
}  // namespace

int FsGeometryLimits::vertices_per_invocation() const {
    return std::min(max_output_vertices, max_total_output_components / kComponentsPerSample);
}

FsGeometryLimits query_geometry_limits() {
    FsGeometryLimits limits;
    limits.max_output_vertices = get_integer(GL_MAX_GEOMETRY_OUTPUT_VERTICES);
    limits.max_total_output_components = get_integer(GL_MAX_GEOMETRY_TOTAL_OUTPUT_COMPONENTS);
    limits.max_storage_blocks = get_integer(GL_MAX_GEOMETRY_SHADER_STORAGE_BLOCKS);
    return limits;
}

FsDiffusionWeights fs_diffusion_weights(FsWeighting weighting, int samples, int width, int height) {
    if (weighting == FsWeighting::listing) return {};
    const double texels = double(width) * double(height);
    const double next = std::max(0.375, 1.0 - std::sqrt(double(samples) / texels));
    return {next, 0.6 * (1.0 - next), 0.4 * (1.0 - next)};
}

int fs_block_size(int width, int height, int samples) {
    constexpr long long kBlocksPerSample = 64;
    int block = 1;
    while (block < height) {
        const long long coarser =
            (long long)((width + 2 * block - 1) / (2 * block)) * ((height + 2 * block - 1) / (2 * block));
        if (coarser < kBlocksPerSample * samples) break;
        block *= 2;
    }
    return block;
}

int fs_scan_rows(int importance_height, int environment_height, bool upper_hemisphere) {
    if (!upper_hemisphere) return importance_height;
    // Importance row r sums the environment rows from ceil(r H / h - 1/2) (glsl/fs_importance.comp,
    // block_start); it holds light from above the horizon when that is one of the upper ceil(H / 2).
    const int upper_rows = (environment_height + 1) / 2;
    int rows = 0;
    while (rows < importance_height &&
           (2LL * rows * environment_height + importance_height - 1) / (2LL * importance_height) < upper_rows)
        ++rows;
    return rows;
}

int fs_capacity(int samples) {
    return samples + samples / 4 + 16;
}

FsSampler::FsSampler(const gl::ShaderLibrary& shaders, FsSamplerOptions options)
    : shaders_(shaders), options_(options), limits_(query_geometry_limits()) {
    if (limits_.max_storage_blocks < 2)
        throw PlatformError(
            "Floyd-Steinberg GPU sampler: the geometry shader needs 2 storage blocks, "
            "GL_MAX_GEOMETRY_SHADER_STORAGE_BLOCKS is " +
            std::to_string(limits_.max_storage_blocks) + "; use the CPU method fs instead");
    if (options_.vertices_per_invocation < 0)
        throw UsageError("Floyd-Steinberg GPU sampler: vertices per invocation must be positive");
    importance_program_ = shaders.build({{GL_COMPUTE_SHADER, "fs_importance.comp"}});
    lights_program_ = shaders.build({{GL_COMPUTE_SHADER, "fs_lights.comp"}});
    if (options_.light_model == FsLightModel::cells) {
        cell_assign_program_ = shaders.build({{GL_COMPUTE_SHADER, "fs_cell_assign.comp"}});
        cell_integrate_program_ = shaders.build({{GL_COMPUTE_SHADER, "fs_cell_integrate.comp"}});
    }
    counts_ = gl::Buffer::create(sizeof(FsCounts));
    feedback_ = gl::TransformFeedback::create();
    empty_vao_ = gl::VertexArray::create();
    // Headless contexts have no default framebuffer; one without attachments is complete (GL 4.3).
    no_attachments_ = gl::Framebuffer::create();
    glNamedFramebufferParameteri(no_attachments_.id(), GL_FRAMEBUFFER_DEFAULT_WIDTH, 1);
    glNamedFramebufferParameteri(no_attachments_.id(), GL_FRAMEBUFFER_DEFAULT_HEIGHT, 1);
}

const gl::Program& FsSampler::sampler_program(int width, int vertices) {
    if (!sampler_program_ || sampler_program_width_ != width || sampler_program_vertices_ != vertices) {
        std::vector<std::string> defines = {"FS_IMPORTANCE_WIDTH " + std::to_string(width),
                                            "FS_MAX_VERTICES " + std::to_string(vertices)};
        if (!options_.double_precision_scan) defines.push_back("FS_SCAN_FLOAT");
        if (options_.weighting == FsWeighting::adaptive_blocks)
            defines.push_back("FS_ADAPTIVE");
        else if (options_.merge_samples_per_texel)
            defines.push_back("FS_MERGE");
        sampler_program_ = shaders_.build(
            {{GL_VERTEX_SHADER, "fs_sampler.vert"}, {GL_GEOMETRY_SHADER, "fs_sampler.geom"}}, defines, {"fs_texel"});
        sampler_program_width_ = width;
        sampler_program_vertices_ = vertices;
    }
    return sampler_program_;
}

void FsSampler::prepare(const gl::Texture& environment, const FsSampleRequest& request) {
    const int samples = request.samples;
    // One texel may take all M samples: its multiplicity must fit the packed sample.
    if (samples < 1 || samples > kFsMaxMultiplicity)
        throw UsageError("Floyd-Steinberg GPU sampler: " + std::to_string(samples) + " samples asked, 1.." +
                         std::to_string(kFsMaxMultiplicity) + " allowed");
    const bool native = options_.importance_width == 0 && options_.importance_height == 0;
    int width = native ? environment.width() : options_.importance_width;
    int height = native ? environment.height() : options_.importance_height;
    if (options_.weighting == FsWeighting::adaptive_blocks) {
        const int rows = request.upper_hemisphere ? (environment.height() + 1) / 2 : environment.height();
        // The importance texel is a whole block: where fs's blocks do not divide the map (a map of no
        // power-of-two size), the largest power of two below them that does.
        int block = fs_block_size(environment.width(), rows, samples);
        while (environment.width() % block != 0 || environment.height() % block != 0) block /= 2;
        width = environment.width() / block;
        height = environment.height() / block;
    }
    const bool unrolled = options_.weighting == FsWeighting::adaptive_blocks || width % size::fs_scan_run == 0;
    if (width < 1 || height < 1 || !unrolled || width > environment.width() || height > environment.height() ||
        width * height > kFsMaxTexels)  // texel indices are packed into fs_texel_bits (glsl/fs_common.glsl)
        throw UsageError("Floyd-Steinberg GPU sampler: importance map of " + std::to_string(width) + "x" +
                         std::to_string(height) + " for an environment of " + std::to_string(environment.width()) +
                         "x" + std::to_string(environment.height()) +
                         " (it may not be larger, nor above 2048x1024, and its width must be a multiple of 16)");
    if (importance_.width() != width || importance_.height() != height) {
        importance_ = gl::Texture::create_2d(GL_R32F, width, height);
        radiance_ = gl::Texture::create_2d(GL_RGBA32F, width, height);
        moments_ = gl::Texture::create_2d(GL_RGBA32F, width, height);
        row_sums_ = gl::Buffer::create(sizeof(double) * size_t(height));
        nearest_light_ = gl::Buffer::create(sizeof(std::uint32_t) * size_t(width) * size_t(height));
    }
    const int capacity = fs_capacity(samples);
    if (capacity > capacity_) {
        samples_ = gl::Buffer::create(sizeof(std::uint32_t) * size_t(capacity));
        lights_ = gl::Buffer::create(sizeof(FsGpuLight) * size_t(capacity));
        sites_ = gl::Buffer::create(sizeof(glm::vec4) * size_t(capacity));
        feedback_.attach(0, samples_);
    }
    capacity_ = std::max(capacity_, capacity);
}

void FsSampler::sample(const gl::Texture& environment, const FsSampleRequest& request, gl::GpuTimer* timer) {
    prepare(environment, request);
    const int width = importance_.width(), height = importance_.height();
    const int hardware_vertices = limits_.vertices_per_invocation();
    const int vertices = options_.vertices_per_invocation > 0
                             ? std::min(options_.vertices_per_invocation, hardware_vertices)
                             : hardware_vertices;
    const int capacity = fs_capacity(request.samples);
    invocations_ = (capacity + vertices - 1) / vertices;
    const gl::Program& sampler = sampler_program(width, std::min(vertices, capacity));
    const int scan_rows = fs_scan_rows(height, environment.height(), request.upper_hemisphere);

    {
        gl::ScopedPass pass(timer, "fs importance");
        importance_program_.use();
        glUniform1i(loc::upper_hemisphere, request.upper_hemisphere ? 1 : 0);
        environment.bind(unit::environment);
        glBindSampler(unit::environment, 0);
        glBindImageTexture(image::importance, importance_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
        glBindImageTexture(image::radiance, radiance_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        glBindImageTexture(image::moments, moments_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::fs_row_sums, row_sums_.id());
        glDispatchCompute(1, GLuint(height), 1);
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    }
    {
        gl::ScopedPass pass(timer, "fs sampler");
        sampler.use();
        glUniform1i(loc::expected_samples, request.samples);
        glUniform1i(loc::capacity, capacity);
        const FsDiffusionWeights weights = fs_diffusion_weights(options_.weighting, request.samples, width, scan_rows);
        glUniform3d(loc::weights, weights.next, weights.below, weights.below_next);
        glUniform1i(loc::scan_rows, scan_rows);
        importance_.bind(unit::importance);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::fs_row_sums, row_sums_.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::fs_counts, counts_.id());
        GLint previous_framebuffer = 0;
        glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &previous_framebuffer);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, no_attachments_.id());
        glEnable(GL_RASTERIZER_DISCARD);
        empty_vao_.bind();
        feedback_.bind();
        glBeginTransformFeedback(GL_POINTS);
        glDrawArrays(GL_POINTS, 0, invocations_);  // one point per slice of the sample ordinals
        glEndTransformFeedback();
        glBindTransformFeedback(GL_TRANSFORM_FEEDBACK, 0);
        glDisable(GL_RASTERIZER_DISCARD);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(previous_framebuffer));
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }
    {
        gl::ScopedPass pass(timer, "fs lights");
        lights_program_.use();
        glUniformMatrix3fv(loc::world_from_map, 1, GL_FALSE, &request.world_from_map[0][0]);
        glUniform1f(loc::radiance_scale, request.radiance_scale);
        glUniform1f(loc::sampled_solid_angle, float((request.upper_hemisphere ? 2.0 : 4.0) * std::numbers::pi));
        radiance_.bind(unit::radiance);
        moments_.bind(unit::moments);
        glBindSampler(unit::radiance, 0);
        glBindSampler(unit::moments, 0);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::fs_samples, samples_.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::fs_counts, counts_.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::fs_lights, lights_.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::fs_sites, sites_.id());
        glDispatchCompute(GLuint((capacity + size::fs_work_group - 1) / size::fs_work_group), 1, 1);
        // Consumers read the lights from shaders, the count as an indirect command or a copy source.
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    }
    if (options_.light_model == FsLightModel::cells) {
        gl::ScopedPass pass(timer, "fs cells");
        cell_assign_program_.use();
        glUniform1i(loc::scan_rows, scan_rows);
        radiance_.bind(unit::radiance);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::fs_counts, counts_.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::fs_sites, sites_.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::fs_nearest, nearest_light_.id());
        glDispatchCompute(GLuint((width * scan_rows + size::fs_work_group - 1) / size::fs_work_group), 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        cell_integrate_program_.use();
        glUniformMatrix3fv(loc::world_from_map, 1, GL_FALSE, &request.world_from_map[0][0]);
        glUniform1f(loc::radiance_scale, request.radiance_scale);
        glUniform1i(loc::scan_rows, scan_rows);
        radiance_.bind(unit::radiance);
        moments_.bind(unit::moments);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::fs_lights, lights_.id());
        glDispatchCompute(GLuint(capacity), 1, 1);  // one work group per light; those past the count return
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    }
    glBindVertexArray(0);
    glUseProgram(0);
}

FsCounts FsSampler::read_counts() const {
    FsCounts counts;
    glGetNamedBufferSubData(counts_.id(), 0, sizeof(counts), &counts);
    return counts;
}

std::vector<Cell> FsSampler::read_lights() const {
    const FsCounts counts = read_counts();
    std::vector<FsGpuLight> lights(counts.light_count);
    if (!lights.empty())
        glGetNamedBufferSubData(lights_.id(), 0, GLsizeiptr(sizeof(FsGpuLight) * lights.size()), lights.data());
    std::vector<Cell> cells;
    cells.reserve(lights.size());
    for (const FsGpuLight& light : lights)
        cells.push_back(
            {light.direction, light.radiance, light.solid_angle, light.cos_radius, light.cos_radius_weighted});
    return cells;
}

std::vector<FsSampler::Sample> FsSampler::read_samples() const {
    const FsCounts counts = read_counts();
    std::vector<std::uint32_t> packed(counts.light_count);
    if (!packed.empty())
        glGetNamedBufferSubData(samples_.id(), 0, GLsizeiptr(sizeof(std::uint32_t) * packed.size()), packed.data());
    std::vector<Sample> samples;
    samples.reserve(packed.size());
    const int width = importance_.width();
    for (std::uint32_t p : packed) {  // glsl/fs_common.glsl fs_pack_sample
        const int texel = int(p & std::uint32_t(kFsMaxTexels - 1));
        samples.push_back({{texel % width, texel / width}, int(p >> size::fs_texel_bits)});
    }
    return samples;
}

}  // namespace envshadow::render
