#pragma once
// The shaders of glsl/ (compiled into the binary by glsl/embed.cmake) as one library, with their
// #include files and, in every stage, the #defines of render/shader_interface.h: what the renderer,
// the display and the GPU sampler build their programs from.
#include "gl/shader.h"

namespace envshadow::render {

gl::ShaderLibrary embedded_shaders();

}  // namespace envshadow::render
