#pragma once
// A material's texture on the CPU (docs/DESIGN.md §5.12): 8-bit RGBA texels, with the glTF sampler's wrap
// and filter modes; colour (base colour, emission) sRGB-encoded as glTF stores it, data (occlusion) linear.
// The renderer uploads it (mipmapped, colour decoded to linear by the hardware); the reference samples it
// here. No GL.
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace envshadow {

enum class TextureWrap { repeat, clamp_to_edge, mirrored_repeat };

struct TextureImage {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgba;  // row 0 first: the row at v = 0 (glTF's uv origin is the top-left)
};

struct MaterialTexture {
    std::shared_ptr<const TextureImage> image;  // never null in a Material
    TextureWrap wrap_s = TextureWrap::repeat;
    TextureWrap wrap_t = TextureWrap::repeat;
    bool nearest = false;  // magFilter NEAREST (pixel art); otherwise bilinear, trilinear when minified
    bool srgb = true;      // RGB sRGB-encoded (colour); false: stored linear (data such as occlusion)
};

// The sRGB transfer function's inverse (IEC 61966-2-1) of an 8-bit value.
float srgb8_to_linear(std::uint8_t value);

// Linear RGB of `texture` at uv (texel centres at (i + 0.5) / width; decoded where srgb), bilinear (or
// nearest) at full resolution with the texture's wrap modes: what the reference renderer reads. The
// GPU's trilinear mipmapped lookup agrees where a texel covers at least a pixel.
glm::vec3 sample_linear_rgb(const MaterialTexture& texture, glm::vec2 uv);
// The same with the texel's alpha (not sRGB-decoded), filtered alike.
glm::vec4 sample_linear_rgba(const MaterialTexture& texture, glm::vec2 uv);

}  // namespace envshadow
