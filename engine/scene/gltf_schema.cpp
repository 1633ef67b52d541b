#include "scene/gltf_schema.h"

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/error.h"

namespace envshadow {
namespace {

using nlohmann::json;

enum class Type {
    string,
    number,
    index,    // integer >= 0 (indices into arrays, counts, byte offsets)
    integer,  // any integer (enums such as componentType, mode)
    boolean,
    object,        // checked against `children` when given
    object_array,  // array of objects checked against `children`
    index_array,
    number_array,  // exactly `length` numbers when length > 0
    string_array,
    index_map,        // object whose values are indices (primitive attributes)
    index_map_array,  // array of index maps (morph targets)
    any,
};

struct Rule {
    const char* key;
    Type type;
    const std::vector<Rule>* children = nullptr;
    int length = 0;
    bool required = false;
};

// The glTF 2.0 core schema, as far as types go (https://registry.khronos.org/glTF/specs/2.0/).
const std::vector<Rule> kNone;
const std::vector<Rule> kAsset = {{"version", Type::string, nullptr, 0, true},
                                  {"minVersion", Type::string},
                                  {"generator", Type::string},
                                  {"copyright", Type::string}};
const std::vector<Rule> kScene = {{"nodes", Type::index_array}};
const std::vector<Rule> kNode = {{"children", Type::index_array},
                                 {"mesh", Type::index},
                                 {"camera", Type::index},
                                 {"skin", Type::index},
                                 {"matrix", Type::number_array, nullptr, 16},
                                 {"rotation", Type::number_array, nullptr, 4},
                                 {"scale", Type::number_array, nullptr, 3},
                                 {"translation", Type::number_array, nullptr, 3},
                                 {"weights", Type::number_array}};
const std::vector<Rule> kPrimitive = {{"attributes", Type::index_map, nullptr, 0, true},
                                      {"indices", Type::index},
                                      {"material", Type::index},
                                      {"mode", Type::integer},
                                      {"targets", Type::index_map_array}};
const std::vector<Rule> kMesh = {{"primitives", Type::object_array, &kPrimitive, 0, true},
                                 {"weights", Type::number_array}};
const std::vector<Rule> kSparseIndices = {{"bufferView", Type::index, nullptr, 0, true},
                                          {"byteOffset", Type::index},
                                          {"componentType", Type::integer, nullptr, 0, true}};
const std::vector<Rule> kSparseValues = {{"bufferView", Type::index, nullptr, 0, true}, {"byteOffset", Type::index}};
const std::vector<Rule> kSparse = {{"count", Type::index, nullptr, 0, true},
                                   {"indices", Type::object, &kSparseIndices, 0, true},
                                   {"values", Type::object, &kSparseValues, 0, true}};
const std::vector<Rule> kAccessor = {{"bufferView", Type::index},
                                     {"byteOffset", Type::index},
                                     {"componentType", Type::integer, nullptr, 0, true},
                                     {"normalized", Type::boolean},
                                     {"count", Type::index, nullptr, 0, true},
                                     {"type", Type::string, nullptr, 0, true},
                                     {"max", Type::number_array},
                                     {"min", Type::number_array},
                                     {"sparse", Type::object, &kSparse}};
const std::vector<Rule> kBufferView = {{"buffer", Type::index, nullptr, 0, true},
                                       {"byteOffset", Type::index},
                                       {"byteLength", Type::index, nullptr, 0, true},
                                       {"byteStride", Type::index},
                                       {"target", Type::integer}};
const std::vector<Rule> kBuffer = {{"uri", Type::string}, {"byteLength", Type::index, nullptr, 0, true}};
const std::vector<Rule> kTextureInfo = {{"index", Type::index, nullptr, 0, true}, {"texCoord", Type::index}};
const std::vector<Rule> kNormalTextureInfo = {
    {"index", Type::index, nullptr, 0, true}, {"texCoord", Type::index}, {"scale", Type::number}};
const std::vector<Rule> kOcclusionTextureInfo = {
    {"index", Type::index, nullptr, 0, true}, {"texCoord", Type::index}, {"strength", Type::number}};
const std::vector<Rule> kPbr = {{"baseColorFactor", Type::number_array, nullptr, 4},
                                {"baseColorTexture", Type::object, &kTextureInfo},
                                {"metallicFactor", Type::number},
                                {"roughnessFactor", Type::number},
                                {"metallicRoughnessTexture", Type::object, &kTextureInfo}};
const std::vector<Rule> kMaterial = {{"pbrMetallicRoughness", Type::object, &kPbr},
                                     {"normalTexture", Type::object, &kNormalTextureInfo},
                                     {"occlusionTexture", Type::object, &kOcclusionTextureInfo},
                                     {"emissiveTexture", Type::object, &kTextureInfo},
                                     {"emissiveFactor", Type::number_array, nullptr, 3},
                                     {"alphaMode", Type::string},
                                     {"alphaCutoff", Type::number},
                                     {"doubleSided", Type::boolean}};
const std::vector<Rule> kTexture = {{"sampler", Type::index}, {"source", Type::index}};
const std::vector<Rule> kImage = {{"uri", Type::string}, {"mimeType", Type::string}, {"bufferView", Type::index}};
const std::vector<Rule> kSampler = {
    {"magFilter", Type::integer}, {"minFilter", Type::integer}, {"wrapS", Type::integer}, {"wrapT", Type::integer}};
const std::vector<Rule> kSkin = {
    {"inverseBindMatrices", Type::index}, {"skeleton", Type::index}, {"joints", Type::index_array}};
const std::vector<Rule> kCamera = {
    {"type", Type::string}, {"perspective", Type::object}, {"orthographic", Type::object}};
const std::vector<Rule> kRoot = {{"asset", Type::object, &kAsset, 0, true},
                                 {"scene", Type::index},
                                 {"scenes", Type::object_array, &kScene},
                                 {"nodes", Type::object_array, &kNode},
                                 {"meshes", Type::object_array, &kMesh},
                                 {"accessors", Type::object_array, &kAccessor},
                                 {"bufferViews", Type::object_array, &kBufferView},
                                 {"buffers", Type::object_array, &kBuffer},
                                 {"materials", Type::object_array, &kMaterial},
                                 {"textures", Type::object_array, &kTexture},
                                 {"images", Type::object_array, &kImage},
                                 {"samplers", Type::object_array, &kSampler},
                                 {"skins", Type::object_array, &kSkin},
                                 {"cameras", Type::object_array, &kCamera},
                                 {"animations", Type::object_array, &kNone},
                                 {"extensionsUsed", Type::string_array},
                                 {"extensionsRequired", Type::string_array}};

class Checker {
public:
    explicit Checker(const std::filesystem::path& file) : file_(file) {}

    void object(const json& value, const std::vector<Rule>& rules, const std::string& where) const {
        if (!value.is_object()) fail(where, "expected an object");
        for (const Rule& rule : rules)
            if (const auto it = value.find(rule.key); it != value.end()) check(*it, rule, join(where, rule.key));
        for (const Rule& rule : rules)
            if (rule.required && !value.contains(rule.key)) fail(join(where, rule.key), "required property is missing");
        if (const auto it = value.find("name"); it != value.end() && !it->is_string())
            fail(join(where, "name"), "expected a string");
        if (const auto it = value.find("extensions"); it != value.end()) {
            if (!it->is_object()) fail(join(where, "extensions"), "expected an object");
            for (const auto& [name, extension] : it->items())
                if (!extension.is_object()) fail(join(where, "extensions") + "." + name, "expected an object");
        }
    }

private:
    static std::string join(const std::string& where, const std::string& key) {
        return where.empty() ? key : where + "." + key;
    }
    static std::string item(const std::string& where, std::size_t i) { return where + "[" + std::to_string(i) + "]"; }

    [[noreturn]] void fail(const std::string& where, const std::string& reason) const {
        throw InputError(file_.string() + ": " + where + ": " + reason);
    }

    void index(const json& value, const std::string& where) const {
        if (!value.is_number_integer() ||
            (value.is_number_integer() && !value.is_number_unsigned() && value.get<long long>() < 0))
            fail(where, "expected a non-negative integer");
    }

    void array(const json& value, const std::string& where) const {
        if (!value.is_array()) fail(where, "expected an array");
    }

    void check(const json& value, const Rule& rule, const std::string& where) const {
        switch (rule.type) {
            case Type::string:
                if (!value.is_string()) fail(where, "expected a string");
                break;
            case Type::number:
                if (!value.is_number()) fail(where, "expected a number");
                break;
            case Type::index:
                index(value, where);
                break;
            case Type::integer:
                if (!value.is_number_integer()) fail(where, "expected an integer");
                break;
            case Type::boolean:
                if (!value.is_boolean()) fail(where, "expected true or false");
                break;
            case Type::object:
                object(value, rule.children ? *rule.children : kNone, where);
                break;
            case Type::object_array:
                array(value, where);
                for (std::size_t i = 0; i < value.size(); ++i)
                    object(value[i], rule.children ? *rule.children : kNone, item(where, i));
                break;
            case Type::index_array:
                array(value, where);
                for (std::size_t i = 0; i < value.size(); ++i) index(value[i], item(where, i));
                break;
            case Type::number_array:
                array(value, where);
                if (rule.length > 0 && value.size() != std::size_t(rule.length))
                    fail(where,
                         "expected " + std::to_string(rule.length) + " numbers, found " + std::to_string(value.size()));
                for (std::size_t i = 0; i < value.size(); ++i)
                    if (!value[i].is_number()) fail(item(where, i), "expected a number");
                break;
            case Type::string_array:
                array(value, where);
                for (std::size_t i = 0; i < value.size(); ++i)
                    if (!value[i].is_string()) fail(item(where, i), "expected a string");
                break;
            case Type::index_map:
                if (!value.is_object()) fail(where, "expected an object");
                for (const auto& [name, v] : value.items()) index(v, where + "." + name);
                break;
            case Type::index_map_array:
                array(value, where);
                for (std::size_t i = 0; i < value.size(); ++i) {
                    if (!value[i].is_object()) fail(item(where, i), "expected an object");
                    for (const auto& [name, v] : value[i].items()) index(v, item(where, i) + "." + name);
                }
                break;
            case Type::any:
                break;
        }
    }

    const std::filesystem::path& file_;
};

}  // namespace

void check_gltf_json(const std::filesystem::path& file, const json& document) {
    if (!document.is_object()) throw InputError(file.string() + ": the glTF JSON is not an object");
    Checker(file).object(document, kRoot, "");
}

}  // namespace envshadow
