// The Floyd-Steinberg GPU sampler (engine/render/fs_sampler.h) against a double-precision scan written
// from the paper (fs_reference.h) and against the CPU method fs (engine/env): the same samples on the
// same importance map, on builtin:sky, an analytic sky and the blender-data city photograph, M = 32,
// 64, 128; split invocations; the lights it makes; the GPU path consumed without a read-back;
// builtin:sky's sun moving with the time of day.
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "env/environment.h"
#include "env/importance.h"
#include "env/sites.h"
#include "fs_reference.h"
#include "gl_fixture.h"
#include "render/embedded_shaders.h"
#include "render/fs_sampler.h"
#include "render/shader_interface.h"

namespace envshadow::testing {
namespace {

using FsSamplerTest = GlTest;
using render::FsSampler;
using render::FsSampleRequest;
using render::FsSamplerOptions;

// Samples in scan order must pair up one to one, each pair at most one texel apart and its
// multiplicity at most one apart (a rounding difference at a threshold crossing).
void expect_same_samples(const std::vector<FsSampler::Sample>& gpu, const std::vector<ReferenceSample>& reference,
                         const std::string& what) {
    ASSERT_EQ(gpu.size(), reference.size()) << what;
    int differing = 0;
    for (size_t k = 0; k < gpu.size(); ++k) {
        const glm::ivec2 d = glm::abs(gpu[k].texel - reference[k].texel);
        const int dm = std::abs(gpu[k].multiplicity - reference[k].multiplicity);
        EXPECT_LE(std::max(d.x, d.y), 1) << what << ": sample " << k << " at (" << gpu[k].texel.x << ", "
                                         << gpu[k].texel.y << "), reference (" << reference[k].texel.x << ", "
                                         << reference[k].texel.y << ")";
        EXPECT_LE(dm, 1) << what << ": sample " << k;
        differing += d != glm::ivec2(0) || dm != 0;
    }
    EXPECT_LE(differing, int(gpu.size()) / 8 + 1) << what;  // rare: rounding at a threshold crossing
}

std::vector<double> read_importance(const FsSampler& sampler) {
    const glm::ivec2 size = sampler.importance_size();
    std::vector<float> texels(size_t(size.x) * size.y);
    glGetTextureImage(sampler.importance().id(), 0, GL_RED, GL_FLOAT, GLsizei(texels.size() * sizeof(float)),
                      texels.data());
    return {texels.begin(), texels.end()};
}

struct Rules {
    const char* name;
    render::FsWeighting weighting;
    bool merge;
};
// Listing 1.1 exactly, and the rules for an importance map of a chosen size (docs/FS_GPU.md).
constexpr Rules kListing{"listing", render::FsWeighting::listing, false};
constexpr Rules kWarmupMatched{"warmup-matched", render::FsWeighting::warmup_matched, true};

// The sampler at a chosen importance resolution (the default is the CPU method's blocks instead).
FsSamplerOptions at_size(int width, int height, int vertices_per_invocation = 0) {
    return {width, height, vertices_per_invocation, render::FsWeighting::warmup_matched};
}

// The GPU sampler on `environment` against the reference scan for M = 32, 64, 128. The reference scans
// the importance map the GPU built (both scan the same map), after that map has been checked against
// `expected_importance` computed here in double.
void expect_reference_samples(const gl::ShaderLibrary& shaders, const gl::Texture& environment,
                              const std::vector<double>& expected_importance, int width, int height,
                              FsSamplerOptions options, const std::string& what) {
    for (const Rules& rules : {kListing, kWarmupMatched}) {
        options.weighting = rules.weighting;
        options.merge_samples_per_texel = rules.merge;
        FsSampler sampler(shaders, options);
        for (int samples : {32, 64, 128}) {
            const std::string name = what + " " + rules.name + " M=" + std::to_string(samples);
            sampler.sample(environment, FsSampleRequest{samples});
            const std::vector<FsSampler::Sample> gpu = sampler.read_samples();
            ASSERT_EQ(sampler.importance_size(), glm::ivec2(width, height)) << name;
            const render::FsCounts counts = sampler.read_counts();
            EXPECT_EQ(counts.rows_scanned, std::uint32_t(height)) << name;
            const std::vector<double> importance = read_importance(sampler);
            for (size_t t = 0; t < importance.size(); ++t)
                ASSERT_NEAR(importance[t], expected_importance[t], 1e-5 * expected_importance[t] + 1e-12)
                    << name << " texel " << t;

            const DiffusionWeights weights = rules.weighting == render::FsWeighting::listing
                                                 ? kListingWeights
                                                 : warmup_matched_weights(samples, width, height);
            const auto reference = reference_floyd_steinberg(importance, width, height, samples, weights, rules.merge);
            expect_same_samples(gpu, reference, name);
            EXPECT_EQ(counts.samples, std::uint32_t(total_samples(reference))) << name;
            EXPECT_LE(total_samples(reference), samples + 1) << name;
            // Listing 1.1's weights lose samples at the end of the scan (docs/FS_GPU.md); the
            // warm-up-matched ones keep most of them.
            if (rules.weighting == render::FsWeighting::warmup_matched) {
                EXPECT_GE(total_samples(reference), 0.85 * samples) << name;
            }
        }
    }
}

TEST_P(FsSamplerTest, GeometryLimitsAllowAtLeastTheGlMinimumPerInvocation) {
    const render::FsGeometryLimits limits = render::query_geometry_limits();
    EXPECT_GE(limits.max_output_vertices, 256);  // GL 4.5 minimums
    EXPECT_GE(limits.max_total_output_components, 1024);
    // One component per sample: the component budget does not cut the vertex budget.
    EXPECT_EQ(limits.vertices_per_invocation(), limits.max_output_vertices);
}

TEST_P(FsSamplerTest, ImportanceMapIsLuminanceTimesSolidAngleSummedOverTheBlock) {
    const EnvironmentMap fine = analytic_sky(512, sun_at(0.5, 1.0));
    FsSampler sampler(render::embedded_shaders(), at_size(128, 64));
    sampler.sample(upload(fine), FsSampleRequest{64});
    const std::vector<double> gpu = read_importance(sampler);
    const std::vector<double> expected = importance_map(downsample(fine, 128, 64));
    double sum = 0.0;
    for (size_t t = 0; t < gpu.size(); ++t) {
        EXPECT_NEAR(gpu[t], expected[t], 1e-5 * expected[t] + 1e-12) << "texel " << t;
        sum += expected[t];
    }
    EXPECT_NEAR(sampler.read_counts().importance_sum, sum, 1e-5 * sum);
}

TEST_P(FsSamplerTest, SameSamplesAsTheReferenceScanOnAnAnalyticSky) {
    const EnvironmentMap sky = analytic_sky(256, sun_at(0.6, 2.0));
    expect_reference_samples(render::embedded_shaders(), upload(sky), importance_map(sky), 256, 128,
                             FsSamplerOptions{256, 128}, "sky 256x128");
}

TEST_P(FsSamplerTest, SameSamplesAsTheReferenceScanOnBuiltinSky) {
    const EnvironmentMap sky = load_environment("builtin:sky:width=256");
    expect_reference_samples(render::embedded_shaders(), upload(sky), importance_map(sky), 256, 128,
                             FsSamplerOptions{256, 128}, "builtin:sky 256x128");
}

TEST_P(FsSamplerTest, SameSamplesAsTheReferenceScanOnCityAtFullResolution) {
    const EnvironmentMap city = city_map();
    ASSERT_EQ(city.width, 1024);
    // 0 x 0: the environment's own resolution.
    expect_reference_samples(render::embedded_shaders(), upload(city), importance_map(city), 1024, 512,
                             FsSamplerOptions{0, 0}, "city 1024x512");
}

TEST_P(FsSamplerTest, SameSamplesAsTheReferenceScanOnCityDownsampledOnTheGpu) {
    EXPECT_EQ(FsSamplerOptions{}.importance_width, 256);  // the default size, where a size is used
    EXPECT_EQ(FsSamplerOptions{}.importance_height, 128);
    EXPECT_EQ(FsSamplerOptions{}.weighting, render::FsWeighting::adaptive_blocks);  // the default: fs's blocks
    EXPECT_EQ(FsSamplerOptions{}.light_model, render::FsLightModel::cells);
    const EnvironmentMap city = city_map();
    expect_reference_samples(render::embedded_shaders(), upload(city), importance_map(downsample(city, 256, 128)), 256,
                             128, at_size(256, 128), "city 1024x512 -> 256x128");
}

// The CPU method's rules (FsWeighting::adaptive_blocks) against their transcription: same blocks in
// the same order, directions at the blocks' importance-weighted means.
void expect_adaptive_block_samples(const gl::ShaderLibrary& shaders, const EnvironmentMap& map,
                                   const std::string& what) {
    FsSamplerOptions options;
    options.weighting = render::FsWeighting::adaptive_blocks;
    options.light_model = render::FsLightModel::estimator;  // each light at its sample's block
    FsSampler sampler(shaders, options);
    const gl::Texture environment = upload(map);
    for (int samples : {32, 64, 128}) {
        const std::string name = what + " adaptive blocks M=" + std::to_string(samples);
        sampler.sample(environment, FsSampleRequest{samples});
        const int block = block_size(map.width, map.height, samples);
        ASSERT_EQ(sampler.importance_size(), glm::ivec2(map.width / block, map.height / block)) << name;
        EXPECT_EQ(sampler.read_counts().rows_scanned, std::uint32_t(map.height / block)) << name;
        const std::vector<FsSampler::Sample> gpu = sampler.read_samples();
        const std::vector<Cell> lights = sampler.read_lights();
        const std::vector<BlockSample> reference = reference_adaptive_blocks(map, samples);
        ASSERT_EQ(gpu.size(), reference.size()) << name;
        EXPECT_GE(double(reference.size()), 0.9 * samples) << name;
        int differing = 0;
        for (size_t k = 0; k < gpu.size(); ++k) {
            const glm::ivec2 d = glm::abs(gpu[k].texel - reference[k].block);
            EXPECT_LE(std::max(d.x, d.y), 1) << name << ": sample " << k;
            EXPECT_EQ(gpu[k].multiplicity, 1) << name;
            if (d == glm::ivec2(0)) {  // the same block: the same mean direction, to float precision
                EXPECT_GT(glm::dot(glm::dvec3(lights[k].direction), reference[k].direction), 1.0 - 1e-9 - 1e-6) << name;
            } else {
                ++differing;
            }
        }
        EXPECT_LE(differing, int(gpu.size()) / 8 + 1) << name;
    }
}

TEST_P(FsSamplerTest, CpuMethodRulesGiveTheSameBlocksOnAnAnalyticSky) {
    expect_adaptive_block_samples(render::embedded_shaders(), analytic_sky(1024, sun_at(0.6, 2.0)), "sky 1024x512");
}

TEST_P(FsSamplerTest, CpuMethodRulesGiveTheSameBlocksOnCity) {
    expect_adaptive_block_samples(render::embedded_shaders(), city_map(), "city 1024x512");
}

// Angle between directions, accurate near 0 (acos of a dot product near 1 is not: a float unit vector's
// length error of 6e-8 alone reads as 3.5e-4 rad).
double angle_between(glm::dvec3 a, glm::dvec3 b) {
    a = glm::normalize(a);
    b = glm::normalize(b);
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

// The CPU method fs itself (engine/env sites_floyd_steinberg) and the GPU in its mode: the same number
// of samples, in the same order, each at the same block's mean direction (to float precision; a
// decision moved by rounding would put a sample a block away).
void expect_cpu_method_samples(const gl::ShaderLibrary& shaders, const std::string& spec) {
    const EnvironmentMap map = load_environment(spec);
    const ImportanceMap importance = build_importance(map);
    FsSamplerOptions options;
    options.weighting = render::FsWeighting::adaptive_blocks;
    options.light_model = render::FsLightModel::estimator;  // each light at its sample's block
    FsSampler sampler(shaders, options);
    const gl::Texture environment = upload(map);
    for (int samples : {32, 64, 128}) {
        const std::string name = spec + " M=" + std::to_string(samples);
        const std::vector<glm::dvec3> cpu = sites_floyd_steinberg(importance, samples).sites;
        sampler.sample(environment, FsSampleRequest{samples});
        const std::vector<Cell> gpu = sampler.read_lights();
        ASSERT_EQ(gpu.size(), cpu.size()) << name;
        const double block_angle = std::numbers::pi / sampler.importance_size().y;
        for (size_t k = 0; k < gpu.size(); ++k)
            EXPECT_LT(angle_between(glm::dvec3(gpu[k].direction), cpu[k]), 1e-4 * block_angle)
                << name << ": sample " << k;
    }
}

TEST_P(FsSamplerTest, SameSamplesAsTheCpuMethodOnBuiltinSky) {
    expect_cpu_method_samples(render::embedded_shaders(), "builtin:sky");
}

TEST_P(FsSamplerTest, SameSamplesAsTheCpuMethodOnCity) {
    expect_cpu_method_samples(render::embedded_shaders(), kCityExr);
}

// The default (the CPU method's blocks) on a map its blocks do not divide: 1000 x 500 at M = 64 has fs's
// blocks of 8 x 8, and 500 is no multiple of 8, so the importance texels are 4 x 4 blocks. The lights
// are still cells of the whole map: their luminance sums to S and their solid angles to 4 pi.
TEST_P(FsSamplerTest, BlocksThatDoNotDivideTheMapAreHalvedUntilTheyDo) {
    const EnvironmentMap sky = analytic_sky(1000, sun_at(0.5, 1.0));
    ASSERT_EQ(sky.height, 500);
    FsSampler sampler(render::embedded_shaders());
    sampler.sample(upload(sky), FsSampleRequest{64});
    EXPECT_EQ(sampler.importance_size(), glm::ivec2(250, 125));
    const render::FsCounts counts = sampler.read_counts();
    const std::vector<Cell> lights = sampler.read_lights();
    EXPECT_GE(lights.size(), 48u);
    double luminance = 0.0, solid_angle = 0.0;
    for (const Cell& light : lights) {
        luminance += latlong::luminance(glm::dvec3(light.radiance));
        solid_angle += light.solid_angle;
    }
    EXPECT_NEAR(luminance, counts.importance_sum, 1e-3 * counts.importance_sum);
    EXPECT_NEAR(solid_angle, 4.0 * std::numbers::pi, 1e-3);
}

// The listing's weights spread the error so thinly when M is far below the texel count that most of
// it never becomes a sample (the warm-up of Szirmay-Kalos et al. §1.3.1); the warm-up-matched ones do not.
TEST_P(FsSamplerTest, ListingWeightsLoseMostSamplesOnCityWhereWarmUpMatchedKeepThem) {
    const gl::Texture environment = upload(city_map());
    FsSampler listing(render::embedded_shaders(), FsSamplerOptions{0, 0, 0, render::FsWeighting::listing, true, false});
    FsSampler matched(render::embedded_shaders(), at_size(0, 0));
    listing.sample(environment, FsSampleRequest{64});
    matched.sample(environment, FsSampleRequest{64});
    EXPECT_LT(listing.read_counts().samples, 32u);
    EXPECT_GE(matched.read_counts().samples, 56u);
}

TEST_P(FsSamplerTest, SplittingTheScanOverInvocationsGivesTheSameSamples) {
    const gl::Texture environment = upload(downsample(city_map(), 256, 128));
    FsSampler whole(render::embedded_shaders(), at_size(256, 128));
    FsSampler split(render::embedded_shaders(), at_size(256, 128, /*vertices_per_invocation=*/7));
    whole.sample(environment, FsSampleRequest{64});
    split.sample(environment, FsSampleRequest{64});
    EXPECT_EQ(whole.invocations(), 1);
    EXPECT_EQ(split.invocations(), (render::fs_capacity(64) + 6) / 7);
    const auto expected = whole.read_samples(), samples = split.read_samples();
    ASSERT_EQ(samples.size(), expected.size());
    ASSERT_GT(samples.size(), 7u);  // more than one slice was used
    for (size_t k = 0; k < samples.size(); ++k) {
        EXPECT_EQ(samples[k].texel, expected[k].texel) << k;
        EXPECT_EQ(samples[k].multiplicity, expected[k].multiplicity) << k;
    }
    EXPECT_EQ(split.read_counts().lights_found, split.read_counts().light_count);
}

TEST_P(FsSamplerTest, LightsCarryTheirShareOfSTheTexelColourAndTheirCaps) {
    const EnvironmentMap sky = analytic_sky(256, sun_at(0.4, -1.0));
    FsSampler sampler(render::embedded_shaders(), FsSamplerOptions{.importance_width = 256,
                                                                   .importance_height = 128,
                                                                   .weighting = render::FsWeighting::warmup_matched,
                                                                   .light_model = render::FsLightModel::estimator});
    const glm::mat3 world_from_map = glm::mat3(glm::rotate(glm::mat4(1.0f), 0.7f, glm::vec3(0.0f, 1.0f, 0.0f)));
    const float exposure = 0.5f;
    sampler.sample(upload(sky), FsSampleRequest{100, world_from_map, exposure});

    const std::vector<Cell> lights = sampler.read_lights();
    const std::vector<FsSampler::Sample> samples = sampler.read_samples();
    const std::vector<double> importance = importance_map(sky);
    double sum = 0.0;
    for (double value : importance) sum += value;
    ASSERT_EQ(samples.size(), lights.size());
    int total = 0;
    for (const FsSampler::Sample& s : samples) total += s.multiplicity;
    EXPECT_EQ(std::uint32_t(total), sampler.read_counts().samples);
    EXPECT_LE(total, 101);
    EXPECT_GE(total, 85);
    EXPECT_LT(lights.size(), size_t(total));  // the sun took several samples as one light

    const double pi = std::numbers::pi;
    double luminance_total = 0.0;
    int sun_lights = 0;
    for (size_t k = 0; k < lights.size(); ++k) {
        const Cell& light = lights[k];
        const glm::ivec2 t = samples[k].texel;
        const double share = double(samples[k].multiplicity) / total;
        const glm::dvec3 expected_direction = glm::dmat3(world_from_map) * latlong::texel_direction(t.x, t.y, 256, 128);
        EXPECT_GT(glm::dot(glm::dvec3(light.direction), expected_direction), 1.0 - 1e-6) << k;
        // Luminance m S / K, in the texel's colour.
        const glm::dvec3 texel = sky.at(t.x, t.y);
        const glm::dvec3 expected_radiance = texel * (exposure * sum * share / latlong::luminance(texel));
        EXPECT_LT(glm::length(glm::dvec3(light.radiance) - expected_radiance), 1e-5 * glm::length(expected_radiance))
            << k;
        EXPECT_NEAR(light.solid_angle, 4.0 * pi * share, 1e-6);
        EXPECT_NEAR(light.cos_radius, 1.0 - 2.0 * share, 1e-6);
        // The radiance-weighted cap: the solid angle over which this texel's radiance carries the
        // light's share of S, at most the light's solid angle.
        const double texel_solid_angle = latlong::texel_solid_angle(t.y, 256, 128);
        const double local =
            std::min(4.0 * pi * share, sum * share * texel_solid_angle / importance[size_t(t.y) * 256 + t.x]);
        EXPECT_NEAR(light.cos_radius_weighted, 1.0 - local / (2.0 * pi), 1e-5) << k;
        if (samples[k].multiplicity > 3) {
            ++sun_lights;  // a sun: a cap no larger than about its texel
            EXPECT_LT(local, 2.0 * texel_solid_angle) << k;
        }
        luminance_total += latlong::luminance(glm::dvec3(light.radiance));
    }
    EXPECT_GE(sun_lights, 1);
    EXPECT_NEAR(luminance_total, exposure * sum, 1e-5 * sum);  // luminance is conserved
}

// The renderer's path: light and count buffers bound as storage buffers, nothing read back in between.
TEST_P(FsSamplerTest, ShadersConsumeTheLightBufferWithTheCountFromTheGpu) {
    FsSampler sampler(render::embedded_shaders(), FsSamplerOptions{256, 128});
    sampler.sample(upload(analytic_sky(256, sun_at(0.3, 0.3))), FsSampleRequest{77});

    gl::ShaderLibrary shaders = render::embedded_shaders();
    shaders.add("fs_test_consumer.comp", R"(#version 450 core
#include "fs_common.glsl"
layout(local_size_x = 1) in;
layout(std430, binding = BINDING_FS_COUNTS) readonly buffer FsCounts { FS_COUNTS_MEMBERS };
layout(std430, binding = BINDING_FS_LIGHTS) readonly buffer FsLights { FsLight fs_lights[]; };
layout(std430, binding = 3) writeonly buffer Result { vec4 radiance_sum; uint lights_seen; };
void main() {
    vec3 sum = vec3(0.0);
    for (uint k = 0; k < light_count; ++k) sum += fs_lights[k].radiance;
    radiance_sum = vec4(sum, 0.0);
    lights_seen = light_count;
}
)");
    const gl::Program consumer = shaders.build({{GL_COMPUTE_SHADER, "fs_test_consumer.comp"}});
    gl::Buffer result = gl::Buffer::create(32);
    consumer.use();
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, render::shader::binding::fs_counts, sampler.count_buffer().id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, render::shader::binding::fs_lights, sampler.light_buffer().id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, result.id());
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    struct {
        glm::vec4 radiance_sum;
        std::uint32_t lights_seen;
    } seen{};
    glGetNamedBufferSubData(result.id(), 0, sizeof(glm::vec4) + sizeof(std::uint32_t), &seen);

    const std::vector<Cell> lights = sampler.read_lights();
    glm::dvec3 expected(0.0);
    for (const Cell& light : lights) expected += glm::dvec3(light.radiance);
    EXPECT_GT(lights.size(), 30u);
    EXPECT_EQ(seen.lights_seen, lights.size());
    EXPECT_NEAR(seen.radiance_sum.r, expected.r, 1e-5 * expected.r);
    EXPECT_NEAR(seen.radiance_sum.b, expected.b, 1e-5 * expected.b);
}

// Dynamic environments: the lights are regenerated from each frame's texture. builtin:sky's sun moves
// with the time of day; the brightest light must be at the sun each time.
TEST_P(FsSamplerTest, BrightestLightFollowsBuiltinSkysSun) {
    FsSampler sampler(render::embedded_shaders(), FsSamplerOptions{256, 128});
    SkyParameters morning, afternoon;
    morning.time_hours = 9.0;
    afternoon.time_hours = 15.0;
    ASSERT_LT(glm::dot(envshadow::sun_direction(morning), envshadow::sun_direction(afternoon)), std::cos(0.5));
    const double texel = std::numbers::pi / 128;
    for (const SkyParameters& sky : {morning, afternoon}) {
        const std::string spec = "builtin:sky:time=" + std::to_string(sky.time_hours);
        sampler.sample(upload(load_environment(spec)), FsSampleRequest{64});
        const std::vector<Cell> lights = sampler.read_lights();
        ASSERT_FALSE(lights.empty());
        const Cell* brightest = &lights[0];
        for (const Cell& light : lights)
            if (latlong::luminance(light.radiance) > latlong::luminance(brightest->radiance)) brightest = &light;
        EXPECT_GT(glm::dot(glm::dvec3(brightest->direction), envshadow::sun_direction(sky)), std::cos(1.5 * texel))
            << spec;
    }
}

ENVSHADOW_INSTANTIATE_GL_TEST(FsSamplerTest);

}  // namespace
}  // namespace envshadow::testing
