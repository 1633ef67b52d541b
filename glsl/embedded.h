#pragma once
// The shaders of glsl/, compiled into the binary by glsl/embed.cmake.
#include <span>

namespace envshadow::glsl {

struct File {
    const char* name;    // file name in glsl/, e.g. "shade.frag"
    const char* source;
};

std::span<const File> files();

}  // namespace envshadow::glsl
