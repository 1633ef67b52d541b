#pragma once
#include "core/image.h"
#include "gl/objects.h"

namespace envshadow::gl {

// Reads colour attachment 0 of `framebuffer` (RGBA float), rows flipped so row 0 is the top.
Image read_color(const Framebuffer& framebuffer, int width, int height);

// Reads the window's back buffer (what will be shown after the swap) as 8-bit RGBA, row 0 at the top.
Image8 read_default_framebuffer(int width, int height);

}  // namespace envshadow::gl
