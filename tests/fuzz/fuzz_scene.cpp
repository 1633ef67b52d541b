// libFuzzer target: load_scene on one scene JSON. The folder also holds box.glb (a valid model) and
// sky.hdr, so scenes can refer to a model and an environment file by relative path.
#include <cstddef>
#include <cstdint>

#include <glm/matrix.hpp>

#include "fuzz_support.h"
#include "sample_inputs.h"
#include "scene/scene.h"

namespace {

bool finite(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace envshadow;
    static const bool folder_ready = [] {
        test::write_sample_glb(fuzz::work_folder() / "box.glb");
        test::write_sample_hdr(fuzz::work_folder() / "sky.hdr", 16, 8, /*run_length=*/true);
        return true;
    }();
    (void)folder_ready;

    const auto path = fuzz::write_input("scene.json", data, size);
    try {
        const Scene scene = load_scene(path);
        if (scene.objects.empty()) fuzz::finding("scene without objects");
        for (const Object& object : scene.objects) {
            if (!object.mesh) fuzz::finding("object without a mesh");
            fuzz::check_mesh(*object.mesh);
            if (!finite(object.transform)) fuzz::finding("non-finite transform");
        }
        if (!fuzz::finite(scene.camera.position) || !fuzz::finite(scene.camera.target))
            fuzz::finding("non-finite camera");
        glm::vec3 lo, hi;
        scene.bounds_at(0.0, lo, hi);
        if (!fuzz::finite(lo) || !fuzz::finite(hi)) fuzz::finding("non-finite scene bounds");
    } catch (const InputError& e) {
        // Errors inside a referenced model are reported as "<scene>: objects[i].model: <model>: reason".
        fuzz::check_error_message(e, path);
    }
    return 0;
}
