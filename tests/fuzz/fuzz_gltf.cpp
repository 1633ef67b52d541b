// libFuzzer target: load_gltf on one .glb or .gltf (a .glb when the input starts with "glTF").
// The folder also holds buffer.bin, so .gltf inputs can refer to an external buffer.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "fuzz_support.h"
#include "scene/gltf.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace envshadow;
    static const bool folder_ready = [] {
        // 64 floats: 0, 1, 2, ... (positions within reach) then index-like small integers.
        std::vector<float> values(64);
        for (std::size_t i = 0; i < values.size(); ++i) values[i] = float(i % 8);
        fuzz::write_input("buffer.bin", reinterpret_cast<const std::uint8_t*>(values.data()),
                          values.size() * sizeof(float));
        return true;
    }();
    (void)folder_ready;

    const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
    const auto path = fuzz::write_input(binary ? "input.glb" : "input.gltf", data, size);
    try {
        const GltfModel model = load_gltf(path);
        if (!model.mesh) fuzz::finding("loaded without a mesh");
        fuzz::check_mesh(*model.mesh);
        if (!fuzz::finite(model.base_color)) fuzz::finding("non-finite base colour");
    } catch (const InputError& e) {
        fuzz::check_error_message(e, path);
    }
    return 0;
}
