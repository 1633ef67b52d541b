#include "scene/gltf_accessor.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/error.h"

namespace envshadow {
namespace {

std::string type_name(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR:
            return "SCALAR";
        case TINYGLTF_TYPE_VEC2:
            return "VEC2";
        case TINYGLTF_TYPE_VEC3:
            return "VEC3";
        case TINYGLTF_TYPE_VEC4:
            return "VEC4";
        case TINYGLTF_TYPE_MAT2:
            return "MAT2";
        case TINYGLTF_TYPE_MAT3:
            return "MAT3";
        case TINYGLTF_TYPE_MAT4:
            return "MAT4";
        default:
            return "type " + std::to_string(type);
    }
}

std::string component_name(int component_type, bool normalized) {
    std::string name;
    switch (component_type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
            name = "byte";
            break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            name = "unsigned byte";
            break;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
            name = "short";
            break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            name = "unsigned short";
            break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
            name = "unsigned int";
            break;
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
            name = "float";
            break;
        default:
            return "componentType " + std::to_string(component_type);
    }
    return normalized ? "normalized " + name : name;
}

std::string expected(const AccessorSpec& spec) {
    std::string kinds;
    auto add = [&](const std::string& k) { kinds += (kinds.empty() ? "" : " or ") + k; };
    if (spec.floats) add("float");
    if (spec.normalized) add("normalized unsigned byte/short");
    if (spec.signed_normalized) add("normalized byte/short");
    if (spec.unsigned_ints) add("unsigned byte/short");
    return type_name(spec.type) + " " + kinds;
}

}  // namespace

void GltfAccessors::fail(const std::string& reason) const {
    throw InputError(file_.string() + ": " + reason);
}

std::size_t GltfAccessors::count(int index, const std::string& what) const {
    if (index < 0 || std::size_t(index) >= model_.accessors.size())
        fail(what + " uses accessor " + std::to_string(index) + ", which does not exist");
    return model_.accessors[std::size_t(index)].count;
}

GltfAccessors::Raw GltfAccessors::raw(int index, const AccessorSpec& spec, const std::string& what) const {
    count(index, what);
    const tinygltf::Accessor& a = model_.accessors[std::size_t(index)];
    const std::string name = what + " (accessor " + std::to_string(index) + ")";
    const int ct = a.componentType;
    const bool is_float = ct == TINYGLTF_COMPONENT_TYPE_FLOAT && !a.normalized;
    const bool is_unsigned_small =
        ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
    const bool is_signed_small = ct == TINYGLTF_COMPONENT_TYPE_BYTE || ct == TINYGLTF_COMPONENT_TYPE_SHORT;
    const bool ok =
        a.type == spec.type && ((spec.floats && is_float) || (spec.normalized && a.normalized && is_unsigned_small) ||
                                (spec.signed_normalized && a.normalized && is_signed_small) ||
                                (spec.unsigned_ints && !a.normalized && is_unsigned_small));
    if (!ok)
        fail(name + ": expected " + expected(spec) + ", got " + type_name(a.type) + " " +
             component_name(ct, a.normalized));
    if (a.sparse.isSparse) fail(name + " is sparse, which is not supported");
    if (a.bufferView < 0 || std::size_t(a.bufferView) >= model_.bufferViews.size())
        fail(name + " has no valid bufferView");
    const int component_size = tinygltf::GetComponentSizeInBytes(std::uint32_t(ct));
    const int components = tinygltf::GetNumComponentsInType(std::uint32_t(a.type));
    const tinygltf::BufferView& view = model_.bufferViews[std::size_t(a.bufferView)];
    const std::string view_name = "bufferView " + std::to_string(a.bufferView);
    if (view.buffer < 0 || std::size_t(view.buffer) >= model_.buffers.size()) fail(view_name + " has no valid buffer");
    const std::size_t buffer_size = model_.buffers[std::size_t(view.buffer)].data.size();
    if (view.byteOffset > buffer_size || view.byteLength > buffer_size - view.byteOffset)
        fail(view_name + " runs past the end of buffer " + std::to_string(view.buffer));
    const std::size_t element = std::size_t(component_size) * std::size_t(components);
    const std::size_t stride = view.byteStride != 0 ? view.byteStride : element;
    if (stride < element || stride > 252 || stride % std::size_t(component_size) != 0)
        fail(view_name + " has byteStride " + std::to_string(view.byteStride) + ", invalid for " + name);
    if (a.count > 0 && (a.byteOffset > view.byteLength || element > view.byteLength - a.byteOffset ||
                        (a.count - 1) > (view.byteLength - a.byteOffset - element) / stride))
        fail(name + " (" + std::to_string(a.count) + " elements) runs past the end of " + view_name);
    Raw r;
    r.bytes = model_.buffers[std::size_t(view.buffer)].data.data() + view.byteOffset + a.byteOffset;
    r.stride = stride;
    r.count = a.count;
    r.components = components;
    r.component_type = ct;
    r.normalized = a.normalized;
    return r;
}

std::vector<float> GltfAccessors::floats(int index, const AccessorSpec& spec, const std::string& what) const {
    const Raw r = raw(index, spec, what);
    std::vector<float> out(r.count * std::size_t(r.components));
    for (std::size_t i = 0; i < r.count; ++i) {
        const unsigned char* p = r.bytes + i * r.stride;
        for (int c = 0; c < r.components; ++c) {
            float v = 0.0f;
            switch (r.component_type) {
                case TINYGLTF_COMPONENT_TYPE_FLOAT:
                    std::memcpy(&v, p + 4 * c, 4);
                    break;
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
                    v = float(p[c]) / 255.0f;
                    break;
                case TINYGLTF_COMPONENT_TYPE_BYTE: {
                    std::int8_t s;
                    std::memcpy(&s, p + c, 1);
                    v = std::max(float(s) / 127.0f, -1.0f);
                    break;
                }
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                    std::uint16_t s;
                    std::memcpy(&s, p + 2 * c, 2);
                    v = float(s) / 65535.0f;
                    break;
                }
                case TINYGLTF_COMPONENT_TYPE_SHORT: {
                    std::int16_t s;
                    std::memcpy(&s, p + 2 * c, 2);
                    v = std::max(float(s) / 32767.0f, -1.0f);
                    break;
                }
                default:
                    break;
            }
            if (!std::isfinite(v))
                fail(what + " (accessor " + std::to_string(index) + ") element " + std::to_string(i) +
                     " is not finite");
            out[i * std::size_t(r.components) + std::size_t(c)] = v;
        }
    }
    return out;
}

std::vector<std::uint32_t> GltfAccessors::uints(int index, const AccessorSpec& spec, const std::string& what) const {
    const Raw r = raw(index, spec, what);
    std::vector<std::uint32_t> out(r.count * std::size_t(r.components));
    for (std::size_t i = 0; i < r.count; ++i) {
        const unsigned char* p = r.bytes + i * r.stride;
        for (int c = 0; c < r.components; ++c) {
            std::uint32_t v = 0;
            if (r.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
                v = p[c];
            } else {
                std::uint16_t s;
                std::memcpy(&s, p + 2 * c, 2);
                v = s;
            }
            out[i * std::size_t(r.components) + std::size_t(c)] = v;
        }
    }
    return out;
}

}  // namespace envshadow
