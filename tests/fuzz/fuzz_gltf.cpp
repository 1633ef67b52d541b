// libFuzzer target: load_gltf on one .glb or .gltf (a .glb when the input starts with "glTF").
// The folder also holds buffer.bin, so .gltf inputs can refer to an external buffer.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "fuzz_support.h"
#include "sample_inputs.h"
#include "scene/gltf.h"
#include "scene/gltf_animation.h"
#include "scene/gltf_material.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace envshadow;
    static const bool folder_ready = [] {
        // 64 floats: 0, 1, 2, ... (positions within reach) then index-like small integers.
        std::vector<float> values(64);
        for (std::size_t i = 0; i < values.size(); ++i) values[i] = float(i % 8);
        fuzz::write_input("buffer.bin", reinterpret_cast<const std::uint8_t*>(values.data()),
                          values.size() * sizeof(float));
        // image.png, for inputs whose image names it (the seed textured_file.gltf).
        test::write_sample_gltf_textured(fuzz::work_folder() / "textured_seed.gltf", "image.png");
        return true;
    }();
    (void)folder_ready;

    const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
    const auto path = fuzz::write_input(binary ? "input.glb" : "input.gltf", data, size);
    try {
        const GltfModel model = load_gltf(path);
        if (model.parts.empty()) fuzz::finding("loaded without a mesh");
        for (const GltfPart& part : model.parts) {
            if (!part.mesh) fuzz::finding("a part without a mesh");
            fuzz::check_mesh(*part.mesh);
            // The mapping keeps every albedo in [0, 1] and n in the shading's range.
            const Material& m = part.material;
            if (!fuzz::finite(m.rho_d) || !(std::min({m.rho_d.r, m.rho_d.g, m.rho_d.b}) >= 0.0f) ||
                !(std::max({m.rho_d.r, m.rho_d.g, m.rho_d.b}) <= 1.0f) || !(m.rho_s >= 0.0f && m.rho_s <= 1.0f) ||
                !(m.shininess >= kGltfMinShininess && m.shininess <= kGltfMaxShininess))
                fuzz::finding("material out of range");
            if (!fuzz::finite(m.emission) || !(std::min({m.emission.r, m.emission.g, m.emission.b}) >= 0.0f) ||
                !(m.base_alpha >= 0.0f && m.base_alpha <= 1.0f) || !(m.alpha_cutoff >= 0.0f) ||
                !std::isfinite(m.alpha_cutoff) || !(m.occlusion_strength >= 0.0f && m.occlusion_strength <= 1.0f))
                fuzz::finding("emission, occlusion or alpha out of range");
            if (m.occlusion_texture && m.occlusion_texture->srgb) fuzz::finding("occlusion read as sRGB colour");
            if (m.metallic_roughness_texture && (m.metallic_roughness_texture->srgb || !m.metallic_roughness))
                fuzz::finding("metallic-roughness texture read as colour, or without the factors");
            // An animated part poses, at any time, into a mesh as sound as the rest pose.
            if (model.rig && part.sources) {
                const MeshDeformation deformation(model.rig, part.sources, part.mesh, 0, true);
                for (const double t : {0.0, 0.37, 1e9}) {
                    if (deformation.rigid()) {
                        const glm::mat4 motion = deformation.rigid_motion(t);
                        for (int c = 0; c < 4; ++c)
                            if (!fuzz::finite(glm::vec3(motion[c])) || !std::isfinite(motion[c][3]))
                                fuzz::finding("non-finite rigid motion");
                    } else {
                        const std::shared_ptr<const Mesh> posed = deformation.mesh_at(t);
                        fuzz::check_mesh(*posed);
                        if (posed->indices != part.mesh->indices) fuzz::finding("a pose changed the triangles");
                    }
                }
            }
            // A texture comes with one finite texture coordinate per vertex and whole RGBA texels.
            for (const std::optional<MaterialTexture>& texture :
                 {m.base_color_texture, m.metallic_roughness_texture, m.emission_texture, m.occlusion_texture}) {
                if (!texture) continue;
                const TextureImage* image = texture->image.get();
                if (!image || image->width <= 0 || image->height <= 0 ||
                    image->rgba.size() != std::size_t(image->width) * std::size_t(image->height) * 4)
                    fuzz::finding("texture image of inconsistent size");
                if (part.mesh->texcoords.size() != part.mesh->positions.size())
                    fuzz::finding("textured part without one texture coordinate per vertex");
                for (const glm::vec2& uv : part.mesh->texcoords)
                    if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) fuzz::finding("non-finite texture coordinate");
            }
        }
    } catch (const InputError& e) {
        fuzz::check_error_message(e, path);
    }
    return 0;
}
