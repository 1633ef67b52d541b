#include "inputs.h"

namespace envshadow::app {

Scene load_scene_with_environment(const std::string& scene_file, const std::string& env) {
    Scene scene = load_scene(scene_file);
    if (!env.empty()) scene.environment.source = env;
    return scene;
}

EnvironmentMap load_environment_at(const std::string& spec, double time) {
    return load_environment(environment_at_time(spec, time));
}

Inputs load_inputs(const std::string& scene_file, const std::string& env, double time) {
    Inputs inputs{load_scene_with_environment(scene_file, env), {}};
    inputs.map = load_environment_at(inputs.scene.environment.source, time);
    return inputs;
}

}  // namespace envshadow::app
