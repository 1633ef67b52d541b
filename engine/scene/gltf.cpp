#include "scene/gltf.h"

#include <stb_image.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/image.h"
#include "core/log.h"
#include "scene/gltf_accessor.h"
#include "scene/gltf_animation.h"
#include "scene/gltf_flatten.h"
#include "scene/gltf_material.h"
#include "scene/gltf_schema.h"
#include "scene/meshes.h"

namespace envshadow {
namespace {

using nlohmann::json;

constexpr std::uintmax_t kMaxFileBytes = 2'000'000'000;  // tinygltf takes unsigned int lengths
constexpr int kMaxJsonDepth = 64;  // nesting of JSON values: tinygltf converts "extras" recursively
constexpr std::size_t kMaxTextureTexels = std::size_t(1) << 28;  // all decoded textures together (1 GiB RGBA8)

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& reason) {
    throw InputError(file.string() + ": " + reason);
}

// tinygltf's messages may span lines; ours are one line.
std::string one_line(std::string text) {
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
    std::string out;
    for (const char c : text) {
        if (c == '\n')
            out += "; ";
        else if (c != '\r')
            out += c;
    }
    return out;
}

std::vector<unsigned char> read_bytes(const std::filesystem::path& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) fail(path, "no such file");
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec) fail(path, "cannot read the file size: " + ec.message());
    if (size > kMaxFileBytes) fail(path, "file is too large (" + std::to_string(size) + " bytes)");
    std::vector<unsigned char> bytes(size);
    std::ifstream in(path, std::ios::binary);
    if (!in || !in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(size)))
        fail(path, "cannot read the file");
    return bytes;
}

std::uint32_t read_u32(const unsigned char* p) {
    std::uint32_t v;
    std::memcpy(&v, p, 4);
    return v;  // glb is little-endian, as is every platform we build for
}

// The JSON chunk of a .glb (header: magic, version, length; then chunks of length, type, data).
std::string glb_json_chunk(const std::filesystem::path& path, const std::vector<unsigned char>& bytes) {
    if (bytes.size() < 20 || std::memcmp(bytes.data(), "glTF", 4) != 0)
        fail(path, "not a binary glTF file (bad magic)");
    if (read_u32(&bytes[4]) != 2)
        fail(path, "binary glTF version " + std::to_string(read_u32(&bytes[4])) + " (need 2)");
    if (read_u32(&bytes[8]) > bytes.size())
        fail(path, "binary glTF is truncated (header says " + std::to_string(read_u32(&bytes[8])) + " bytes)");
    const std::uint32_t json_length = read_u32(&bytes[12]);
    if (std::memcmp(&bytes[16], "JSON", 4) != 0) fail(path, "binary glTF does not start with a JSON chunk");
    if (json_length > bytes.size() - 20) fail(path, "binary glTF JSON chunk runs past the end of the file");
    return std::string(reinterpret_cast<const char*>(&bytes[20]), json_length);
}

// nlohmann's message without its "[json.exception.parse_error.101] " prefix.
std::string json_reason(const json::exception& e) {
    const std::string what = e.what();
    const auto bracket = what.find("] ");
    return what.rfind("[json.exception", 0) == 0 && bracket != std::string::npos ? what.substr(bracket + 2) : what;
}

std::string percent_decode(const std::string& uri) {
    std::string out;
    for (std::size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(uint8_t(uri[i + 1])) &&
            std::isxdigit(uint8_t(uri[i + 2]))) {
            out += char(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

// tinygltf's image callback: decodes, with stb_image, the images the base-colour textures use (the
// others are left undecoded) after checking their headers against the size limits.
struct ImageDecoder {
    std::vector<bool> wanted;                                 // by image index
    std::vector<std::shared_ptr<const TextureImage>> images;  // decoded, by image index
    std::size_t texels = 0;
    std::string error;  // the first failure, in our words (tinygltf's message around it is dropped)

    static bool decode(tinygltf::Image*, const int index, std::string* err, std::string*, int, int,
                       const unsigned char* bytes, int size, void* user) {
        auto& self = *static_cast<ImageDecoder*>(user);
        if (index < 0 || std::size_t(index) >= self.wanted.size() || !self.wanted[std::size_t(index)]) return true;
        const std::string what = "image " + std::to_string(index);
        const auto failed = [&](const std::string& reason) {
            if (self.error.empty()) self.error = what + ": " + reason;
            if (err) *err += self.error;
            return false;
        };
        const bool png = size >= 8 && std::memcmp(bytes, "\x89PNG\r\n\x1a\n", 8) == 0;
        const bool jpeg = size >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF;
        if (!png && !jpeg) return failed("not a PNG or JPEG image");
        int w = 0, h = 0, channels = 0;
        // A PNG's size straight from its IHDR chunk: stb_image's header scan refuses large ones with
        // a reason that another format's probe then overwrites.
        if (png && size >= 24 && std::memcmp(bytes + 12, "IHDR", 4) == 0) {
            const auto be32 = [](const unsigned char* p) {
                return (std::uint32_t(p[0]) << 24) | (std::uint32_t(p[1]) << 16) | (std::uint32_t(p[2]) << 8) | p[3];
            };
            w = int(std::min<std::uint32_t>(be32(bytes + 16), 1u << 30));
            h = int(std::min<std::uint32_t>(be32(bytes + 20), 1u << 30));
        } else if (!stbi_info_from_memory(bytes, size, &w, &h, &channels)) {
            return failed(std::string("cannot read its header (") + stbi_failure_reason() + ")");
        }
        if (w <= 0 || h <= 0 || w > kMaxImageWidth || h > kMaxImageHeight)
            return failed(std::to_string(w) + "x" + std::to_string(h) + " is beyond the " +
                          std::to_string(kMaxImageWidth) + "x" + std::to_string(kMaxImageHeight) + " limit");
        if (std::size_t(w) * std::size_t(h) > kMaxTextureTexels - self.texels)
            return failed("the textures together exceed " + std::to_string(kMaxTextureTexels) + " texels (limit)");
        stbi_uc* data = stbi_load_from_memory(bytes, size, &w, &h, &channels, 4);
        if (!data) return failed(std::string("cannot decode it (") + stbi_failure_reason() + ")");
        auto image = std::make_shared<TextureImage>();
        image->width = w;
        image->height = h;
        image->rgba.assign(data, data + std::size_t(w) * std::size_t(h) * 4);
        stbi_image_free(data);
        self.texels += std::size_t(w) * std::size_t(h);
        self.images[std::size_t(index)] = std::move(image);
        return true;
    }
};

TextureWrap wrap_mode(int gl_wrap) {
    switch (gl_wrap) {
        case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE:
            return TextureWrap::clamp_to_edge;
        case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT:
            return TextureWrap::mirrored_repeat;
        default:
            return TextureWrap::repeat;
    }
}

// Texture t (its image decoded by the ImageDecoder, and its sampler) into out[t], unless done or without
// a PNG/JPEG source.
void resolve_texture(const std::filesystem::path& path, const tinygltf::Model& model, std::size_t t,
                     const ImageDecoder& decoder, std::vector<std::optional<MaterialTexture>>& out) {
    if (out[t]) return;
    const tinygltf::Texture& texture = model.textures[t];
    if (texture.source < 0 || !decoder.images[std::size_t(texture.source)]) return;
    MaterialTexture mt;
    mt.image = decoder.images[std::size_t(texture.source)];
    if (texture.sampler >= 0) {
        if (std::size_t(texture.sampler) >= model.samplers.size())
            fail(path, "texture " + std::to_string(t) + " refers to sampler " + std::to_string(texture.sampler) +
                           ", which does not exist");
        const tinygltf::Sampler& sampler = model.samplers[std::size_t(texture.sampler)];
        mt.wrap_s = wrap_mode(sampler.wrapS);
        mt.wrap_t = wrap_mode(sampler.wrapT);
        mt.nearest = sampler.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
    }
    out[t] = std::move(mt);
}

// The glTF textures the materials use (GltfMaterial::texture_refs()), by texture index: their image
// (decoded by the ImageDecoder) and sampler. A texture without a PNG/JPEG source (only an extension's) is
// left unset, with a warning: its material shows its factors.
std::vector<std::optional<MaterialTexture>> resolve_textures(const std::filesystem::path& path,
                                                             const tinygltf::Model& model,
                                                             const std::vector<GltfMaterial>& materials,
                                                             const ImageDecoder& decoder) {
    std::vector<std::optional<MaterialTexture>> out(model.textures.size());
    for (const GltfMaterial& m : materials)
        for (const std::optional<GltfTextureRef>* ref : m.texture_refs())
            if (*ref) resolve_texture(path, model, std::size_t((*ref)->texture), decoder, out);
    return out;
}

// tinygltf's file access, limited to regular files: it reads every image and buffer a URI names,
// and opening a FIFO (or a device) there would block or read for ever.
bool regular_file_exists(const std::string& path, void*) {
    std::error_code ec;
    return std::filesystem::is_regular_file(path, ec);
}

std::string path_unchanged(const std::string& path, void*) {
    return path;
}

bool read_regular_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
    try {
        *out = read_bytes(path);
        return true;
    } catch (const InputError& e) {
        if (err) *err += e.what();
        return false;
    }
}

}  // namespace

GltfModel load_gltf(const std::filesystem::path& path) {
    const std::string extension = [&] {
        std::string e = path.extension().string();
        std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
        return e;
    }();
    if (extension != ".gltf" && extension != ".glb") fail(path, "not a glTF file (expected .gltf or .glb)");
    const std::vector<unsigned char> bytes = read_bytes(path);
    const bool binary = extension == ".glb";
    const std::string json_text = binary ? glb_json_chunk(path, bytes) : std::string(bytes.begin(), bytes.end());

    json document;
    try {
        document = json::parse(json_text, [&](int depth, json::parse_event_t, json&) {
            if (depth > kMaxJsonDepth)
                fail(path, "JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
            return true;
        });
    } catch (const json::exception& e) {  // parse_error, and out_of_range for numbers too large
        fail(path, "invalid JSON: " + json_reason(e));
    }
    check_gltf_json(path, document);
    // Extensions that change how geometry is stored; others (materials, textures) can be ignored.
    for (const auto& name : document.value("extensionsRequired", json::array()))
        for (const char* unsupported :
             {"KHR_draco_mesh_compression", "KHR_mesh_quantization", "EXT_meshopt_compression"})
            if (name == unsupported) fail(path, "requires " + std::string(unsupported) + ", which is not supported");

    GltfMaterials materials = read_gltf_materials(path, document);

    // The images the materials' textures use, checked to exist before tinygltf reads them.
    const json textures = document.value("textures", json::array());
    const json images = document.value("images", json::array());
    ImageDecoder decoder;
    decoder.wanted.assign(images.size(), false);
    decoder.images.resize(images.size());
    for (std::size_t i = 0; i < materials.materials.size(); ++i)
        for (const std::optional<GltfTextureRef>* texture_ref : materials.materials[i].texture_refs()) {
            const std::optional<GltfTextureRef>& ref = *texture_ref;
            if (!ref) continue;
            if (std::size_t(ref->texture) >= textures.size())
                fail(path, "materials[" + std::to_string(i) + "] uses texture " + std::to_string(ref->texture) +
                               ", which does not exist");
            const json& texture = textures[std::size_t(ref->texture)];
            const auto source = texture.find("source");
            if (source == texture.end()) {
                log::warn(path.string() + ": texture " + std::to_string(ref->texture) +
                          " has no PNG or JPEG source: materials[" + std::to_string(i) + "] shows its factors");
                continue;
            }
            if (!source->is_number_unsigned() || source->get<std::size_t>() >= images.size())
                fail(path, "texture " + std::to_string(ref->texture) + " refers to image " + source->dump() +
                               ", which does not exist");
            decoder.wanted[source->get<std::size_t>()] = true;
        }
    const std::filesystem::path base_dir = path.parent_path();
    for (std::size_t i = 0; i < document.value("buffers", json::array()).size(); ++i) {
        const json& buffer = document["buffers"][i];
        if (!buffer.contains("uri")) continue;
        const std::string uri = buffer["uri"].get<std::string>();
        if (uri.rfind("data:", 0) == 0) continue;
        const std::filesystem::path file = base_dir / percent_decode(uri);
        std::error_code ec;
        if (!std::filesystem::is_regular_file(file, ec))
            fail(path, "buffer " + std::to_string(i) + " file " + file.string() + " not found");
    }

    for (std::size_t i = 0; i < images.size(); ++i) {
        if (!decoder.wanted[i] || !images[i].contains("uri")) continue;
        const std::string uri = images[i]["uri"].get<std::string>();
        if (uri.rfind("data:", 0) == 0) continue;
        const std::filesystem::path file = base_dir / percent_decode(uri);
        std::error_code ec;
        if (!std::filesystem::is_regular_file(file, ec))
            fail(path, "image " + std::to_string(i) + " file " + file.string() + " not found");
    }

    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(ImageDecoder::decode, &decoder);
    loader.SetFsCallbacks({regular_file_exists, path_unchanged, read_regular_file, nullptr, nullptr});
    tinygltf::Model model;
    std::string err, warn;
    const bool ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(), unsigned(bytes.size()),
                                                         base_dir.string())
                           : loader.LoadASCIIFromString(&model, &err, &warn, json_text.data(),
                                                        unsigned(json_text.size()), base_dir.string());
    if (!decoder.error.empty()) fail(path, decoder.error);
    if (!ok) fail(path, one_line(err.empty() ? "tinygltf could not load it" : err));
    if (!err.empty()) fail(path, one_line(err));  // tinygltf reports some errors and still returns true
    if (!warn.empty()) log::warn(path.string() + ": " + one_line(warn));

    // Animation, skins and morph targets (scene/gltf_animation.h), read only when the file has any.
    bool animated = !model.animations.empty() || !model.skins.empty();
    for (const auto& mesh : model.meshes)
        for (const auto& prim : mesh.primitives) animated = animated || !prim.targets.empty();
    const GltfAccessors accessors(path, model);
    std::shared_ptr<const GltfRig> rig;
    if (animated) rig = std::make_shared<const GltfRig>(read_gltf_rig(accessors, model));
    std::vector<std::optional<MaterialTexture>> resolved = resolve_textures(path, model, materials.materials, decoder);
    GltfModel result =
        flatten_gltf(path, model, std::move(materials.materials), std::move(resolved), rig.get(), &accessors);
    result.rig = rig;
    result.ignored_extensions = std::move(materials.ignored_extensions);
    for (const std::string& name : result.ignored_extensions)
        log::warn(path.string() + ": material extension " + name + " is not supported: ignored");
    return result;
}

std::size_t GltfModel::triangle_count() const {
    std::size_t n = 0;
    for (const GltfPart& part : parts) n += part.mesh->triangle_count();
    return n;
}

}  // namespace envshadow
