#include "gl/readback.h"

#include <algorithm>

namespace envshadow::gl {

Image read_color(const Framebuffer& framebuffer, int width, int height) {
    Image image(width, height);
    glNamedFramebufferReadBuffer(framebuffer.id(), GL_COLOR_ATTACHMENT0);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer.id());
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, image.pixels.data());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    for (int y = 0; y < height / 2; ++y)
        std::swap_ranges(image.pixels.begin() + ptrdiff_t(y) * width, image.pixels.begin() + ptrdiff_t(y + 1) * width,
                         image.pixels.begin() + ptrdiff_t(height - 1 - y) * width);
    return image;
}

}  // namespace envshadow::gl
