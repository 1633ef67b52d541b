#include "render/embedded_shaders.h"

#include "glsl/embedded.h"
#include "render/shader_interface.h"

namespace envshadow::render {

gl::ShaderLibrary embedded_shaders() {
    gl::ShaderLibrary library;
    for (const glsl::File& f : glsl::files()) library.add(f.name, f.source);
    for (std::string& define : shader::defines()) library.define(std::move(define));
    return library;
}

}  // namespace envshadow::render
