#pragma once
// Floyd-Steinberg sampling of an environment texture on the GPU (Szirmay-Kalos, Szécsi, Penzov,
// Environment Mapping with Floyd-Steinberg Halftoning, §1.3, Listing 1.1; docs/DESIGN.md §5): lights regenerated from
// the texture every frame, without a CPU round trip, so the environment may rotate, change exposure, be swapped or
// animate. docs/FS_GPU.md has the design.
//
//   1. fs_importance.comp  environment texture -> importance map I = lum(sum L dw) at the chosen
//                          resolution (default 256 x 128), its row sums and each texel's
//                          importance-weighted direction;
//   2. fs_sampler.geom     one geometry-shader invocation scans the map (serpentine error diffusion,
//                          threshold S / 2M) and emits each sample's texel index into a transform
//                          feedback buffer; it writes K and S into the count buffer;
//   3. fs_lights.comp      one light per sample texel (m of the K samples): texel centroid,
//                          radiance of luminance m S / K in the texel's colour, a cap of solid angle
//                          m 4 pi / K;
//   4. with FsLightModel::cells (the default), fs_cell_assign.comp and fs_cell_integrate.comp replace
//                          each light's radiance, centre and caps by those of its nearest-light cell of
//                          the importance map.
#include <cstdint>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "env/cells.h"
#include "gl/objects.h"
#include "gl/shader.h"
#include "gl/timer.h"

namespace envshadow::render {

// The light buffer's element (glsl/fs_common.glsl FsLight, std430).
struct FsGpuLight {
    glm::vec3 direction;
    float solid_angle;
    glm::vec3 radiance;
    float cos_radius;
    float cos_radius_weighted;
    float unused[3];
};
static_assert(sizeof(FsGpuLight) == 48);

// The head of the count buffer (glsl/fs_common.glsl FS_COUNTS_MEMBERS, std430).
struct FsCounts {
    std::uint32_t light_count = 0;  // valid entries of the light buffer: min(lights_found, capacity)
    std::uint32_t samples = 0;      // K: the samples those lights carry (multiplicities summed)
    float importance_sum = 0.0f;    // S
    std::uint32_t capacity = 0;
    std::uint32_t rows_scanned = 0;  // fs_scan_rows unless the scan was cut short
    std::uint32_t lights_found = 0;  // above capacity: lights were dropped (K counts only those kept)
    std::uint32_t unused[2] = {};
};
static_assert(sizeof(FsCounts) == 32);

// What the GL implementation allows a geometry shader to emit (they differ: llvmpipe, NVIDIA, ...).
struct FsGeometryLimits {
    int max_output_vertices = 0;          // GL_MAX_GEOMETRY_OUTPUT_VERTICES
    int max_total_output_components = 0;  // GL_MAX_GEOMETRY_TOTAL_OUTPUT_COMPONENTS
    int max_storage_blocks = 0;           // GL_MAX_GEOMETRY_SHADER_STORAGE_BLOCKS (the count buffer)
    // Samples one invocation may emit: one uint component per sample.
    int vertices_per_invocation() const;
};
FsGeometryLimits query_geometry_limits();

// Error diffusion weights: the shares of a texel's error passed to the next texel along the scan,
// the texel below and the texel below the next.
struct FsDiffusionWeights {
    double next = 0.375, below = 0.375, below_next = 0.25;
};

enum class FsWeighting {
    // Listing 1.1's 3/8, 3/8, 1/4. With M far below the texel count N, a region of uniform importance
    // needs 5N / (16M) rows before its error reaches the threshold (the warm-up of Szirmay-Kalos et al.
    // §1.3.1): much of the importance never becomes a sample (K = 7 for M = 32 on city.exr at
    // 1024 x 512) and leaves the map at the last row. docs/FS_GPU.md has the measurements.
    listing,
    // The paper's remedy (§1.3.1: "the weight of the faster running coordinate should be increased"),
    // sized so that the warm-up in a uniform region, N (1 - next) / (2M) rows, is half the mean sample
    // spacing sqrt(N / M): next = 1 - sqrt(M / N) (at least 3/8); the rest split 3 : 2 between below
    // and below-next as in the listing.
    warmup_matched,
    // The CPU method fs's rules (engine/env, sites_floyd_steinberg), so that `fs` and `fs-gpu` give the
    // same samples: the environment in blocks of B x B texels (fs_block_size) as the importance map,
    // whatever importance_width/height say; the share along the row adapts per block,
    // clamp(1 - I / (S/M), 3/8, 15/16); no carry across rows, the diagonal wraps around the seam, the
    // last row passes everything along; one sample per texel (merge_samples_per_texel is ignored).
    adaptive_blocks,
};

// The CPU method fs's block size for M samples of a width x height map: a power of two, the largest that
// keeps at least 64 blocks per sample (engine/env/sites.h kBlocksPerSample). `height` is the rows
// decomposed: the map's, or with a ground those above the horizon (ceil(H / 2)), as fs counts them.
int fs_block_size(int width, int height, int samples);

// The weights `weighting` gives for M samples of a width x height importance map.
FsDiffusionWeights fs_diffusion_weights(FsWeighting weighting, int samples, int width, int height);

// What a light carries.
enum class FsLightModel {
    // The seed's estimator: luminance m S / K in the sample texel's colour, a cap of solid angle
    // m 4 pi / K. Its sum is S, but each light stands for an area it does not measure: with few samples
    // the image is as noisy as the samples (9.7% from `fs` on default.json at N = 64).
    estimator,
    // The nearest-sample cells of the importance map, each integrated as the CPU methods integrate
    // theirs (docs/DESIGN.md §3; fs_cell_assign.comp, fs_cell_integrate.comp): L~ = sum L dw over the cell,
    // centre, both caps. Energy is conserved cell by cell, as with `fs`.
    cells,
};

struct FsSamplerOptions {
    // Importance map resolution (listing and warmup_matched; adaptive_blocks takes the CPU method's
    // blocks); 0 x 0 takes the environment's. Must not exceed it; the width must be a multiple of 16 (the
    // scan's unrolled runs).
    int importance_width = 256;
    int importance_height = 128;
    // Samples per geometry-shader invocation; 0 takes the most the GL limits allow. Smaller values
    // force the split into several invocations (tested).
    int vertices_per_invocation = 0;
    // The default: the CPU method's blocks and rules, which with FsLightModel::cells give the lights of
    // `fs` (0.5% apart on default.json, N = 64, where warmup_matched at 256 x 128 is 4.4% apart with
    // cells and the estimator 9.7%; docs/FS_GPU.md).
    FsWeighting weighting = FsWeighting::adaptive_blocks;
    // Accumulate the scan in double (matches a CPU scan in double to the texel) or float (faster where
    // doubles are slow; near-1D diffusion lets float rounding move a sample a few texels along a row).
    bool double_precision_scan = true;
    // Multi-level diffusion: a texel takes every sample its error reaches, as one light (a sun becomes
    // one light instead of a streak of them). false: one sample per texel, as Listing 1.1.
    bool merge_samples_per_texel = true;
    FsLightModel light_model = FsLightModel::cells;
};

// The sampler's wall time from dispatch to lights read back, as `bench` and the viewer list it beside
// the renderer's GPU passes.
inline constexpr const char* kFsSamplingPass = "fs-gpu sampling (wall)";

struct FsSampleRequest {
    int samples = 128;               // M, the number of samples wanted (1 .. shader::kFsMaxMultiplicity, 2047)
    glm::mat3 world_from_map{1.0f};  // applied to the lights; the default identity keeps map space
    float radiance_scale = 1.0f;     // exposure
    // A scene with a ground: only the environment above the horizon is sampled (docs/DESIGN.md §3.1): the
    // texels below it weigh nothing and the scan stops at the horizon (fs_scan_rows); each light's cap is
    // m 2 pi / K.
    bool upper_hemisphere = false;
};

class FsSampler {
public:
    // Compiles the stages from `shaders` (the project's glsl/ library; copied). Throws PlatformError when the
    // GL implementation cannot run the sampler (no storage blocks in geometry shaders).
    explicit FsSampler(const gl::ShaderLibrary& shaders, FsSamplerOptions options = {});

    // Regenerates the lights from `environment`: a lat-long float RGB(A) texture whose texel (i, j) is
    // map texel (i, j) (row 0 the zenith). Issues GPU work only; nothing waits. With `timer`, the three
    // passes are timed as "fs importance", "fs sampler", "fs lights" (and "fs cells").
    void sample(const gl::Texture& environment, const FsSampleRequest& request, gl::GpuTimer* timer = nullptr);

    // Valid after sample(), until the next sample(). Bind as shader storage buffers:
    //   light_buffer(): FsLight lights[capacity()] (std430, glsl/fs_common.glsl), the first
    //                   FsCounts::light_count valid, in scan order;
    //   count_buffer(): FsCounts at offset 0 (light_count first, so it can be copied into an
    //                   indirect draw's instance count with glCopyNamedBufferSubData).
    const gl::Buffer& light_buffer() const { return lights_; }
    const gl::Buffer& count_buffer() const { return counts_; }
    const gl::Buffer& sample_buffer() const { return samples_; }   // uint texel index per sample
    const gl::Texture& importance() const { return importance_; }  // r32f
    int capacity() const { return capacity_; }
    glm::ivec2 importance_size() const { return {importance_.width(), importance_.height()}; }
    int invocations() const { return invocations_; }  // geometry-shader invocations of the last sample()

    // Read back; these wait for the GPU.
    FsCounts read_counts() const;
    // The lights as cells in scan order, turned by the request's world_from_map. render, bench and view
    // keep the identity: map-space cells, which Renderer::set_lights rotates by the scene's rotation.
    std::vector<Cell> read_lights() const;
    struct Sample {
        glm::ivec2 texel;  // importance map texel (i, j)
        int multiplicity;  // samples on it
    };
    std::vector<Sample> read_samples() const;  // one per light, scan order

private:
    void prepare(const gl::Texture& environment, const FsSampleRequest& request);
    const gl::Program& sampler_program(int width, int vertices);

    gl::ShaderLibrary shaders_;  // a copy: the sampler program is rebuilt when the map's width changes
    FsSamplerOptions options_;
    FsGeometryLimits limits_;
    gl::Program importance_program_, lights_program_, sampler_program_, cell_assign_program_, cell_integrate_program_;
    int sampler_program_width_ = 0, sampler_program_vertices_ = 0;
    gl::Texture importance_, radiance_, moments_;
    gl::Buffer row_sums_, counts_, samples_, lights_, sites_, nearest_light_;
    gl::TransformFeedback feedback_;
    gl::VertexArray empty_vao_;
    gl::Framebuffer no_attachments_;  // draws need a complete framebuffer, even with rasterizer discard
    int capacity_ = 0, invocations_ = 0;
};

// The importance rows the scan visits: all `importance_height`, or with upper_hemisphere those holding
// environment rows above the horizon (half of them when both heights are even: the horizon is a row border).
int fs_scan_rows(int importance_height, int environment_height, bool upper_hemisphere);

// Capacity reserved for M wanted samples: the scan produces M give or take a few (the error left at
// the map's edges), so there is headroom.
int fs_capacity(int samples);

}  // namespace envshadow::render
