// Writes the fuzzers' seed corpus: small valid files of every kind the loaders read, made by the
// project (tests/robustness/sample_inputs.h). Usage: make_fuzz_seeds OUTPUT_FOLDER
// Creates OUTPUT_FOLDER/{exr,hdr,gltf,scene}/.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sample_inputs.h"

namespace fs = std::filesystem;
using namespace envshadow::test;

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: make_fuzz_seeds OUTPUT_FOLDER\n");
        return 2;
    }
    const fs::path out = argv[1];
    for (const char* kind : {"exr", "hdr", "gltf", "scene"}) fs::create_directories(out / kind);

    // EXR: every compression OpenEXR 3.1 writes (0 none ... 9 DWAB), half and float, scanline and tiled.
    for (int compression = 0; compression <= 9; ++compression)
        write_sample_exr(out / "exr" / ("c" + std::to_string(compression) + ".exr"), 16, 8, compression);
    write_sample_exr(out / "exr" / "float_zip.exr", 16, 8, 3, ExrLayout::scanline, ExrPixels::full_float);
    write_sample_exr(out / "exr" / "tiled_piz.exr", 40, 20, 4, ExrLayout::tiled, ExrPixels::half);
    write_sample_exr(out / "exr" / "tiled_float_alpha.exr", 20, 10, 0, ExrLayout::tiled, ExrPixels::full_float, true);
    write_sample_exr(out / "exr" / "one_texel.exr", 1, 1, 0);

    // Radiance HDR: run-length scanlines, flat ones, and a width too small for run lengths.
    write_sample_hdr(out / "hdr" / "rle.hdr", 16, 8, true);
    write_sample_hdr(out / "hdr" / "flat.hdr", 16, 8, false);
    write_sample_hdr(out / "hdr" / "narrow.hdr", 4, 2, false);

    // glTF: binary, embedded buffer, interleaved strip, and one reading the harness's buffer.bin.
    write_sample_glb(out / "gltf" / "box.glb");
    write_sample_gltf_embedded(out / "gltf" / "embedded.gltf");
    write_sample_gltf_interleaved_strip(out / "gltf" / "strip.gltf");
    // Base-colour textures: a PNG in a data: URI, and one in the harness's image.png beside the input.
    write_sample_gltf_textured(out / "gltf" / "textured.gltf");
    // Animation: a skin, a morph target, and channels of each interpolation.
    write_sample_gltf_animated(out / "gltf" / "animated.gltf");
    write_sample_gltf_textured(out / "gltf" / "textured_file.gltf", "image.png");
    const nlohmann::json external = {
        {"asset", {{"version", "2.0"}}},
        {"scenes", {{{"nodes", {0}}}}},
        {"nodes", {{{"mesh", 0}}}},
        {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}}},
        {"buffers", {{{"uri", "buffer.bin"}, {"byteLength", 256}}}},
        {"bufferViews", {{{"buffer", 0}, {"byteLength", 36}}, {{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 3}}}},
        {"accessors",
         {{{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"}},
          {{"bufferView", 1}, {"componentType", 5121}, {"count", 3}, {"type", "SCALAR"}}}}};
    write_bytes(out / "gltf" / "external.gltf", [&] {
        const std::string text = external.dump();
        return std::vector<std::uint8_t>(text.begin(), text.end());
    }());

    // Scenes: every kind of key, referring to the harness's box.glb and sky.hdr, and a builtin sky.
    auto write_text = [](const fs::path& path, const std::string& text) {
        write_bytes(path, std::vector<std::uint8_t>(text.begin(), text.end()));
    };
    write_text(out / "scene" / "every_key.json", sample_scene_json("box.glb", "sky.hdr"));
    write_text(out / "scene" / "builtin_sky.json",
               R"({"environment": "builtin:sky:elevation=30,azimuth=120", "objects": [{"mesh": "sphere"}]})");
    return 0;
}
