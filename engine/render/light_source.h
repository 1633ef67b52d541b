#pragma once
// Where the renderer's lights come from: the cells of a decomposition made once at load time
// (engine/env), or Floyd-Steinberg samples of the environment texture drawn on the GPU every frame
// (render/fs_sampler.h, docs/FS_GPU.md), which follow a rotated, swapped or animated map at once.
// `envshadow render`, `bench` and the viewer drive both the same way:
//
//   LightSource lights = make_light_source(light_method(name), map, count, seed);
//   lights.attach(renderer);        // the cells; nothing for a per-frame source
//   for (each frame) {
//       lights.update(renderer);    // per frame: sample the renderer's environment texture now
//       renderer.render(time, view);
//   }
#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "env/cells.h"
#include "env/environment.h"
#include "render/fs_sampler.h"

namespace envshadow::render {

class Renderer;

enum class LightSourceKind {
    cells,   // a decomposition at load time (env/cells.h)
    gpu_fs,  // Floyd-Steinberg samples made on the GPU every frame
};

// A way to make the lights, as the command line and the viewer name it.
struct LightMethod {
    LightSourceKind kind = LightSourceKind::cells;
    Method decomposition = Method::lloyd;  // the method of `cells`; gpu_fs: Method::fs, its CPU twin
    std::string_view help;                 // a few words on what it is
    std::string_view name() const;         // to_string(decomposition), or "fs-gpu"
};

// Every method: the decompositions in env/cells.h kMethodNames order, then the GPU sampler.
std::span<const LightMethod> light_methods();
// The method called `name`; UsageError listing the names for anything else.
const LightMethod& light_method(std::string_view name);
// The method of `kind` (with `decomposition` for cells).
const LightMethod& light_method(LightSourceKind kind, Method decomposition);

class LightSource {
public:
    // The cells of `decomposition` (map space), handed to the renderer as they are.
    explicit LightSource(Decomposition decomposition);
    // `lights` samples (1..kMaxLights) of the renderer's environment texture every frame. A GL 4.5
    // context must be current; PlatformError where the GL cannot run the sampler.
    // With Hemisphere::upper only the directions above the horizon are sampled (a scene with a ground).
    LightSource(int lights, FsSamplerOptions options, Hemisphere hemisphere = Hemisphere::full);
    ~LightSource();
    LightSource(LightSource&&) noexcept;
    LightSource& operator=(LightSource&&) noexcept;

    LightSourceKind kind() const { return kind_; }
    Hemisphere hemisphere() const { return per_frame() ? hemisphere_ : decomposition_.hemisphere; }
    bool per_frame() const { return kind_ == LightSourceKind::gpu_fs; }
    const LightMethod& method() const;

    // Before the first frame, and again after `renderer` was given other lights: the cells.
    // A per-frame source hands over nothing here.
    void attach(Renderer& renderer) const;
    // Before every frame: a per-frame source samples the renderer's environment texture now and hands
    // over the lights (waiting for the sampler: the light list stays on the CPU). Cells: nothing.
    void update(Renderer& renderer);

    // cells: the decomposition; gpu_fs: empty (Decomposition{}).
    const Decomposition& decomposition() const { return decomposition_; }
    // The lights handed over last: the cells, or the last update's samples (map space).
    const std::vector<Cell>& lights() const { return per_frame() ? sampled_ : decomposition_.cells; }

    // gpu_fs only (null for cells): the sampler, its counts and importance size after an update.
    const FsSampler* sampler() const { return sampler_.get(); }
    int requested_lights() const { return requested_; }
    // gpu_fs: the samples the next updates ask for (1..kMaxLights, UsageError otherwise).
    void set_requested_lights(int lights);
    // Wall time of the last update's sampling, from dispatch to the lights handed over (milliseconds).
    double sampling_ms() const { return sampling_ms_; }
    // Lights of the last update beyond kMaxLights, folded into the brightest kMaxLights (the scan can
    // find a few more lights than samples asked for).
    int lights_folded() const { return folded_; }

private:
    LightSourceKind kind_ = LightSourceKind::cells;
    Decomposition decomposition_;
    std::unique_ptr<FsSampler> sampler_;
    int requested_ = 0;
    Hemisphere hemisphere_ = Hemisphere::full;  // gpu_fs: what is sampled; cells: decomposition_.hemisphere
    std::vector<Cell> sampled_;
    double sampling_ms_ = 0.0;
    int folded_ = 0;
};

// `method` for `map`: a decomposition into `lights` cells with `seed` now (cells), or a GPU sampler of
// `lights` samples per frame (a GL context must be current; `fs_options` configure it).
// `hemisphere`: the whole sphere, or only the directions above the horizon (docs/DESIGN.md §3.1).
LightSource make_light_source(const LightMethod& method, const EnvironmentMap& map, int lights, std::uint64_t seed,
                              Hemisphere hemisphere = Hemisphere::full, const FsSamplerOptions& fs_options = {});

// At most kMaxLights of `lights`: the brightest, each scaled so that their sum keeps the radiance of
// all (the renderer's atlas and light buffer hold kMaxLights). Returns how many were folded in.
int fold_to_max_lights(std::vector<Cell>& lights);

}  // namespace envshadow::render
