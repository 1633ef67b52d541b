#pragma once
// Material textures on the GPU (docs/DESIGN.md §5.12): colour as sRGB8_ALPHA8 with a full mip chain, so
// the hardware decodes to linear before filtering (data as RGBA8), and the glTF sampler's wrap and
// magnification modes.
// Needs a current GL context.
#include "gl/objects.h"
#include "scene/texture.h"

namespace envshadow::render {

gl::Texture upload_material_texture(const MaterialTexture& texture);

// One white texel: what shade.frag's material textures read for a material without one.
gl::Texture white_texture();

}  // namespace envshadow::render
