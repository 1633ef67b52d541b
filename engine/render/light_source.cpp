#include "render/light_source.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <numeric>
#include <string>

#include "core/error.h"
#include "env/latlong.h"
#include "render/embedded_shaders.h"
#include "render/renderer.h"

namespace envshadow::render {
namespace {

constexpr std::array<LightMethod, 6> kLightMethods = {{
    {LightSourceKind::cells, Method::lloyd, "Lloyd relaxation of the importance (the default)"},
    {LightSourceKind::cells, Method::ccvt, "capacity-constrained Voronoi: equal importance per cell"},
    {LightSourceKind::cells, Method::mediancut, "median cut (N rounded down to a power of two)"},
    {LightSourceKind::cells, Method::random, "sites drawn at random by importance"},
    {LightSourceKind::cells, Method::fs, "Floyd-Steinberg samples of the importance"},
    {LightSourceKind::gpu_fs, Method::fs, "Floyd-Steinberg samples made on the GPU every frame"},
}};

}  // namespace

std::string_view LightMethod::name() const {
    return kind == LightSourceKind::gpu_fs ? "fs-gpu" : to_string(decomposition);
}

std::span<const LightMethod> light_methods() {
    return kLightMethods;
}

const LightMethod& light_method(std::string_view name) {
    std::string names;
    for (const LightMethod& method : kLightMethods) {
        if (method.name() == name) return method;
        names += (names.empty() ? "" : ", ") + std::string(method.name());
    }
    throw UsageError("unknown light method '" + std::string(name) + "' (" + names + ")");
}

const LightMethod& light_method(LightSourceKind kind, Method decomposition) {
    for (const LightMethod& method : kLightMethods)
        if (method.kind == kind && (kind == LightSourceKind::gpu_fs || method.decomposition == decomposition))
            return method;
    return kLightMethods.front();  // unreachable: every Method has its entry
}

LightSource::LightSource(Decomposition decomposition) : decomposition_(std::move(decomposition)) {}

LightSource::LightSource(int lights, FsSamplerOptions options, Hemisphere hemisphere)
    : kind_(LightSourceKind::gpu_fs), hemisphere_(hemisphere) {
    set_requested_lights(lights);
    sampler_ = std::make_unique<FsSampler>(embedded_shaders(), options);
}

void LightSource::set_requested_lights(int lights) {
    if (lights < 1 || lights > kMaxLights)
        throw UsageError("GPU sampler: " + std::to_string(lights) + " lights asked for, 1.." +
                         std::to_string(kMaxLights) + " allowed");
    requested_ = lights;
}

LightSource::~LightSource() = default;
LightSource::LightSource(LightSource&&) noexcept = default;
LightSource& LightSource::operator=(LightSource&&) noexcept = default;

const LightMethod& LightSource::method() const {
    return light_method(kind_, decomposition_.method);
}

void LightSource::attach(Renderer& renderer) const {
    if (!per_frame()) renderer.set_lights(decomposition_.cells);
}

void LightSource::update(Renderer& renderer) {
    if (!per_frame()) return;
    const auto start = std::chrono::steady_clock::now();
    sampler_->sample(renderer.environment_texture(),
                     FsSampleRequest{.samples = requested_, .upper_hemisphere = hemisphere_ == Hemisphere::upper});
    sampled_ = sampler_->read_lights();  // waits for the sampler
    folded_ = fold_to_max_lights(sampled_);
    renderer.set_lights(sampled_, Renderer::CellSpace::map, Renderer::LightLifetime::every_frame);
    sampling_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

LightSource make_light_source(const LightMethod& method, const EnvironmentMap& map, int lights, std::uint64_t seed,
                              Hemisphere hemisphere, const FsSamplerOptions& fs_options) {
    if (method.kind == LightSourceKind::gpu_fs) return LightSource(lights, fs_options, hemisphere);
    return LightSource(decompose(
        map,
        DecomposeOptions{.method = method.decomposition, .lights = lights, .seed = seed, .hemisphere = hemisphere}));
}

int fold_to_max_lights(std::vector<Cell>& lights) {
    const int folded = int(lights.size()) - kMaxLights;
    if (folded <= 0) return 0;
    auto radiance_sum = [](const std::vector<Cell>& cells) {
        return std::accumulate(cells.begin(), cells.end(), glm::dvec3(0.0),
                               [](glm::dvec3 sum, const Cell& c) { return sum + glm::dvec3(c.radiance); });
    };
    const glm::dvec3 all = radiance_sum(lights);
    std::stable_sort(lights.begin(), lights.end(), [](const Cell& a, const Cell& b) {
        return latlong::luminance(glm::dvec3(a.radiance)) > latlong::luminance(glm::dvec3(b.radiance));
    });
    lights.resize(std::size_t(kMaxLights));
    const glm::dvec3 kept = radiance_sum(lights);
    for (Cell& c : lights)
        for (int channel = 0; channel < 3; ++channel)
            if (kept[channel] > 0.0)
                c.radiance[channel] = float(double(c.radiance[channel]) * all[channel] / kept[channel]);
    return folded;
}

}  // namespace envshadow::render
