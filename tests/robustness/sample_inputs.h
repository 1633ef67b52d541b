#pragma once
// Small valid input files written by the project itself: the fuzzers' seed corpus and the starting
// point of the malformed-input tests (which truncate them and flip their bits). Written with
// OpenEXR, by hand (Radiance RGBE) or with nlohmann::json (glTF), never with the loaders under test.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "common/test_files.h"  // write_bytes, read_bytes, write_text

namespace envshadow::test {

// A sky-like lat-long picture: blue above, brown below, a small bright sun; every texel finite and > 0.
glm::vec3 sample_radiance(int i, int j, int width, int height);

enum class ExrLayout { scanline, tiled };
enum class ExrPixels { half, full_float };
// Compression is an Imf::Compression value (0 none, 1 RLE, 2 ZIPS, 3 ZIP, 4 PIZ, 5 PXR24, 6 B44, ...).
void write_sample_exr(const std::filesystem::path& path, int width, int height, int compression = 3,
                      ExrLayout layout = ExrLayout::scanline, ExrPixels pixels = ExrPixels::half,
                      bool with_alpha = false);
// An EXR with the given RGB texels (row-major, row 0 at the top), float, no compression.
void write_exr_texels(const std::filesystem::path& path, int width, int height, const std::vector<glm::vec3>& texels);

// Radiance RGBE (.hdr): run-length encoded scanlines (needs 8 <= width < 32768) or flat ones.
void write_sample_hdr(const std::filesystem::path& path, int width, int height, bool run_length);
std::vector<std::uint8_t> hdr_bytes(int width, int height, const std::vector<glm::vec3>& texels, bool run_length);

// A unit box (24 vertices with normals, 36 unsigned-short indices) under a translated, rotated node:
// a .glb, or a .gltf whose buffer is a base64 data: URI, or a .gltf with an external .bin named
// after it, or a .gltf with an interleaved (strided) buffer and a triangle strip.
std::vector<std::uint8_t> sample_glb_bytes();
void write_sample_glb(const std::filesystem::path& path);
void write_sample_gltf_embedded(const std::filesystem::path& path);
void write_sample_gltf_external(const std::filesystem::path& path);
void write_sample_gltf_interleaved_strip(const std::filesystem::path& path);
// The box with texture coordinates and a base-colour texture (a 4x4 PNG; KHR_texture_transform on
// its textureInfo), the same texture its emission's (emissiveFactor, KHR_materials_emissive_strength), its
// occlusion's (with a strength) and its alpha MASK's: the image in a
// data: URI when `image_file` is empty, else written to that file (beside `path`) and named by it. A strip of two quads
// on a two-joint skin, its second joint turned by a LINEAR rotation channel, with a morph target on the strip and a
// CUBICSPLINE weights channel and a STEP translation of the root: every kind of glTF animation data, buffers in a data:
// URI.
void write_sample_gltf_animated(const std::filesystem::path& path);
void write_sample_gltf_textured(const std::filesystem::path& path, const std::string& image_file = "");

// A scene JSON using every kind of key, with a model and an environment at the given (relative) paths.
std::string sample_scene_json(const std::string& model, const std::string& environment);

}  // namespace envshadow::test
