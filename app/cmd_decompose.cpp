// envshadow decompose: cut an environment map into N directional cells (docs/DESIGN.md §3) and write them
// as JSON (docs/DESIGN.md §6) and/or as a picture of the cells over the map.
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "commands.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/image.h"
#include "core/log.h"
#include "env/cell_overlay.h"
#include "env/cells.h"
#include "env/environment.h"

namespace envshadow::app {
namespace {

struct DecomposeArguments {
    CommonOptions common;  // --env, --lights, --method, --seed
    std::string json, png, hemisphere = "full";
    bool clamp_invalid = false;
};

// Keys in the order of docs/DESIGN.md §6.
nlohmann::ordered_json to_json(const Decomposition& d) {
    nlohmann::ordered_json lights = nlohmann::ordered_json::array();
    for (const Cell& c : d.cells)
        lights.push_back(nlohmann::ordered_json{{"dir", {c.direction.x, c.direction.y, c.direction.z}},
                                                {"radiance", {c.radiance.r, c.radiance.g, c.radiance.b}},
                                                {"solid_angle", c.solid_angle},
                                                {"cos_radius", c.cos_radius},
                                                {"cos_radius_weighted", c.cos_radius_weighted}});
    return {{"method", std::string(to_string(d.method))},
            {"hemisphere", std::string(to_string(d.hemisphere))},
            {"width", d.width},
            {"height", d.height},
            {"lights", lights},
            {"integral", {d.integral.r, d.integral.g, d.integral.b}},
            {"seconds", d.seconds},
            {"iterations", d.iterations},
            {"coarse_iterations", d.coarse_iterations},
            {"final_movement", d.final_movement}};
}

int run_decompose(const DecomposeArguments& args) {
    const std::string& env = args.common.env;
    DecomposeOptions options{parse_enum<Method>(args.common.method), args.common.lights, args.common.seed};
    options.hemisphere = parse_enum<Hemisphere>(args.hemisphere);

    EnvironmentLoadReport report;
    const EnvironmentMap map = load_environment(env, {args.clamp_invalid}, &report);
    if (report.negative_clamped > 0)
        log::info(env + ": " + std::to_string(report.negative_clamped) + " negative texel values set to 0");
    if (report.invalid_clamped > 0)
        log::warn(env + ": " + std::to_string(report.invalid_clamped) + " NaN/infinite texel values set to 0");

    const Decomposition d = decompose(map, options);
    if (d.uniform_importance) log::warn(env + ": the map is black; cells follow solid angle (uniform importance)");
    if (!args.json.empty()) write_file_atomically(args.json, to_json(d).dump(2) + "\n");
    if (!args.png.empty()) write_png(args.png, draw_cells(map, d));

    std::printf("decompose: %s %dx%d, %s, %s, %zu lights, %.3f s", env.c_str(), d.width, d.height,
                std::string(to_string(d.method)).c_str(), hemisphere_words(d.hemisphere), d.cells.size(), d.seconds);
    if (options.method == Method::lloyd || options.method == Method::ccvt) {
        std::printf(", %d iterations", d.iterations);
        if (d.coarse_iterations > 0) std::printf(" (%d of them at a lower resolution)", d.coarse_iterations);
        std::printf(", final movement %.2e rad", d.final_movement);
    }
    glm::dvec3 sum(0.0);
    for (const Cell& c : d.cells) sum += glm::dvec3(c.radiance);
    std::printf("\nintegral of L dw%s = (%.6g, %.6g, %.6g), sum over the cells = (%.6g, %.6g, %.6g)\n",
                d.hemisphere == Hemisphere::upper ? " over the upper hemisphere" : "", d.integral.r, d.integral.g,
                d.integral.b, sum.r, sum.g, sum.b);
    return 0;
}

}  // namespace

Command add_decompose_command(CLI::App& parent) {
    auto args = std::make_shared<DecomposeArguments>();
    CLI::App* app = parent.add_subcommand("decompose", "Cut an environment map into N directional cells");
    CommonOptionSet set;
    set.scene = false;  // --env is the map itself
    set.gpu_method = false;
    set.size = false;
    set.backend = false;
    set.hemisphere = false;  // its own --hemisphere full|upper: there is no scene
    add_common_options(app, &args->common, set);
    app->add_option("--hemisphere", args->hemisphere,
                    "full (default) or upper: only the directions above the horizon (a scene with a ground)")
        ->check(CLI::IsMember(enum_value_names<Hemisphere>()));
    app->add_option("--json", args->json, "Write the cells as JSON here");
    app->add_option("--png", args->png, "Write a picture of the cells over the map here");
    app->add_flag("--clamp-invalid", args->clamp_invalid, "Set NaN and infinite texels to 0 instead of failing");
    return {app, [args] { return run_decompose(*args); }};
}

}  // namespace envshadow::app
