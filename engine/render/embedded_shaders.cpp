#include "render/embedded_shaders.h"

#include "glsl/embedded.h"

namespace envshadow::render {

gl::ShaderLibrary embedded_shaders() {
    gl::ShaderLibrary library;
    for (const glsl::File& f : glsl::files()) library.add(f.name, f.source);
    return library;
}

}  // namespace envshadow::render
