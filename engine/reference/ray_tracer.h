#pragma once
// The scene's triangles at one instant, in world space, in two Embree 3 BVHs: everything (what the
// camera sees) and the shadow casters (Object::casts_shadows; what blocks the environment).
#include <cstddef>
#include <cstdint>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <memory>
#include <optional>

#include "scene/scene.h"

namespace envshadow::reference {

struct Hit {
    std::size_t object = 0;       // index into Scene::objects
    double distance = 0.0;        // along the (unit) ray
    glm::dvec3 position;          // on the triangle (from the barycentrics, not origin + t d)
    glm::dvec3 shading_normal;    // interpolated vertex normals, world space, unit
    glm::dvec3 geometric_normal;  // the triangle's, on the side its vertices turn counter-clockwise in object
                                  // space (the front, whatever the transform), world space, unit
    glm::vec2 texcoord{0.0f};     // interpolated Mesh::texcoords; (0, 0) without them
    glm::dvec4 tangent{0.0};      // interpolated Mesh::tangents (world space, not unit; w's sign is the
                                  // handedness, as the rasteriser interpolates it); 0 without them
    std::size_t triangle = 0;     // index of the triangle hit in its object's mesh
};

class RayTracer {
public:
    // Geometry at time `time` (Object::world_from_object). Throws PlatformError if Embree fails.
    RayTracer(const Scene& scene, double time);
    ~RayTracer();
    RayTracer(const RayTracer&) = delete;
    RayTracer& operator=(const RayTracer&) = delete;

    // Nearest hit along origin + t direction, t in (0, inf); `direction` unit. A blended surface
    // (Material::blended) stops the ray with probability alpha, decided by a hash of the ray, the point and
    // `salt` (the same query gives the same hit; change the salt for another draw); with
    // `blended_always_hit` it stops every ray, as an opaque surface.
    std::optional<Hit> intersect(const glm::dvec3& origin, const glm::dvec3& direction, std::uint32_t salt = 0,
                                 bool blended_always_hit = false) const;
    // Whether a shadow caster lies along origin + t direction, t in (0, t_max); a blended caster blocks the
    // ray with probability alpha, as for intersect().
    bool occluded(const glm::dvec3& origin, const glm::dvec3& direction, double t_max) const;

    // Where the ray origin + t direction meets the plane of `hit`'s triangle (extended beyond its edges):
    // a Hit on that triangle with the barycentrics there (outside [0, 1] off the triangle), its normals and
    // texture coordinates interpolated (extrapolated) alike. Nothing where the ray runs parallel to the
    // plane, meets it behind the origin or the triangle is degenerate.
    std::optional<Hit> hit_on_plane(const Hit& hit, const glm::dvec3& origin, const glm::dvec3& direction) const;
    // The texture coordinates where the ray origin + t direction meets the plane of `hit`'s triangle
    // (extended beyond its edges): a neighbouring pixel's ray there gives the pixel's footprint in uv
    // (a ray differential). Nothing where the ray runs parallel to the plane or the mesh has no
    // texture coordinates.
    std::optional<glm::dvec2> texcoord_on_plane(const Hit& hit, const glm::dvec3& origin,
                                                const glm::dvec3& direction) const;

    // Whether some object is blended (Material::blended): its hits are random draws.
    bool has_blended() const { return has_blended_; }

    // Radius of a sphere about the origin holding all geometry: the scale for ray offsets.
    double extent() const { return extent_; }
    std::size_t triangle_count() const { return triangles_; }

private:
    // The hit on `triangle` of `object` at barycentrics (u, v) (of vertices 1 and 2), `distance` along the
    // unit `direction`.
    Hit hit_at(std::size_t object, std::size_t triangle, double u, double v, double distance,
               const glm::dvec3& direction) const;
    // Barycentrics (u, v) and distance where the ray meets the plane of `hit`'s triangle.
    std::optional<glm::dvec3> plane_crossing(const Hit& hit, const glm::dvec3& origin,
                                             const glm::dvec3& direction) const;

    struct State;
    std::unique_ptr<State> state_;
    double extent_ = 1.0;
    std::size_t triangles_ = 0;
    bool has_blended_ = false;
};

}  // namespace envshadow::reference
