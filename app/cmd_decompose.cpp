// `envshadow decompose`: an environment map cut into N directional cells (DESIGN.md §3), written as
// the JSON of DESIGN.md §6 and, for people, as a picture of the map with the cells drawn over it.
#include <cstdio>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "core/atomic_file.h"
#include "core/image.h"
#include "core/log.h"
#include "env/cell_overlay.h"
#include "env/cells.h"
#include "env/environment.h"

namespace envshadow::app {
namespace {

struct DecomposeCommandOptions {
    std::string env, method = "lloyd", json, png;
    int lights = 128;
    std::uint64_t seed = 1;
    bool clamp_invalid = false;
};

nlohmann::json to_json(const Decomposition& d) {
    nlohmann::json lights = nlohmann::json::array();
    for (const Cell& c : d.cells)
        lights.push_back({{"dir", {c.direction.x, c.direction.y, c.direction.z}},
                          {"radiance", {c.radiance.r, c.radiance.g, c.radiance.b}},
                          {"solid_angle", c.solid_angle},
                          {"cos_radius", c.cos_radius},
                          {"cos_radius_weighted", c.cos_radius_weighted}});
    return {{"method", to_string(d.method)},
            {"width", d.width},
            {"height", d.height},
            {"lights", lights},
            {"integral", {d.integral.r, d.integral.g, d.integral.b}},
            {"seconds", d.seconds},
            {"iterations", d.iterations},
            {"final_movement", d.final_movement}};
}

int run_decompose(const DecomposeCommandOptions& o) {
    EnvironmentLoadReport report;
    const EnvironmentMap map = load_environment(o.env, EnvironmentLoadOptions{o.clamp_invalid}, &report);
    if (report.negative_clamped > 0)
        log::info(o.env + ": " + std::to_string(report.negative_clamped) + " negative texel components clamped to 0");
    if (report.invalid_clamped > 0)
        log::info(o.env + ": " + std::to_string(report.invalid_clamped) + " NaN/Inf texel components set to 0");
    const Decomposition d = decompose(map, DecomposeOptions{parse_method(o.method), o.lights, o.seed});

    glm::dvec3 sum(0.0);
    for (const Cell& c : d.cells) sum += glm::dvec3(c.radiance);
    std::printf("%s: %dx%d, %s, %zu cells in %.1f ms", o.env.c_str(), map.width, map.height, o.method.c_str(),
                d.cells.size(), d.seconds * 1000.0);
    if (d.iterations > 0) std::printf(" (%d iterations, last move %.2e rad)", d.iterations, d.final_movement);
    std::printf("\nintegral of L dw = (%.6g, %.6g, %.6g), sum over cells = (%.6g, %.6g, %.6g)\n", d.integral.r,
                d.integral.g, d.integral.b, sum.r, sum.g, sum.b);
    if (!o.json.empty()) write_file_atomically(o.json, to_json(d).dump(2) + "\n");
    if (!o.png.empty()) write_png(o.png, draw_cells(map, d));
    return 0;
}

}  // namespace

Command add_decompose_command(CLI::App& parent) {
    auto o = std::make_shared<DecomposeCommandOptions>();
    CLI::App* app = parent.add_subcommand("decompose", "Cut an environment map into N directional cells");
    app->add_option("--env", o->env, "Environment map: .exr, .hdr, builtin:constant or builtin:sky[:key=value,…]")
        ->required();
    app->add_option("--lights", o->lights, "Number of cells N (1..256; mediancut rounds down to a power of two)")
        ->check(CLI::Range(1, kMaxLights));
    app->add_option("--method", o->method, "lloyd, ccvt, mediancut, random or fs")
        ->check(CLI::IsMember({"lloyd", "ccvt", "mediancut", "random", "fs"}));
    app->add_option("--seed", o->seed, "Seed (lloyd, ccvt and random draw their initial sites with it)");
    app->add_option("--json", o->json, "Write the cells as JSON (DESIGN.md §6)");
    app->add_option("--png", o->png, "Write the map with the cell borders and centres drawn over it");
    app->add_flag("--clamp-invalid", o->clamp_invalid, "Set NaN/Inf texels to 0 instead of refusing the map");
    return {app, [o] { return run_decompose(*o); }};
}

}  // namespace envshadow::app
