#pragma once
// Scenes (docs/DESIGN.md §6): an environment, a camera and objects with materials and optional
// animation. Loaded from the JSON files in assets/scenes/ or from a bare .gltf/.glb. No GL here.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "scene/texture.h"

namespace envshadow {

// The glTF 2.0 metallic-roughness parameters (docs/DESIGN.md §11): ratio shading and the reference shade a
// material that has them with the specification's BRDF. The base-colour texture multiplies base_color.
struct MetallicRoughness {
    glm::vec3 base_color{1.0f};
    float metallic = 1.0f;
    float roughness = 1.0f;  // perceptual, as in the file
    bool operator==(const MetallicRoughness&) const = default;
};

// glTF's alphaMode (docs/SCENES.md "Alpha"): opaque ignores alpha; mask cuts the surface out where its alpha,
// Material::base_alpha times the base-colour texture's alpha, is below Material::alpha_cutoff: in shading, in
// the depth pre-pass, in every shadow tile and for the reference's rays; blend lays the surface over what is
// behind it in proportion to that alpha, and passes 1 - alpha of the light to what lies behind it (the shadow
// atlas's translucent layer; the reference's shadow rays pass with that probability).
enum class AlphaMode { opaque, mask, blend };

// Albedos (docs/DESIGN.md §2): k_d = rho_d / pi, k_s = rho_s (n + 2) / (2 pi).
// A base-colour texture, where present, multiplies rho_d per pixel (linear RGB; docs/SCENES.md
// "Textures"): k_d = rho_d texture(uv) / pi.
// With metallic_roughness, rho_d, rho_s and shininess are its Phong stand-in (docs/SCENES.md "Materials from
// glTF"): what cells shading draws. The metallic-roughness texture, where present, multiplies metallic (its B)
// and roughness (its G) per pixel (docs/SCENES.md "Textures"); only where metallic_roughness is set, only in
// ratio shading and the reference (the stand-in keeps the factors).
struct Material {
    glm::vec3 rho_d{0.8f};
    float rho_s = 0.0f;
    float shininess = 1.0f;
    std::optional<MaterialTexture> base_color_texture = std::nullopt;  // needs Mesh::texcoords
    std::optional<MetallicRoughness> metallic_roughness = std::nullopt;
    std::optional<MaterialTexture> metallic_roughness_texture = std::nullopt;  // needs Mesh::texcoords; srgb false
    // Emitted radiance (linear RGB, glTF's emissiveFactor times KHR_materials_emissive_strength), times the
    // emission texture where present (docs/SCENES.md "Emission"). Seen directly; it lights nothing else.
    glm::vec3 emission{0.0f};
    std::optional<MaterialTexture> emission_texture = std::nullopt;  // needs Mesh::texcoords
    // glTF's occlusionTexture (its R channel, linear): the reflected light is scaled by
    // 1 + occlusion_strength (R - 1) (docs/SCENES.md "Occlusion"); not the emission.
    std::optional<MaterialTexture> occlusion_texture = std::nullopt;  // needs Mesh::texcoords; srgb false
    float occlusion_strength = 1.0f;                                  // 0..1
    // glTF's normalTexture (tangent space, linear RGB): the shading normal is
    // normalize(T x s + B y s + N z) with (x, y, z) = 2 texel - 1 and s = normal_scale, T and B from
    // Mesh::tangents (docs/SCENES.md "Normal maps"); shadows keep the triangle's plane.
    std::optional<MaterialTexture> normal_texture = std::nullopt;  // needs Mesh::texcoords, tangents; srgb false
    float normal_scale = 1.0f;
    AlphaMode alpha_mode = AlphaMode::opaque;
    float alpha_cutoff = 0.5f;
    float base_alpha = 1.0f;  // baseColorFactor's alpha
    // false (glTF's doubleSided false): where the mesh is closed, its back faces are not drawn (a camera
    // inside sees out); open meshes show both sides whatever this says (docs/SCENES.md "Sides").
    bool double_sided = true;

    // Whether some of the surface is cut out (AlphaMode::mask with an alpha that can fall below the cutoff).
    bool masked() const { return alpha_mode == AlphaMode::mask && (base_color_texture || base_alpha < alpha_cutoff); }
    // Whether some of the surface lets what is behind it through (AlphaMode::blend with an alpha that can be
    // below 1); a blend material that is opaque everywhere is drawn as opaque.
    bool blended() const { return alpha_mode == AlphaMode::blend && (base_color_texture || base_alpha < 1.0f); }

    bool same_as(const Material& o) const {
        return rho_d == o.rho_d && rho_s == o.rho_s && shininess == o.shininess &&
               metallic_roughness == o.metallic_roughness && emission == o.emission && alpha_mode == o.alpha_mode &&
               alpha_cutoff == o.alpha_cutoff && base_alpha == o.base_alpha && double_sided == o.double_sided &&
               same_texture(base_color_texture, o.base_color_texture) &&
               same_texture(metallic_roughness_texture, o.metallic_roughness_texture) &&
               same_texture(emission_texture, o.emission_texture) &&
               same_texture(occlusion_texture, o.occlusion_texture) && occlusion_strength == o.occlusion_strength &&
               same_texture(normal_texture, o.normal_texture) && normal_scale == o.normal_scale;
    }

private:
    static bool same_texture(const std::optional<MaterialTexture>& a, const std::optional<MaterialTexture>& b) {
        if (!a || !b) return !a && !b;
        return a->image == b->image && a->wrap_s == b->wrap_s && a->wrap_t == b->wrap_t && a->nearest == b->nearest &&
               a->srgb == b->srgb;
    }
};

// Triangles in object space. normals.size() == positions.size(); indices.size() % 3 == 0; texcoords
// empty or one per position (the texture coordinates a material's texture reads, any transform applied);
// tangents empty or one per position: glTF's TANGENT, xyz a unit vector along +u in the surface, w = +-1
// the handedness (bitangent = w cross(normal, xyz)), for normal maps.
struct Mesh {
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;
    std::vector<glm::vec2> texcoords;
    std::vector<glm::vec4> tangents;
    std::vector<std::uint32_t> indices;
    glm::vec3 bounds_min{0.0f}, bounds_max{0.0f};

    std::size_t triangle_count() const { return indices.size() / 3; }
    void compute_bounds();
};

// Object motion as a function of time t (seconds): world_from_object(t) = motion(t) * transform.
struct Animation {
    enum class Kind { none, orbit, path };
    Kind kind = Kind::none;
    double period = 10.0;           // seconds per loop
    glm::vec3 center{0.0f};         // orbit: centre, axis +Y
    float radius = 1.0f;            // orbit
    float height = 0.0f;            // orbit: added to the centre's y
    std::vector<glm::vec3> points;  // path: a closed polyline (last point joins the first), travelled at
                                    // constant speed: time is proportional to arc length
    bool face_motion = true;        // turn the object about +Y so that its +Z (glTF's front) faces along
                                    // its horizontal motion

    // Translation to the position at time t (times t and t + period give the same), turned to face
    // the motion if face_motion; identity for Kind::none. Orbit: at t = 0 the object is at
    // centre + (radius, height, 0) and moves from +X towards +Z.
    glm::mat4 motion_at(double t) const;
};

class MeshDeformation;  // scene/gltf_animation.h

struct Object {
    std::string name;
    std::shared_ptr<const Mesh> mesh;
    glm::mat4 transform{1.0f};  // world_from_object at rest
    Material material;
    Animation animation;
    bool casts_shadows = true;

    // glTF animation (scene/gltf_animation.h): null when the model is still. A node-only animation of
    // one node moves the whole object (world_from_object); skins, morphs and several nodes deform it.
    std::shared_ptr<const MeshDeformation> deformation;

    glm::mat4 world_from_object(double t) const;  // motion_at(t) * transform (* the glTF node's motion)
    // Whether anything about the object's world-space geometry depends on t: the one test the shadow
    // cache (docs/DESIGN.md §5.11) keeps apart what it may draw once from what it draws every frame.
    bool moves() const { return animation.kind != Animation::Kind::none || deformation != nullptr; }
    // Whether its vertices change with t (then mesh_at(t) differs from mesh).
    bool deforms() const;
    // The object-space mesh at time t: `mesh` unless it deforms.
    std::shared_ptr<const Mesh> mesh_at(double t) const;
    // How long before the motion repeats (or stops): the longer of the scene-file animation's period
    // and the glTF clip's duration; 0 for a still object.
    double motion_period() const;
};

struct EnvironmentSettings {
    std::string source = "builtin:sky";  // file path (resolved against the scene file's folder) or builtin:
    float rotation_degrees = 0.0f;       // about +Y, applied to the map's directions
    float exposure_stops = 0.0f;         // applied when tone mapping
};

struct Camera {
    glm::vec3 position{0.0f, 1.0f, 4.0f};
    glm::vec3 target{0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float fov_y_degrees = 45.0f;

    // Right-handed, +Y up, looking down -Z in view space (glm::lookAtRH).
    glm::mat4 view_from_world() const;
    // OpenGL clip space: depth -1 at the near plane, +1 at the far plane (glm::perspectiveRH_NO).
    glm::mat4 clip_from_view(float aspect, float near_plane, float far_plane) const;
};

// Largest scene any loader builds, all objects together (README "Input limits").
inline constexpr std::size_t kMaxSceneTriangles = 50'000'000;
// Largest world coordinate (metres) of any vertex, camera or animation point: products and sums of
// a few such values (bounds, extents, projection fits) stay far inside float range.
inline constexpr double kMaxCoordinate = 1e12;

struct Scene {
    std::filesystem::path file;
    EnvironmentSettings environment;
    Camera camera;
    std::vector<Object> objects;
    float ground_height = 0.0f;  // y of the ground plane when there is one; lights under it see nothing
    bool has_ground = false;

    std::size_t triangle_count() const;
    // World-space bounds of every object at time t.
    void bounds_at(double t, glm::vec3& lo, glm::vec3& hi) const;
};

// A camera on the front-right of the box [lo, hi], a little above it, aimed at its centre and close
// enough that the box's bounding sphere fits a vertical field of view of fov_y_degrees (and so any
// picture at least as wide as it is tall).
Camera camera_framing(const glm::vec3& lo, const glm::vec3& hi, float fov_y_degrees = 40.0f);

// Loads a scene JSON, or a .gltf/.glb placed on a ground plane and framed by the camera under the
// default environment. Throws InputError naming the file and the reason.
Scene load_scene(const std::filesystem::path& path);

}  // namespace envshadow
