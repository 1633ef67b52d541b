#pragma once
// What every command that renders starts from: the scene, its environment overridden by --env, and
// that environment at the animation time (builtin:sky's sun moves with it, env/environment.h
// environment_at_time), so render, bench, reference and the viewer light the same sky.
#include <string>

#include "env/environment.h"
#include "scene/scene.h"

namespace envshadow::app {

struct Inputs {
    Scene scene;         // scene.environment.source: the scene's map, or `env` when given
    EnvironmentMap map;  // scene.environment.source at the animation time
};

// The scene of `scene_file`, its environment replaced by `env` unless that is empty.
Scene load_scene_with_environment(const std::string& scene_file, const std::string& env);

// The environment `spec` after `time` seconds of animation.
EnvironmentMap load_environment_at(const std::string& spec, double time);

Inputs load_inputs(const std::string& scene_file, const std::string& env, double time);

}  // namespace envshadow::app
