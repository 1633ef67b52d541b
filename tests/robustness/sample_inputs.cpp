#include "sample_inputs.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <ImfTileDescriptionAttribute.h>
#include <ImfTiledOutputFile.h>
#include <half.h>
#include <stb_image_write.h>
#include <nlohmann/json.hpp>

namespace envshadow::test {
namespace {

using nlohmann::json;

void append(std::vector<std::uint8_t>& out, const void* data, std::size_t bytes) {
    const auto* p = static_cast<const std::uint8_t*>(data);
    out.insert(out.end(), p, p + bytes);
}

void append_u32(std::vector<std::uint8_t>& out, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(std::uint8_t(v >> (8 * i)));  // little-endian
}

std::string base64(const std::vector<std::uint8_t>& bytes) {
    static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        const std::uint32_t n = std::uint32_t(bytes[i]) << 16 | (i + 1 < bytes.size() ? bytes[i + 1] << 8 : 0) |
                                (i + 2 < bytes.size() ? bytes[i + 2] : 0);
        out += alphabet[(n >> 18) & 63];
        out += alphabet[(n >> 12) & 63];
        out += i + 1 < bytes.size() ? alphabet[(n >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? alphabet[n & 63] : '=';
    }
    return out;
}

// The box's geometry: 6 faces of 4 vertices, outward normals, counter-clockwise seen from outside.
struct BoxData {
    std::vector<float> positions, normals;  // 24 * 3 each
    std::vector<std::uint16_t> indices;     // 36
};

BoxData box() {
    BoxData b;
    const int axes[6][3] = {{0, 1, 2}, {0, 1, 2}, {1, 2, 0}, {1, 2, 0}, {2, 0, 1}, {2, 0, 1}};
    for (int face = 0; face < 6; ++face) {
        const float sign = face % 2 == 0 ? 1.0f : -1.0f;
        const int n = axes[face][2], u = axes[face][0], v = axes[face][1];
        const float corners[4][2] = {{-0.5f, -0.5f}, {0.5f, -0.5f}, {0.5f, 0.5f}, {-0.5f, 0.5f}};
        const auto base = std::uint16_t(b.positions.size() / 3);
        for (const auto& c : corners) {
            float p[3], nn[3] = {0, 0, 0};
            p[n] = 0.5f * sign;
            p[u] = c[0] * sign;  // mirrored faces flip u to stay counter-clockwise
            p[v] = c[1];
            nn[n] = sign;
            b.positions.insert(b.positions.end(), p, p + 3);
            b.normals.insert(b.normals.end(), nn, nn + 3);
        }
        for (const int k : {0, 1, 2, 0, 2, 3}) b.indices.push_back(std::uint16_t(base + k));
    }
    return b;
}

// Document and binary buffer for the box, the buffer's uri left for the caller.
json box_document(std::vector<std::uint8_t>& bin) {
    const BoxData b = box();
    bin.clear();
    append(bin, b.positions.data(), b.positions.size() * 4);
    append(bin, b.normals.data(), b.normals.size() * 4);
    append(bin, b.indices.data(), b.indices.size() * 2);
    while (bin.size() % 4 != 0) bin.push_back(0);
    json doc;
    doc["asset"] = {{"version", "2.0"}, {"generator", "envshadow tests"}};
    doc["scene"] = 0;
    doc["scenes"] = json::array({{{"nodes", {0}}}});
    doc["nodes"] = json::array({{{"children", {1}}, {"translation", {0.0, 0.5, 0.0}}},
                                {{"mesh", 0}, {"rotation", {0.0, 0.3826834, 0.0, 0.9238795}}, {"scale", {1, 1, 1}}}});
    doc["meshes"] = json::array(
        {{{"primitives",
           json::array(
               {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}, {"indices", 2}, {"material", 0}, {"mode", 4}}})}}});
    doc["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.2, 0.2, 1.0}}}}}});
    doc["buffers"] = json::array({{{"byteLength", bin.size()}}});
    doc["bufferViews"] = json::array({{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 288}, {"target", 34962}},
                                      {{"buffer", 0}, {"byteOffset", 288}, {"byteLength", 288}, {"target", 34962}},
                                      {{"buffer", 0}, {"byteOffset", 576}, {"byteLength", 72}, {"target", 34963}}});
    doc["accessors"] = json::array({{{"bufferView", 0},
                                     {"componentType", 5126},
                                     {"count", 24},
                                     {"type", "VEC3"},
                                     {"min", {-0.5, -0.5, -0.5}},
                                     {"max", {0.5, 0.5, 0.5}}},
                                    {{"bufferView", 1}, {"componentType", 5126}, {"count", 24}, {"type", "VEC3"}},
                                    {{"bufferView", 2}, {"componentType", 5123}, {"count", 36}, {"type", "SCALAR"}}});
    return doc;
}

// Radiance's RGBE: a shared exponent, mantissas scaled to 0..255.
void to_rgbe(const glm::vec3& c, std::uint8_t out[4]) {
    const float largest = std::max({c.r, c.g, c.b});
    if (largest < 1e-32f) {
        out[0] = out[1] = out[2] = out[3] = 0;
        return;
    }
    int exponent = 0;
    const float scale = std::frexp(largest, &exponent) * 256.0f / largest;
    out[0] = std::uint8_t(c.r * scale);
    out[1] = std::uint8_t(c.g * scale);
    out[2] = std::uint8_t(c.b * scale);
    out[3] = std::uint8_t(exponent + 128);
}

// One channel of a new-style RLE scanline: runs of >= 3 equal bytes as (128 + n, byte), the rest as
// literals (n, bytes...), n <= 127 either way.
void rle_channel(const std::vector<std::uint8_t>& in, std::vector<std::uint8_t>& out) {
    std::size_t i = 0;
    while (i < in.size()) {
        std::size_t run = 1;
        while (i + run < in.size() && run < 127 && in[i + run] == in[i]) ++run;
        if (run >= 3) {
            out.push_back(std::uint8_t(128 + run));
            out.push_back(in[i]);
            i += run;
            continue;
        }
        std::size_t literal = 0;
        while (i + literal < in.size() && literal < 127) {
            const std::size_t k = i + literal;
            if (k + 2 < in.size() && in[k] == in[k + 1] && in[k] == in[k + 2]) break;
            ++literal;
        }
        out.push_back(std::uint8_t(literal));
        out.insert(out.end(), in.begin() + std::ptrdiff_t(i), in.begin() + std::ptrdiff_t(i + literal));
        i += literal;
    }
}

}  // namespace

glm::vec3 sample_radiance(int i, int j, int width, int height) {
    const float v = (float(j) + 0.5f) / float(height);
    const float u = (float(i) + 0.5f) / float(width);
    glm::vec3 c = v < 0.5f ? glm::vec3(0.3f, 0.5f, 1.0f) * (1.5f - v) : glm::vec3(0.4f, 0.3f, 0.2f) * (0.5f + v);
    const float du = u - 0.3f, dv = v - 0.25f;
    if (du * du + dv * dv < 0.004f) c += glm::vec3(40.0f, 38.0f, 30.0f);
    return c;
}

void write_sample_exr(const std::filesystem::path& path, int width, int height, int compression, ExrLayout layout,
                      ExrPixels pixels, bool with_alpha) {
    const Imf::PixelType type = pixels == ExrPixels::half ? Imf::HALF : Imf::FLOAT;
    Imf::Header header(width, height);
    header.compression() = Imf::Compression(compression);
    const char* names[4] = {"R", "G", "B", "A"};
    const int channels = with_alpha ? 4 : 3;
    for (int c = 0; c < channels; ++c) header.channels().insert(names[c], Imf::Channel(type));

    std::vector<half> halves(std::size_t(width) * std::size_t(height) * 4);
    std::vector<float> floats(halves.size());
    for (int j = 0; j < height; ++j)
        for (int i = 0; i < width; ++i) {
            const glm::vec3 c = sample_radiance(i, j, width, height);
            const std::size_t k = (std::size_t(j) * std::size_t(width) + std::size_t(i)) * 4;
            for (int ch = 0; ch < 4; ++ch) {
                floats[k + std::size_t(ch)] = ch < 3 ? c[ch] : 1.0f;
                halves[k + std::size_t(ch)] = half(floats[k + std::size_t(ch)]);
            }
        }
    Imf::FrameBuffer frame;
    const std::size_t element = type == Imf::HALF ? sizeof(half) : sizeof(float);
    char* base = type == Imf::HALF ? reinterpret_cast<char*>(halves.data()) : reinterpret_cast<char*>(floats.data());
    for (int c = 0; c < channels; ++c)
        frame.insert(names[c],
                     Imf::Slice(type, base + std::size_t(c) * element, 4 * element, 4 * element * std::size_t(width)));
    if (layout == ExrLayout::tiled) {
        header.setTileDescription(Imf::TileDescription(16, 16, Imf::ONE_LEVEL));
        Imf::TiledOutputFile file(path.c_str(), header);
        file.setFrameBuffer(frame);
        file.writeTiles(0, file.numXTiles() - 1, 0, file.numYTiles() - 1);
    } else {
        Imf::OutputFile file(path.c_str(), header);
        file.setFrameBuffer(frame);
        file.writePixels(height);
    }
}

void write_exr_texels(const std::filesystem::path& path, int width, int height, const std::vector<glm::vec3>& texels) {
    if (texels.size() != std::size_t(width) * std::size_t(height)) throw std::invalid_argument("texel count");
    Imf::Header header(width, height);
    header.compression() = Imf::NO_COMPRESSION;
    const char* names[3] = {"R", "G", "B"};
    for (const char* n : names) header.channels().insert(n, Imf::Channel(Imf::FLOAT));
    Imf::FrameBuffer frame;
    char* base = const_cast<char*>(reinterpret_cast<const char*>(texels.data()));
    for (int c = 0; c < 3; ++c)
        frame.insert(names[c], Imf::Slice(Imf::FLOAT, base + std::size_t(c) * sizeof(float), sizeof(glm::vec3),
                                          sizeof(glm::vec3) * std::size_t(width)));
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(frame);
    file.writePixels(height);
}

std::vector<std::uint8_t> hdr_bytes(int width, int height, const std::vector<glm::vec3>& texels, bool run_length) {
    if (texels.size() != std::size_t(width) * std::size_t(height)) throw std::invalid_argument("texel count");
    if (run_length && (width < 8 || width >= 32768)) throw std::invalid_argument("RLE needs 8 <= width < 32768");
    const std::string header = "#?RADIANCE\n# envshadow test map\nFORMAT=32-bit_rle_rgbe\nEXPOSURE=1.0\n\n-Y " +
                               std::to_string(height) + " +X " + std::to_string(width) + "\n";
    std::vector<std::uint8_t> out(header.begin(), header.end());
    std::vector<std::uint8_t> channel[4];
    for (int j = 0; j < height; ++j) {
        for (auto& c : channel) c.clear();
        for (int i = 0; i < width; ++i) {
            std::uint8_t rgbe[4];
            to_rgbe(texels[std::size_t(j) * std::size_t(width) + std::size_t(i)], rgbe);
            if (!run_length) append(out, rgbe, 4);
            for (int c = 0; c < 4; ++c) channel[c].push_back(rgbe[c]);
        }
        if (!run_length) continue;
        out.insert(out.end(), {2, 2, std::uint8_t(width >> 8), std::uint8_t(width & 0xff)});
        for (const auto& c : channel) rle_channel(c, out);
    }
    return out;
}

void write_sample_hdr(const std::filesystem::path& path, int width, int height, bool run_length) {
    std::vector<glm::vec3> texels;
    for (int j = 0; j < height; ++j)
        for (int i = 0; i < width; ++i) texels.push_back(sample_radiance(i, j, width, height));
    write_bytes(path, hdr_bytes(width, height, texels, run_length));
}

std::vector<std::uint8_t> sample_glb_bytes() {
    std::vector<std::uint8_t> bin;
    std::string text = box_document(bin).dump();
    while (text.size() % 4 != 0) text += ' ';
    std::vector<std::uint8_t> out;
    out.insert(out.end(), {'g', 'l', 'T', 'F'});
    append_u32(out, 2);
    append_u32(out, std::uint32_t(12 + 8 + text.size() + 8 + bin.size()));
    append_u32(out, std::uint32_t(text.size()));
    out.insert(out.end(), {'J', 'S', 'O', 'N'});
    append(out, text.data(), text.size());
    append_u32(out, std::uint32_t(bin.size()));
    out.insert(out.end(), {'B', 'I', 'N', 0});
    append(out, bin.data(), bin.size());
    return out;
}

void write_sample_glb(const std::filesystem::path& path) {
    write_bytes(path, sample_glb_bytes());
}

void write_sample_gltf_embedded(const std::filesystem::path& path) {
    std::vector<std::uint8_t> bin;
    json doc = box_document(bin);
    doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(bin);
    write_text(path, doc.dump(1));
}

void write_sample_gltf_external(const std::filesystem::path& path) {
    std::vector<std::uint8_t> bin;
    json doc = box_document(bin);
    const std::string bin_name = path.stem().string() + ".bin";
    doc["buffers"][0]["uri"] = bin_name;
    write_bytes(path.parent_path() / bin_name, bin);
    write_text(path, doc.dump(1));
}

void write_sample_gltf_interleaved_strip(const std::filesystem::path& path) {
    // A quad as a 4-vertex strip; position and normal interleaved with a 24-byte stride; no indices.
    const float interleaved[4][6] = {{0, 0, 0, 0, 0, 1}, {1, 0, 0, 0, 0, 1}, {0, 1, 0, 0, 0, 1}, {1, 1, 0, 0, 0, 1}};
    std::vector<std::uint8_t> bin;
    append(bin, interleaved, sizeof interleaved);
    json doc;
    doc["asset"] = {{"version", "2.0"}};
    doc["nodes"] = json::array({{{"mesh", 0}, {"matrix", {2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 1, 0, 0, 1}}}});
    doc["meshes"] =
        json::array({{{"primitives", json::array({{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}, {"mode", 5}}})}}});
    doc["buffers"] =
        json::array({{{"byteLength", bin.size()}, {"uri", "data:application/octet-stream;base64," + base64(bin)}}});
    doc["bufferViews"] = json::array({{{"buffer", 0}, {"byteLength", bin.size()}, {"byteStride", 24}}});
    doc["accessors"] =
        json::array({{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}},
                     {{"bufferView", 0}, {"byteOffset", 12}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}}});
    write_text(path, doc.dump(1));
}

void write_sample_gltf_animated(const std::filesystem::path& path) {
    std::vector<std::uint8_t> bin;
    json views = json::array(), accessors = json::array();
    const auto add = [&](const void* data, std::size_t bytes, int component, std::size_t count, const char* type) {
        while (bin.size() % 4 != 0) bin.push_back(0);
        views.push_back({{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}});
        append(bin, data, bytes);
        accessors.push_back(
            {{"bufferView", views.size() - 1}, {"componentType", component}, {"count", count}, {"type", type}});
        return int(accessors.size()) - 1;
    };
    const float positions[] = {0, 0, 0, 0.2f, 0, 0, 0, 1, 0, 0.2f, 1, 0, 0, 2, 0, 0.2f, 2, 0};
    const float deltas[] = {0, 0, 0, 0, 0, 0, 0.1f, 0, 0, 0.1f, 0, 0, 0.3f, 0, 0, 0.3f, 0, 0};
    const std::uint16_t indices[] = {0, 1, 3, 0, 3, 2, 2, 3, 5, 2, 5, 4};
    const std::uint8_t joints[] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
    const float weights[] = {1, 0, 0, 0, 1, 0, 0, 0, 0.5f, 0.5f, 0, 0, 0.5f, 0.5f, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
    const float ibm[] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0,  0, 1,
                         1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1};
    const float times[] = {0, 1, 2};
    const float turns[] = {0, 0, 0, 1, 0, 0, 0.7071068f, 0.7071068f, 0, 0, 0, 1};
    const float weight_keys[] = {0, 0, 0, 0, 1, 0, 0, 0, 0};  // in-tangent, value, out-tangent per key
    const float steps[] = {0, 0, 0, 0.5f, 0, 0, 0, 0, 0};
    const int p = add(positions, sizeof positions, 5126, 6, "VEC3");
    const int d = add(deltas, sizeof deltas, 5126, 6, "VEC3");
    const int i = add(indices, sizeof indices, 5123, 12, "SCALAR");
    const int j = add(joints, sizeof joints, 5121, 6, "VEC4");
    const int w = add(weights, sizeof weights, 5126, 6, "VEC4");
    const int b = add(ibm, sizeof ibm, 5126, 2, "MAT4");
    const int t = add(times, sizeof times, 5126, 3, "SCALAR");
    const int r = add(turns, sizeof turns, 5126, 3, "VEC4");
    const int m = add(weight_keys, sizeof weight_keys, 5126, 9, "SCALAR");
    const int s = add(steps, sizeof steps, 5126, 3, "VEC3");
    accessors[std::size_t(p)]["min"] = {0, 0, 0};
    accessors[std::size_t(p)]["max"] = {0.2, 2, 0};
    json doc;
    doc["asset"] = {{"version", "2.0"}};
    doc["scene"] = 0;
    doc["scenes"] = json::array({{{"nodes", {0, 1}}}});
    doc["nodes"] = json::array({{{"mesh", 0}, {"skin", 0}}, {{"children", {2}}}, {{"translation", {0, 1, 0}}}});
    doc["meshes"] =
        json::array({{{"primitives", json::array({{{"attributes", {{"POSITION", p}, {"JOINTS_0", j}, {"WEIGHTS_0", w}}},
                                                   {"indices", i},
                                                   {"targets", json::array({{{"POSITION", d}}})}}})},
                      {"weights", {0.0}}}});
    doc["skins"] = json::array({{{"joints", {1, 2}}, {"inverseBindMatrices", b}}});
    doc["animations"] = json::array(
        {{{"name", "bend"},
          {"samplers", json::array({{{"input", t}, {"output", r}, {"interpolation", "LINEAR"}},
                                    {{"input", t}, {"output", m}, {"interpolation", "CUBICSPLINE"}},
                                    {{"input", t}, {"output", s}, {"interpolation", "STEP"}}})},
          {"channels", json::array({{{"sampler", 0}, {"target", {{"node", 2}, {"path", "rotation"}}}},
                                    {{"sampler", 1}, {"target", {{"node", 0}, {"path", "weights"}}}},
                                    {{"sampler", 2}, {"target", {{"node", 1}, {"path", "translation"}}}}})}}});
    doc["bufferViews"] = views;
    doc["accessors"] = accessors;
    doc["buffers"] =
        json::array({{{"byteLength", bin.size()}, {"uri", "data:application/octet-stream;base64," + base64(bin)}}});
    write_text(path, doc.dump(1));
}

void write_sample_gltf_textured(const std::filesystem::path& path, const std::string& image_file) {
    std::vector<std::uint8_t> bin;
    json doc = box_document(bin);
    // Each face's four corners at the texture's corners: 24 vertices, in faces of four.
    const std::size_t uv_offset = bin.size();
    for (int v = 0; v < 24; ++v) {
        const float uv[2] = {float(v % 4 == 1 || v % 4 == 2), float(v % 4 >= 2)};
        append(bin, uv, sizeof uv);
    }
    // One tangent for every vertex, +x: it lies in four faces and is refused (then made) on the other two.
    const std::size_t tangent_offset = bin.size();
    for (int v = 0; v < 24; ++v) {
        const float tangent[4] = {1.0f, 0.0f, 0.0f, 1.0f};
        append(bin, tangent, sizeof tangent);
    }
    doc["buffers"][0]["byteLength"] = bin.size();
    doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", uv_offset}, {"byteLength", 24 * 8}});
    doc["accessors"].push_back({{"bufferView", 3}, {"componentType", 5126}, {"count", 24}, {"type", "VEC2"}});
    doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = 3;
    doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", tangent_offset}, {"byteLength", 24 * 16}});
    doc["accessors"].push_back({{"bufferView", 4}, {"componentType", 5126}, {"count", 24}, {"type", "VEC4"}});
    doc["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] = 4;
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {
        {"index", 0}, {"extensions", {{"KHR_texture_transform", {{"offset", {0.5, 0}}, {"scale", {2, 1}}}}}}};
    // Emission, occlusion, normal and metallic-roughness from the same texture on the same coordinates, the emission
    // factor scaled by the extension.
    doc["materials"][0]["emissiveTexture"] = doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"];
    doc["materials"][0]["emissiveFactor"] = {0.2, 0.1, 0.0};
    doc["materials"][0]["extensions"] = {{"KHR_materials_emissive_strength", {{"emissiveStrength", 2.0}}}};
    doc["materials"][0]["occlusionTexture"] = {{"index", 0}, {"strength", 0.5}};
    doc["materials"][0]["normalTexture"] = {{"index", 0}, {"scale", 0.7}};
    doc["materials"][0]["pbrMetallicRoughness"]["metallicRoughnessTexture"] =
        doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"];
    doc["materials"][0]["alphaMode"] = "MASK";
    doc["materials"][0]["alphaCutoff"] = 0.3;
    doc["samplers"] = json::array({{{"magFilter", 9728}, {"wrapS", 33648}, {"wrapT", 33071}}});
    doc["textures"] = json::array({{{"sampler", 0}, {"source", 0}}});
    std::vector<std::uint8_t> png;
    std::uint8_t texels[4 * 4 * 4];
    for (int i = 0; i < 16; ++i)
        for (int c = 0; c < 4; ++c) texels[i * 4 + c] = c == 3 ? 255 : std::uint8_t((i * 37 + c * 91) % 256);
    stbi_write_png_to_func(
        [](void* context, void* data, int size) {
            auto* out = static_cast<std::vector<std::uint8_t>*>(context);
            out->insert(out->end(), static_cast<std::uint8_t*>(data), static_cast<std::uint8_t*>(data) + size);
        },
        &png, 4, 4, 4, texels, 16);
    if (image_file.empty()) {
        doc["images"] = json::array({{{"uri", "data:image/png;base64," + base64(png)}}});
    } else {
        write_bytes(path.parent_path() / image_file, png);
        doc["images"] = json::array({{{"uri", image_file}}});
    }
    doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(bin);
    write_text(path, doc.dump(1));
}

std::string sample_scene_json(const std::string& model, const std::string& environment) {
    const json scene = {
        {"description", "every kind of key"},
        {"environment", {{"source", environment}, {"rotation", 30}, {"exposure", -0.5}}},
        {"camera", {{"position", {0, 2, 6}}, {"target", {0, 0.5, 0}}, {"up", {0, 1, 0}}, {"fov", 40}}},
        {"objects",
         json::array(
             {{{"name", "ground"}, {"mesh", {{"type", "plane"}, {"size", 10}}}, {"ground", true}},
              {{"model", model},
               {"fit", 1.0},
               {"transform", {{"translation", {-1, 0, 0}}, {"rotation", {0, 45, 0}}, {"scale", 1.5}}},
               {"material", {{"diffuse", {0.7, 0.6, 0.5}}, {"specular", 0.3}, {"shininess", 50}}}},
              {{"mesh", {{"type", "sphere"}, {"radius", 0.4}, {"segments", 16}}},
               {"transform", {{"rotation", {{"axis", {0, 1, 0}}, {"angle", 10}}}}},
               {"animation", {{"type", "orbit"}, {"center", {0, 0, 0}}, {"radius", 2}, {"height", 1}, {"period", 8}}}},
              {{"mesh", {{"type", "box"}, {"size", {0.5, 0.2, 0.3}}}},
               {"casts_shadows", false},
               {"animation",
                {{"type", "path"}, {"points", {{0, 1, 0}, {1, 1, 0}, {1, 1, 1}}}, {"face_motion", false}}}},
              {{"mesh",
                {{"type", "torus"}, {"major_radius", 0.5}, {"minor_radius", 0.1}, {"segments", 12}, {"sides", 6}}}},
              {{"mesh", {{"type", "blob"}, {"radius", 0.3}, {"triangles", 80}, {"lumpiness", 0.3}, {"seed", 3}}}},
              {{"mesh", {{"type", "figure"}, {"height", 1.7}, {"triangles", 2000}}}},
              {{"mesh", {{"type", "virus"}, {"radius", 0.2}, {"spikes", 6}, {"spike_length", 0.1}, {"detail", 2}}}}})}};
    return scene.dump(1);
}

}  // namespace envshadow::test
