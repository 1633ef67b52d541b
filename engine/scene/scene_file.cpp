// Scene files (docs/SCENES.md) and bare glTF models as scenes.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "scene/gltf.h"
#include "scene/gltf_animation.h"
#include "scene/gltf_material.h"
#include "scene/meshes.h"
#include "scene/scene.h"

namespace envshadow {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

constexpr const char* kDefaultEnvironmentFile = "/usr/share/blender/datafiles/studiolights/world/courtyard.exr";
constexpr float kBareModelSize = 2.0f;      // metres: a bare glTF's largest side
constexpr float kBareGroundFactor = 15.0f;  // ground plane side, in model sizes: room for long shadows
constexpr int kMaxJsonDepth = 64;           // nesting of JSON values: dump() and the reader recurse

std::string lowercase_extension(const fs::path& path) {
    std::string e = path.extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return e;
}

// world_from_model that scales a model of bounds [lo, hi] uniformly so that its largest side is `size`,
// centred on the Y axis, standing on y = 0.
glm::mat4 fit_standing(const glm::vec3& lo, const glm::vec3& hi, float size) {
    const glm::vec3 extent = hi - lo;
    const float largest = std::max({extent.x, extent.y, extent.z});
    const float scale = largest > 0.0f ? size / largest : 1.0f;
    const glm::vec3 base(0.5f * (lo.x + hi.x), lo.y, 0.5f * (lo.z + hi.z));
    return glm::scale(glm::mat4(1.0f), glm::vec3(scale)) * glm::translate(glm::mat4(1.0f), -base);
}

// Bounds of the objects that are not the ground, at time t.
void bounds_without_ground(const Scene& scene, const std::vector<bool>& is_ground, double t, glm::vec3& lo,
                           glm::vec3& hi) {
    Scene others;
    for (std::size_t i = 0; i < scene.objects.size(); ++i)
        if (!is_ground[i]) others.objects.push_back(scene.objects[i]);
    others.bounds_at(t, lo, hi);
}

// The part's deformation by clip `clip` of its model (none for clip -1 or a model without a rig).
void attach_clip(Object& object, const GltfModel& model, const GltfPart& part, int clip, bool loop) {
    if (!model.rig || !part.sources || clip < 0) return;
    object.deformation = std::make_shared<const MeshDeformation>(model.rig, part.sources, part.mesh, clip, loop);
}

// The clip a bare model plays: its first.
int first_clip(const GltfModel& model) {
    return model.rig && !model.rig->clips.empty() ? 0 : -1;
}

class SceneReader {
public:
    explicit SceneReader(const fs::path& file) : file_(file), folder_(file.parent_path()) {}

    Scene read(const json& document) {
        expect_keys(document, "", {"description", "environment", "camera", "objects"});
        Scene scene;
        scene.file = file_;
        if (const auto it = document.find("description"); it != document.end()) text(*it, "description");
        if (const auto it = document.find("environment"); it != document.end()) scene.environment = environment(*it);

        const auto objects = document.find("objects");
        if (objects == document.end()) fail("objects", "required: the list of objects");
        if (!objects->is_array() || objects->empty()) fail("objects", "expected a non-empty array of objects");
        // The sizes built-in meshes ask for, summed before any is built (building them takes seconds).
        double declared = 0.0;
        for (const json& o : *objects) declared += declared_triangles(o);
        if (declared > double(kMaxSceneTriangles)) fail("objects", too_many_triangles());
        std::vector<bool> is_ground;
        std::size_t triangles = 0;
        for (std::size_t i = 0; i < objects->size(); ++i) {
            bool ground = false;
            // A model gives one object per material (GltfModel::parts).
            for (Object& o : read_objects((*objects)[i], "objects[" + std::to_string(i) + "]", ground)) {
                triangles += o.mesh->triangle_count();
                scene.objects.push_back(std::move(o));
                is_ground.push_back(ground);
            }
            if (triangles > kMaxSceneTriangles) fail("objects[" + std::to_string(i) + "]", too_many_triangles());
            if (ground) {
                if (scene.has_ground)
                    fail("objects[" + std::to_string(i) + "].ground", "only one object can be the ground");
                scene.has_ground = true;
                scene.ground_height = scene.objects.back().transform[3].y;
            }
        }

        if (const auto it = document.find("camera"); it != document.end()) {
            scene.camera = camera(*it);
        } else {  // frame what stands on the ground
            glm::vec3 lo, hi;
            bounds_without_ground(scene, is_ground, 0.0, lo, hi);
            scene.camera = camera_framing(lo, hi);
        }
        return scene;
    }

private:
    [[noreturn]] void fail(const std::string& where, const std::string& reason) const {
        throw InputError(file_.string() + ": " + where + ": " + reason);
    }
    static std::string too_many_triangles() {
        return "the scene has more than " + std::to_string(kMaxSceneTriangles) + " triangles (limit)";
    }
    // Triangles a built-in mesh asks for (meshes.h), from its parameters as written: 0 for anything
    // else, or for values of the wrong type (reported when the mesh is read).
    static double declared_triangles(const json& object) {
        const auto mesh = object.is_object() ? object.find("mesh") : object.end();
        if (!object.is_object() || mesh == object.end() || !mesh->is_object()) return 0.0;
        const auto get = [&](const char* key, double fallback) {
            const auto it = mesh->find(key);
            return it != mesh->end() && it->is_number() ? it->get<double>() : fallback;
        };
        const auto type = mesh->find("type");
        if (type == mesh->end() || !type->is_string()) return 0.0;
        if (*type == "sphere") {
            const double segments = get("segments", SphereShape{}.segments);
            return 2.0 * segments * (segments / 2.0 - 1.0);
        }
        if (*type == "torus") return 2.0 * get("segments", TorusShape{}.segments) * get("sides", TorusShape{}.sides);
        if (*type == "blob") return get("triangles", BlobShape{}.triangles);
        if (*type == "figure") return get("triangles", FigureShape{}.triangles);
        return 0.0;
    }
    static std::string join(const std::string& where, const std::string& key) {
        return where.empty() ? key : where + "." + key;
    }

    // Unknown keys are errors: they are nearly always typos.
    void expect_keys(const json& value, const std::string& where, std::initializer_list<const char*> keys) const {
        if (!value.is_object()) fail(where.empty() ? "scene" : where, "expected an object");
        for (const auto& item : value.items()) {
            const std::string& key = item.key();  // not a structured binding: clang 14 cannot capture those
            if (std::find_if(keys.begin(), keys.end(), [&](const char* k) { return key == k; }) != keys.end()) continue;
            std::string known;
            for (const char* k : keys) known += std::string(known.empty() ? "" : ", ") + k;
            fail(join(where, key), "unknown key (expected one of: " + known + ")");
        }
    }

    float number(const json& value, const std::string& where) const {
        if (!value.is_number()) fail(where, "expected a number");
        const double v = value.get<double>();
        if (!std::isfinite(v) || std::abs(v) > 1e30) fail(where, "number out of range");
        return float(v);
    }
    float number_in(const json& value, const std::string& where, float lo, float hi) const {
        const float v = number(value, where);
        if (v < lo || v > hi)
            fail(where, "must be between " + format(lo) + " and " + format(hi) + ", found " + format(v));
        return v;
    }
    float positive(const json& value, const std::string& where) const {
        const float v = number(value, where);
        if (!(v > 0.0f)) fail(where, "must be greater than 0, found " + format(v));
        return v;
    }
    int integer_in(const json& value, const std::string& where, int lo, int hi) const {
        if (!value.is_number() || value.get<double>() != std::floor(value.get<double>()))
            fail(where, "expected an integer");
        const double v = value.get<double>();
        if (v < lo || v > hi)
            fail(where, "must be between " + std::to_string(lo) + " and " + std::to_string(hi) + ", found " +
                            format(float(v)));
        return int(v);
    }
    bool boolean(const json& value, const std::string& where) const {
        if (!value.is_boolean()) fail(where, "expected true or false");
        return value.get<bool>();
    }
    std::string text(const json& value, const std::string& where) const {
        if (!value.is_string()) fail(where, "expected a string");
        return value.get<std::string>();
    }
    glm::vec3 vec3(const json& value, const std::string& where) const {
        if (!value.is_array() || value.size() != 3) fail(where, "expected an array of 3 numbers");
        return {number(value[0], where + "[0]"), number(value[1], where + "[1]"), number(value[2], where + "[2]")};
    }
    // A number for all three components, or three numbers.
    glm::vec3 scalar_or_vec3(const json& value, const std::string& where) const {
        if (value.is_number()) return glm::vec3(number(value, where));
        if (!value.is_array() || value.size() != 3) fail(where, "expected a number or an array of 3 numbers");
        return vec3(value, where);
    }
    static std::string format(float v) {
        std::ostringstream s;
        s << v;
        return s.str();
    }

    // Relative paths are relative to the scene file's folder.
    fs::path resolve(const std::string& path) const {
        const fs::path p(path);
        return (p.is_absolute() ? p : folder_ / p).lexically_normal();
    }
    void require_file(const fs::path& path, const std::string& where) const {
        std::error_code ec;
        if (!fs::is_regular_file(path, ec)) fail(where, path.string() + " not found");
    }

    // Coordinates past kMaxCoordinate make bounds, extents and projection fits overflow downstream.
    void require_within_limit(const glm::vec3& p, const std::string& where) const {
        if (!(std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}) <= kMaxCoordinate))
            fail(where, "lies beyond 1e12 (coordinate limit)");
    }
    void require_within_limit(const glm::mat4& world_from_object, const glm::vec3& lo, const glm::vec3& hi,
                              const std::string& where) const {
        for (int corner = 0; corner < 8; ++corner) {
            const glm::vec3 p(corner & 1 ? hi.x : lo.x, corner & 2 ? hi.y : lo.y, corner & 4 ? hi.z : lo.z);
            const glm::dvec4 w = glm::dmat4(world_from_object) * glm::dvec4(glm::dvec3(p), 1.0);
            if (!(std::max({std::abs(w.x), std::abs(w.y), std::abs(w.z)}) <= kMaxCoordinate))
                fail(where, "puts the object beyond 1e12 (coordinate limit)");
        }
    }

    EnvironmentSettings environment(const json& value) {
        EnvironmentSettings env;
        const json* source = &value;
        if (value.is_object()) {
            expect_keys(value, "environment", {"source", "rotation", "exposure"});
            if (const auto it = value.find("rotation"); it != value.end())
                env.rotation_degrees = number(*it, "environment.rotation");
            if (const auto it = value.find("exposure"); it != value.end())
                env.exposure_stops = number_in(*it, "environment.exposure", -30.0f, 30.0f);
            const auto it = value.find("source");
            if (it == value.end()) fail("environment.source", "required: a map file or builtin:...");
            source = &*it;
        } else if (!value.is_string()) {
            fail("environment", "expected a map file, builtin:... or an object");
        }
        const std::string where = value.is_object() ? "environment.source" : "environment";
        const std::string spec = text(*source, where);
        if (spec.rfind("builtin:", 0) == 0) {
            env.source = spec;  // parsed (and checked) by load_environment
        } else {
            const fs::path path = resolve(spec);
            require_file(path, where);
            env.source = path.string();
        }
        return env;
    }

    Camera camera(const json& value) const {
        expect_keys(value, "camera", {"position", "target", "up", "fov"});
        Camera c;
        const auto position = value.find("position");
        const auto target = value.find("target");
        if (position == value.end()) fail("camera.position", "required");
        if (target == value.end()) fail("camera.target", "required");
        c.position = vec3(*position, "camera.position");
        c.target = vec3(*target, "camera.target");
        require_within_limit(c.position, "camera.position");
        require_within_limit(c.target, "camera.target");
        if (const auto it = value.find("up"); it != value.end()) c.up = vec3(*it, "camera.up");
        if (const auto it = value.find("fov"); it != value.end())
            c.fov_y_degrees = number_in(*it, "camera.fov", 1.0f, 170.0f);
        const glm::vec3 forward = c.target - c.position;
        if (!(glm::length(forward) > 1e-6f)) fail("camera", "position and target are the same point");
        if (!(glm::length(glm::cross(glm::normalize(forward), c.up)) > 1e-3f))
            fail("camera.up", "is parallel to the view direction");
        return c;
    }

    std::shared_ptr<const Mesh> builtin_mesh(const json& value, const std::string& where) {
        const json spec = value.is_string() ? json{{"type", value}} : value;
        if (!spec.is_object()) fail(where, "expected a built-in mesh name or an object with \"type\"");
        const auto type_it = spec.find("type");
        if (type_it == spec.end()) fail(where + ".type", "required: plane, sphere, torus, box, blob, figure or virus");
        const std::string type = text(*type_it, where + ".type");
        const std::string key = spec.dump();
        if (const auto it = builtin_cache_.find(key); it != builtin_cache_.end()) return it->second;

        const auto get = [&](const char* name) -> const json* {
            const auto it = spec.find(name);
            return it == spec.end() ? nullptr : &*it;
        };
        const auto at = [&](const char* name) { return where + "." + name; };
        Mesh mesh;
        if (type == "plane") {
            expect_keys(spec, where, {"type", "size"});
            PlaneShape s;
            if (auto v = get("size")) s.size = positive(*v, at("size"));
            mesh = make_mesh(s);
        } else if (type == "sphere") {
            expect_keys(spec, where, {"type", "radius", "segments"});
            SphereShape s;
            if (auto v = get("radius")) s.radius = positive(*v, at("radius"));
            if (auto v = get("segments")) s.segments = integer_in(*v, at("segments"), 4, 3000);
            mesh = make_mesh(s);
        } else if (type == "torus") {
            expect_keys(spec, where, {"type", "major_radius", "minor_radius", "segments", "sides"});
            TorusShape s;
            if (auto v = get("major_radius")) s.major_radius = positive(*v, at("major_radius"));
            if (auto v = get("minor_radius")) s.minor_radius = positive(*v, at("minor_radius"));
            if (auto v = get("segments")) s.segments = integer_in(*v, at("segments"), 3, kMaxSegments);
            if (auto v = get("sides")) s.sides = integer_in(*v, at("sides"), 3, kMaxSegments);
            if (s.minor_radius >= s.major_radius) fail(at("minor_radius"), "must be smaller than major_radius");
            if (2ll * s.segments * s.sides > kMaxBuiltinTriangles)
                fail(where, "too many triangles (segments * sides * 2 > 5000000)");
            mesh = make_mesh(s);
        } else if (type == "box") {
            expect_keys(spec, where, {"type", "size"});
            BoxShape s;
            if (auto v = get("size")) s.size = scalar_or_vec3(*v, at("size"));
            if (!(std::min({s.size.x, s.size.y, s.size.z}) > 0.0f)) fail(at("size"), "must be greater than 0");
            mesh = make_mesh(s);
        } else if (type == "blob") {
            expect_keys(spec, where, {"type", "radius", "triangles", "lumpiness", "seed"});
            BlobShape s;
            if (auto v = get("radius")) s.radius = positive(*v, at("radius"));
            if (auto v = get("triangles")) s.triangles = integer_in(*v, at("triangles"), 20, kMaxBuiltinTriangles);
            if (auto v = get("lumpiness")) s.lumpiness = number_in(*v, at("lumpiness"), 0.0f, 1.0f);
            if (auto v = get("seed")) s.seed = std::uint32_t(integer_in(*v, at("seed"), 0, 1'000'000'000));
            mesh = make_mesh(s);
        } else if (type == "figure") {
            expect_keys(spec, where, {"type", "height", "triangles"});
            FigureShape s;
            if (auto v = get("height")) s.height = positive(*v, at("height"));
            if (auto v = get("triangles")) s.triangles = integer_in(*v, at("triangles"), 2000, kMaxBuiltinTriangles);
            mesh = make_mesh(s);
        } else if (type == "virus") {
            expect_keys(spec, where, {"type", "radius", "spikes", "spike_length", "detail"});
            VirusShape s;
            if (auto v = get("radius")) s.radius = positive(*v, at("radius"));
            if (auto v = get("spikes")) s.spikes = integer_in(*v, at("spikes"), 0, kMaxSpikes);
            if (auto v = get("spike_length")) s.spike_length = positive(*v, at("spike_length"));
            if (auto v = get("detail")) s.detail = integer_in(*v, at("detail"), 1, 200);
            mesh = make_mesh(s);
        } else {
            fail(where + ".type",
                 "unknown built-in mesh \"" + type + "\" (expected plane, sphere, torus, box, blob, figure or virus)");
        }
        auto shared = std::make_shared<const Mesh>(std::move(mesh));
        builtin_cache_.emplace(key, shared);
        return shared;
    }

    const GltfModel& model(const json& value, const std::string& where) {
        const fs::path path = resolve(text(value, where));
        if (const auto it = model_cache_.find(path.string()); it != model_cache_.end()) return it->second;
        require_file(path, where);
        try {
            return model_cache_.emplace(path.string(), load_gltf(path)).first->second;
        } catch (const InputError& e) {
            fail(where, e.what());  // names the scene and, inside, the glTF file
        }
    }

    glm::mat4 rotation(const json& value, const std::string& where) const {
        if (value.is_array()) {  // Euler angles in degrees, applied about X, then Y, then Z (fixed axes)
            const glm::vec3 degrees = vec3(value, where);
            glm::mat4 r(1.0f);
            r = glm::rotate(r, glm::radians(degrees.z), glm::vec3(0, 0, 1));
            r = glm::rotate(r, glm::radians(degrees.y), glm::vec3(0, 1, 0));
            r = glm::rotate(r, glm::radians(degrees.x), glm::vec3(1, 0, 0));
            return r;
        }
        expect_keys(value, where, {"axis", "angle"});
        const auto axis = value.find("axis");
        const auto angle = value.find("angle");
        if (axis == value.end() || angle == value.end())
            fail(where, "expected [x, y, z] Euler degrees or {\"axis\": [x, y, z], \"angle\": degrees}");
        const glm::vec3 a = vec3(*axis, where + ".axis");
        if (!(glm::length(a) > 1e-6f)) fail(where + ".axis", "must not be zero");
        return glm::rotate(glm::mat4(1.0f), glm::radians(number(*angle, where + ".angle")), glm::normalize(a));
    }

    glm::mat4 transform(const json& value, const std::string& where) const {
        expect_keys(value, where, {"translation", "rotation", "scale"});
        glm::mat4 m(1.0f);
        if (const auto it = value.find("translation"); it != value.end())
            m = glm::translate(m, vec3(*it, where + ".translation"));
        if (const auto it = value.find("rotation"); it != value.end()) m = m * rotation(*it, where + ".rotation");
        if (const auto it = value.find("scale"); it != value.end()) {
            const glm::vec3 s = scalar_or_vec3(*it, where + ".scale");
            if (!(std::min({s.x, s.y, s.z}) > 0.0f))
                fail(where + ".scale", "must be greater than 0 (mirroring is not supported)");
            m = glm::scale(m, s);
        }
        return m;
    }

    // The keys given replace those of `base` (a model part's mapped material, or Material{}); "diffuse"
    // replaces its base-colour texture too. Either the paper's Phong parameters ("diffuse", "specular",
    // "shininess", which leave the glTF BRDF) or glTF's ("base_color", "metallic", "roughness").
    // "emission" (either model) replaces the emitted radiance and its texture.
    Material material(const json& value, const std::string& where, const Material& base) const {
        expect_keys(value, where,
                    {"diffuse", "specular", "shininess", "base_color", "metallic", "roughness", "emission"});
        const bool phong = value.contains("diffuse") || value.contains("specular") || value.contains("shininess");
        const bool gltf = value.contains("base_color") || value.contains("metallic") || value.contains("roughness");
        if (phong && gltf)
            fail(where,
                 "give either diffuse/specular/shininess (Phong) or base_color/metallic/roughness (glTF), not both");
        Material m = gltf    ? metallic_roughness_material(value, where, base)
                     : phong ? phong_material(value, where, base)
                             : base;  // "emission" alone: the BRDF stays the model's
        if (const auto it = value.find("emission"); it != value.end()) {
            m.emission = scalar_or_vec3(*it, where + ".emission");
            if (!(std::min({m.emission.r, m.emission.g, m.emission.b}) >= 0.0f) ||
                !(std::max({m.emission.r, m.emission.g, m.emission.b}) <= 1e6f))
                fail(where + ".emission", "radiance components must be between 0 and 1e6");
            m.emission_texture.reset();
        }
        return m;
    }

    Material phong_material(const json& value, const std::string& where, const Material& base) const {
        Material m = base;
        m.metallic_roughness.reset();
        m.metallic_roughness_texture.reset();  // it scales glTF's factors, which the Phong material has not
        if (const auto it = value.find("diffuse"); it != value.end()) {
            m.rho_d = scalar_or_vec3(*it, where + ".diffuse");
            if (std::min({m.rho_d.r, m.rho_d.g, m.rho_d.b}) < 0.0f ||
                std::max({m.rho_d.r, m.rho_d.g, m.rho_d.b}) > 1.0f)
                fail(where + ".diffuse", "albedo components must be between 0 and 1");
            m.base_color_texture.reset();  // a colour given is the colour seen, not a tint of the texture
        }
        if (const auto it = value.find("specular"); it != value.end())
            m.rho_s = number_in(*it, where + ".specular", 0.0f, 1.0f);
        if (const auto it = value.find("shininess"); it != value.end())
            m.shininess = number_in(*it, where + ".shininess", 0.0f, 100000.0f);
        return m;
    }

    // glTF's metallic-roughness parameters; those not given are the base's (glTF's defaults, 1, where the base
    // has none). "base_color" replaces the base-colour texture, as "diffuse" does; "metallic" or "roughness"
    // replaces the metallic-roughness texture, which holds both.
    Material metallic_roughness_material(const json& value, const std::string& where, const Material& base) const {
        MetallicRoughness p = base.metallic_roughness.value_or(MetallicRoughness{});
        bool keeps_texture = true;
        const bool keeps_parameters_texture = !value.contains("metallic") && !value.contains("roughness");
        if (const auto it = value.find("base_color"); it != value.end()) {
            p.base_color = scalar_or_vec3(*it, where + ".base_color");
            if (std::min({p.base_color.r, p.base_color.g, p.base_color.b}) < 0.0f ||
                std::max({p.base_color.r, p.base_color.g, p.base_color.b}) > 1.0f)
                fail(where + ".base_color", "components must be between 0 and 1");
            keeps_texture = false;
        }
        if (const auto it = value.find("metallic"); it != value.end())
            p.metallic = number_in(*it, where + ".metallic", 0.0f, 1.0f);
        if (const auto it = value.find("roughness"); it != value.end())
            p.roughness = number_in(*it, where + ".roughness", 0.0f, 1.0f);
        Material m = with_metallic_roughness(base, p);
        if (!keeps_texture) m.base_color_texture.reset();
        if (!keeps_parameters_texture) m.metallic_roughness_texture.reset();
        return m;
    }

    // A clip by index, by name, or false (none).
    int pick_clip(const GltfModel& gltf, const json& value, const std::string& where) const {
        const std::size_t count = gltf.rig ? gltf.rig->clips.size() : 0;
        if (value.is_boolean()) {
            if (value.get<bool>()) fail(where, "expected a clip name or index, or false for none");
            return -1;
        }
        if (value.is_number()) {
            const double index = value.get<double>();
            if (!(index >= 0.0) || index != std::floor(index) || index >= double(count))
                fail(where, "clip " + value.dump() + " does not exist (the model has " + std::to_string(count) +
                                " animations)");
            return int(index);
        }
        const std::string name = text(value, where);
        std::string names;
        for (std::size_t i = 0; i < count; ++i) {
            if (gltf.rig->clips[i].name == name) return int(i);
            names += (names.empty() ? "" : ", ") + ("\"" + gltf.rig->clips[i].name + "\"");
        }
        fail(where,
             "no animation named \"" + name + "\" (the model has " + (count ? names : std::string("none")) + ")");
    }

    Animation animation(const json& value, const std::string& where) const {
        if (!value.is_object()) fail(where, "expected an object with \"type\": \"orbit\" or \"path\"");
        const auto type_it = value.find("type");
        if (type_it == value.end()) fail(where + ".type", "required: orbit or path");
        const std::string type = text(*type_it, where + ".type");
        Animation a;
        if (type == "orbit") {
            expect_keys(value, where, {"type", "center", "radius", "height", "period", "face_motion"});
            a.kind = Animation::Kind::orbit;
            if (const auto it = value.find("center"); it != value.end()) a.center = vec3(*it, where + ".center");
            if (const auto it = value.find("radius"); it != value.end())
                a.radius = number_in(*it, where + ".radius", 0.0f, 1e6f);
            if (const auto it = value.find("height"); it != value.end()) a.height = number(*it, where + ".height");
            require_within_limit(a.center + glm::vec3(a.radius, a.height, a.radius), where);
            require_within_limit(a.center - glm::vec3(a.radius, -a.height, a.radius), where);
        } else if (type == "path") {
            expect_keys(value, where, {"type", "points", "period", "face_motion"});
            a.kind = Animation::Kind::path;
            const auto points = value.find("points");
            if (points == value.end() || !points->is_array() || points->size() < 2)
                fail(where + ".points", "expected an array of at least 2 points [x, y, z]");
            for (std::size_t i = 0; i < points->size(); ++i)
                a.points.push_back(vec3((*points)[i], where + ".points[" + std::to_string(i) + "]"));
            for (std::size_t i = 0; i < a.points.size(); ++i)
                require_within_limit(a.points[i], where + ".points[" + std::to_string(i) + "]");
            double length = 0.0;
            for (std::size_t i = 0; i < a.points.size(); ++i)
                length += glm::distance(a.points[i], a.points[(i + 1) % a.points.size()]);
            if (!(length > 0.0)) fail(where + ".points", "the path has zero length");
        } else {
            fail(where + ".type", "unknown animation \"" + type + "\" (expected orbit or path)");
        }
        if (const auto it = value.find("period"); it != value.end()) a.period = positive(*it, where + ".period");
        if (const auto it = value.find("face_motion"); it != value.end())
            a.face_motion = boolean(*it, where + ".face_motion");
        return a;
    }

    std::vector<Object> read_objects(const json& value, const std::string& where, bool& ground) {
        expect_keys(value, where,
                    {"name", "model", "mesh", "fit", "transform", "material", "animation", "ground", "casts_shadows"});
        const auto model_it = value.find("model");
        const auto mesh_it = value.find("mesh");
        if ((model_it == value.end()) == (mesh_it == value.end()))
            fail(where, "needs exactly one of \"model\" (a glTF file) or \"mesh\" (a built-in mesh)");

        Object object;
        const GltfModel* gltf = nullptr;
        glm::vec3 lo, hi;  // the whole model's bounds
        if (model_it != value.end()) {
            gltf = &model(*model_it, where + ".model");
            object.name = resolve(model_it->get<std::string>()).stem().string();
            lo = gltf->bounds_min;
            hi = gltf->bounds_max;
        } else {
            object.mesh = builtin_mesh(*mesh_it, where + ".mesh");
            object.name = mesh_it->is_string() ? mesh_it->get<std::string>() : (*mesh_it)["type"].get<std::string>();
            lo = object.mesh->bounds_min;
            hi = object.mesh->bounds_max;
        }
        if (const auto it = value.find("name"); it != value.end()) object.name = text(*it, where + ".name");

        glm::mat4 fit(1.0f);
        if (const auto it = value.find("fit"); it != value.end())
            fit = fit_standing(lo, hi, positive(*it, where + ".fit"));
        glm::mat4 placement(1.0f);
        if (const auto it = value.find("transform"); it != value.end())
            placement = transform(*it, where + ".transform");
        object.transform = placement * fit;
        require_within_limit(object.transform, lo, hi, where + ".transform");

        const auto material_it = value.find("material");
        if (material_it != value.end() && !gltf)
            object.material = material(*material_it, where + ".material", Material{});
        // glTF animation: "animation" names the clip (name or index, false for none) or, as an object,
        // holds "clip" and "loop" beside (or instead of) an orbit or path.
        int clip = gltf ? first_clip(*gltf) : -1;
        bool loop = true;
        if (const auto it = value.find("animation"); it != value.end()) {
            const std::string at = where + ".animation";
            json motion = *it;
            const json* choice = nullptr;
            json clip_value;
            if (it->is_string() || it->is_number() || it->is_boolean()) {
                clip_value = *it;
                choice = &clip_value;
                motion = nullptr;
            } else if (it->is_object()) {
                if (const auto c = it->find("clip"); c != it->end()) {
                    clip_value = *c;
                    choice = &clip_value;
                    motion.erase("clip");
                }
                if (const auto l = it->find("loop"); l != it->end()) {
                    if (!gltf) fail(at + ".loop", "only a glTF model's animation can loop");
                    loop = boolean(*l, at + ".loop");
                    motion.erase("loop");
                }
                if (motion.empty()) motion = nullptr;
            }
            if (choice) {
                if (!gltf) fail(at, "only a glTF model has animation clips to pick");
                clip = pick_clip(*gltf, *choice, at);
            }
            if (!motion.is_null()) object.animation = animation(motion, at);
        }

        ground = false;
        if (const auto it = value.find("ground"); it != value.end()) ground = boolean(*it, where + ".ground");
        if (ground) {
            const bool is_plane =
                mesh_it != value.end() && (mesh_it->is_string() ? *mesh_it == "plane" : (*mesh_it)["type"] == "plane");
            if (!is_plane) fail(where + ".ground", "only a plane mesh can be the ground");
            if (object.animation.kind != Animation::Kind::none)
                fail(where + ".ground", "the ground cannot be animated");
            const glm::vec3 up =
                glm::normalize(glm::vec3(glm::inverseTranspose(glm::mat3(object.transform)) * glm::vec3(0, 1, 0)));
            if (up.y < 0.9999f)
                fail(where + ".ground", "the ground plane must stay horizontal (rotate it about Y only)");
        }
        // The ground receives shadows but casting them would only stretch every light's shadow frustum.
        object.casts_shadows = !ground;
        if (const auto it = value.find("casts_shadows"); it != value.end())
            object.casts_shadows = boolean(*it, where + ".casts_shadows");
        if (!gltf) return {object};

        // One object per part, sharing the placement; the scene's material keys override every part's.
        std::vector<Object> parts;
        for (const GltfPart& part : gltf->parts) {
            Object o = object;
            o.mesh = part.mesh;
            o.material =
                material_it != value.end() ? material(*material_it, where + ".material", part.material) : part.material;
            if (gltf->parts.size() > 1) o.name += "/" + part.name;
            attach_clip(o, *gltf, part, clip, loop);
            parts.push_back(std::move(o));
        }
        return parts;
    }

    fs::path file_;
    fs::path folder_;
    std::map<std::string, std::shared_ptr<const Mesh>> builtin_cache_;
    std::map<std::string, GltfModel> model_cache_;
};

Scene load_scene_json(const fs::path& path) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) throw InputError(path.string() + ": no such scene file");
    std::ifstream in(path);
    if (!in) throw InputError(path.string() + ": cannot read the file");
    json document;
    try {
        document = json::parse(in, [&](int depth, json::parse_event_t, json&) {
            if (depth > kMaxJsonDepth)
                throw InputError(path.string() + ": JSON nested deeper than " + std::to_string(kMaxJsonDepth) +
                                 " levels");
            return true;
        });
    } catch (const json::exception& e) {  // parse_error, and out_of_range for numbers too large
        std::string what = e.what();
        if (const auto bracket = what.find("] "); what.rfind("[json.exception", 0) == 0 && bracket != std::string::npos)
            what = what.substr(bracket + 2);  // drop nlohmann's "[json.exception.parse_error.101] "
        throw InputError(path.string() + ": invalid JSON: " + what);
    }
    return SceneReader(path).read(document);
}

// A bare model: fitted to kBareModelSize, standing on a ground plane, framed by the camera.
Scene load_bare_model(const fs::path& path) {
    const GltfModel model = load_gltf(path);
    Scene scene;
    scene.file = path;
    std::error_code ec;
    scene.environment.source =
        fs::is_regular_file(kDefaultEnvironmentFile, ec) ? kDefaultEnvironmentFile : "builtin:sky";

    Object ground;
    ground.name = "ground";
    ground.mesh = std::make_shared<const Mesh>(make_mesh(PlaneShape{kBareGroundFactor * kBareModelSize}));
    ground.casts_shadows = false;
    scene.objects.push_back(ground);
    scene.has_ground = true;
    scene.ground_height = 0.0f;

    for (const GltfPart& part : model.parts) {
        Object object;
        object.name = path.stem().string() + (model.parts.size() > 1 ? "/" + part.name : "");
        object.mesh = part.mesh;
        object.transform = fit_standing(model.bounds_min, model.bounds_max, kBareModelSize);
        object.material = part.material;
        attach_clip(object, model, part, first_clip(model), true);  // a dropped-in model plays its first clip
        scene.objects.push_back(object);
    }

    glm::vec3 lo, hi;
    std::vector<bool> is_ground(scene.objects.size(), false);
    is_ground[0] = true;
    bounds_without_ground(scene, is_ground, 0.0, lo, hi);
    scene.camera = camera_framing(lo, hi);
    return scene;
}

}  // namespace

Scene load_scene(const fs::path& path) {
    const std::string extension = lowercase_extension(path);
    if (extension == ".gltf" || extension == ".glb") return load_bare_model(path);
    return load_scene_json(path);
}

}  // namespace envshadow
