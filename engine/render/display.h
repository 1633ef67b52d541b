#pragma once
// What the viewer shows besides the frame itself: the linear frame tone-mapped into the window,
// a picture of the shadow atlas, and 8-bit images (the environment with its cells) as textures.
// A GL 4.5 context must be current.
#include <array>

#include "core/image.h"
#include "gl/objects.h"
#include "gl/shader.h"

namespace envshadow::render {

class Display {
public:
    Display();

    // Draws `linear` (RGBA float) over the whole default framebuffer (the window), `width` x `height`
    // pixels: exposure (stops), the tone map `op`, sRGB (glsl/tonemap.glsl, twin of core's
    // tonemap_to_srgb8).
    void present(const gl::Texture& linear, float exposure_stops, ToneMap op, int width, int height);

    // A greyscale RGBA8 picture of the depth atlas, at most `max_width` wide (aspect kept).
    const gl::Texture& atlas_preview(const gl::Texture& atlas_depth, int max_width);

    // Uploads an 8-bit RGBA picture into a new texture.
    static gl::Texture upload(const Image8& image);

private:
    std::array<gl::Program, kToneMapCount> present_programs_;  // one per ToneMap, in its order
    gl::Program preview_program_;
    gl::VertexArray empty_vertex_array_;
    gl::Texture preview_;
    gl::Framebuffer preview_target_;
};

}  // namespace envshadow::render
