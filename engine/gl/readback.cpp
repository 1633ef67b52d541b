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

Image8 read_default_framebuffer(int width, int height) {
    Image8 image(width, height);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, image.rgba.data());
    const size_t row = size_t(width) * 4;
    for (int y = 0; y < height / 2; ++y)
        std::swap_ranges(image.rgba.begin() + ptrdiff_t(y * row), image.rgba.begin() + ptrdiff_t((y + 1) * row),
                         image.rgba.begin() + ptrdiff_t((height - 1 - y) * row));
    for (size_t i = 3; i < image.rgba.size(); i += 4) image.rgba[i] = 255;  // the window is opaque
    return image;
}

}  // namespace envshadow::gl
