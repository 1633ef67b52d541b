#include "reference/ray_tracer.h"

#include <embree3/rtcore.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "core/error.h"
#include "scene/mesh_topology.h"
#include "scene/meshes.h"
#include "scene/texture.h"

namespace envshadow::reference {
namespace {

// The hits on an object that do not count (Embree filter functions): where its alpha mask cuts it out
// (Material::masked, docs/SCENES.md "Alpha"), for camera and shadow rays alike; where a blended surface
// (Material::blended) lets the ray through, with probability 1 - alpha; and, on a closed single-sided object
// (glTF's doubleSided false, docs/SCENES.md "Sides"), its back faces, for camera rays.
struct HitFilter {
    const MaterialTexture* texture = nullptr;  // the base colour, where the mesh has texture coordinates
    const std::vector<glm::vec2>* texcoords = nullptr;
    const std::vector<std::uint32_t>* indices = nullptr;
    float base_alpha = 1.0f, cutoff = 0.0f;         // cutoff 0: nothing cut out
    bool blended = false;                           // hit where the alpha exceeds a hashed threshold
    const std::vector<glm::vec3>* front = nullptr;  // world positions where back faces are culled, else null
    bool mirrored = false;                          // world_from_object turns the winding round

    float alpha(unsigned triangle, float u, float v) const {
        float alpha = base_alpha;
        if (texture) {
            const std::uint32_t* t = &(*indices)[3 * std::size_t(triangle)];
            const glm::vec2 uv = (1.0f - u - v) * (*texcoords)[t[0]] + u * (*texcoords)[t[1]] + v * (*texcoords)[t[2]];
            alpha *= sample_linear_rgba(*texture, uv).a;
        }
        return alpha;
    }
    bool back_facing(unsigned triangle, const glm::vec3& direction) const {
        const std::uint32_t* t = &(*indices)[3 * std::size_t(triangle)];
        const glm::vec3 p0 = (*front)[t[0]], p1 = (*front)[t[1]], p2 = (*front)[t[2]];
        const float facing = glm::dot(glm::cross(p1 - p0, p2 - p0), direction);
        return mirrored ? facing < 0.0f : facing > 0.0f;
    }
};

// Embree's context with what the filters need to know of the query (RayTracer::intersect's arguments).
struct QueryContext {
    RTCIntersectContext embree;  // first: the filters get a pointer to it
    std::uint32_t salt = 0;
    bool blended_always_hit = false;
};

std::uint64_t mix(std::uint64_t h) {  // splitmix64's finaliser
    h = (h ^ (h >> 30)) * 0xbf58476d1ce4e5b9ull;
    h = (h ^ (h >> 27)) * 0x94d049bb133111ebull;
    return h ^ (h >> 31);
}

// A threshold uniform in [0, 1) from the ray, the triangle, the point on it and the query's salt: rays that
// differ in any of them decide independently whether a blended surface stops them.
template <class Args>
float hashed_threshold(const Args* args, unsigned i, unsigned triangle, std::uint32_t salt) {
    std::uint64_t h = mix(salt ^ (std::uint64_t(triangle) << 32));
    for (const float f : {RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i),
                          RTCRayN_org_z(args->ray, args->N, i), RTCRayN_dir_x(args->ray, args->N, i),
                          RTCRayN_dir_y(args->ray, args->N, i), RTCRayN_dir_z(args->ray, args->N, i),
                          RTCHitN_u(args->hit, args->N, i), RTCHitN_v(args->hit, args->N, i)})
        h = mix(h ^ std::bit_cast<std::uint32_t>(f));
    return float(h >> 40) / float(1u << 24);
}

template <bool camera>
void hit_filter(const RTCFilterFunctionNArguments* args) {
    const auto& filter = *static_cast<const HitFilter*>(args->geometryUserPtr);
    const auto& query = *reinterpret_cast<const QueryContext*>(args->context);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        const unsigned triangle = RTCHitN_primID(args->hit, args->N, i);
        const float u = RTCHitN_u(args->hit, args->N, i), v = RTCHitN_v(args->hit, args->N, i);
        if (filter.cutoff > 0.0f && filter.alpha(triangle, u, v) < filter.cutoff)
            args->valid[i] = 0;
        else if (filter.blended && !query.blended_always_hit &&
                 filter.alpha(triangle, u, v) <= hashed_threshold(args, i, triangle, query.salt))
            args->valid[i] = 0;
        else if (camera && filter.front &&
                 filter.back_facing(triangle,
                                    {RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
                                     RTCRayN_dir_z(args->ray, args->N, i)}))
            args->valid[i] = 0;
    }
}

}  // namespace

struct RayTracer::State {
    RTCDevice device = nullptr;
    RTCScene everything = nullptr;
    RTCScene casters = nullptr;
    std::vector<std::size_t> object_of_geometry;    // geometry ID in `everything` -> object index
    std::vector<std::vector<glm::vec3>> positions;  // world space, per object
    std::vector<std::vector<glm::vec3>> normals;    // world space, unit, per object
    std::vector<std::vector<glm::vec4>> tangents;   // world space, unit, w the handedness; empty: none
    std::vector<bool> mirrored;                     // per object: world_from_object's determinant < 0
    std::vector<const std::vector<std::uint32_t>*> indices;
    std::vector<const std::vector<glm::vec2>*> texcoords;  // the mesh's, per object (empty: none)
    std::vector<std::unique_ptr<HitFilter>> filters;       // per object; null where every hit counts

    ~State() {
        if (casters) rtcReleaseScene(casters);
        if (everything) rtcReleaseScene(everything);
        if (device) rtcReleaseDevice(device);
    }
};

namespace {

void check(RTCDevice device, const char* what) {
    const RTCError error = rtcGetDeviceError(device);
    if (error != RTC_ERROR_NONE)
        throw PlatformError(std::string("Embree: ") + what + " failed (error " + std::to_string(int(error)) + ")");
}

// A triangle geometry over `positions` / `indices` (Embree copies nothing: the buffers must outlive it), its
// hits filtered by `filter` where given (intersect: camera rays; occluded: shadow rays).
void attach(RTCDevice device, RTCScene scene, const std::vector<glm::vec3>& positions,
            const std::vector<std::uint32_t>& indices, const HitFilter* filter) {
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    // Embree may read 16 bytes from the last vertex: the positions vector is padded by the caller.
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, positions.data(), 0,
                               sizeof(glm::vec3), positions.size() - 1);
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, indices.data(), 0,
                               3 * sizeof(std::uint32_t), indices.size() / 3);
    if (filter) {
        rtcSetGeometryUserData(geometry, const_cast<HitFilter*>(filter));
        rtcSetGeometryIntersectFilterFunction(geometry, hit_filter<true>);
        rtcSetGeometryOccludedFilterFunction(geometry, hit_filter<false>);
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
}

}  // namespace

RayTracer::RayTracer(const Scene& scene, double time) : state_(std::make_unique<State>()) {
    State& s = *state_;
    s.device = rtcNewDevice(nullptr);
    if (!s.device) throw PlatformError("Embree: cannot create a device");
    s.everything = rtcNewScene(s.device);
    s.casters = rtcNewScene(s.device);
    for (RTCScene bvh : {s.everything, s.casters}) {
        rtcSetSceneFlags(bvh, RTC_SCENE_FLAG_ROBUST);
        rtcSetSceneBuildQuality(bvh, RTC_BUILD_QUALITY_HIGH);
    }
    s.positions.resize(scene.objects.size());
    s.normals.resize(scene.objects.size());
    s.tangents.resize(scene.objects.size());
    s.mirrored.resize(scene.objects.size(), false);
    s.indices.resize(scene.objects.size(), nullptr);
    s.texcoords.resize(scene.objects.size(), nullptr);
    s.filters.resize(scene.objects.size());
    double extent = 0.0;
    for (std::size_t k = 0; k < scene.objects.size(); ++k) {
        const Object& object = scene.objects[k];
        if (!object.mesh || object.mesh->indices.empty()) continue;
        // The pose at `time` (glTF skins and morphs; the same indices as object.mesh, which stays alive).
        const std::shared_ptr<const Mesh> posed = object.mesh_at(time);
        const Mesh& mesh = *posed;
        const glm::mat4 world_from_object = object.world_from_object(time);
        const glm::mat3 normal_matrix = glm::transpose(glm::inverse(glm::mat3(world_from_object)));
        s.mirrored[k] = glm::determinant(glm::mat3(world_from_object)) < 0.0f;
        std::vector<glm::vec3>& positions = s.positions[k];
        std::vector<glm::vec3>& normals = s.normals[k];
        positions.reserve(mesh.positions.size() + 1);
        normals.reserve(mesh.positions.size());
        for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
            positions.push_back(glm::vec3(world_from_object * glm::vec4(mesh.positions[v], 1.0f)));
            const glm::vec3 n = normal_matrix * mesh.normals[v];
            const float length = glm::length(n);
            normals.push_back(length > 0.0f ? n / length : glm::vec3(0.0f));
            extent = std::max(extent, double(glm::length(positions.back())));
        }
        positions.push_back(glm::vec3(0.0f));  // padding for Embree's 16-byte vertex reads
        const glm::dmat3 linear(glm::mat3{world_from_object});
        for (std::size_t v = 0; v < mesh.tangents.size(); ++v)
            s.tangents[k].push_back(transform_tangent(linear, mesh.tangents[v], glm::dvec3(normals[v])));
        s.indices[k] = &object.mesh->indices;
        s.texcoords[k] = &object.mesh->texcoords;  // a pose keeps the bind mesh's texture coordinates
        const Material& material = object.material;
        const bool culled = !material.double_sided && is_closed_surface(*object.mesh);
        if (material.masked() || material.blended() || culled) {
            auto filter = std::make_unique<HitFilter>();
            filter->indices = &object.mesh->indices;
            if (material.masked() || material.blended()) {
                if (material.base_color_texture && !object.mesh->texcoords.empty()) {
                    filter->texture = &*material.base_color_texture;
                    filter->texcoords = &object.mesh->texcoords;
                }
                filter->base_alpha = material.base_alpha;
                if (material.masked()) filter->cutoff = material.alpha_cutoff;
                filter->blended = material.blended();
                has_blended_ = has_blended_ || material.blended();
            }
            if (culled) filter->front = &positions;
            filter->mirrored = s.mirrored[k];
            s.filters[k] = std::move(filter);
        }
        attach(s.device, s.everything, positions, object.mesh->indices, s.filters[k].get());
        s.object_of_geometry.push_back(k);
        if (object.casts_shadows) attach(s.device, s.casters, positions, object.mesh->indices, s.filters[k].get());
        triangles_ += mesh.triangle_count();
    }
    rtcCommitScene(s.everything);
    rtcCommitScene(s.casters);
    check(s.device, "building the scene's BVH");
    extent_ = std::max(extent, 1e-3);
}

RayTracer::~RayTracer() = default;

std::optional<Hit> RayTracer::intersect(const glm::dvec3& origin, const glm::dvec3& direction, std::uint32_t salt,
                                        bool blended_always_hit) const {
    RTCRayHit query{};
    query.ray.org_x = float(origin.x);
    query.ray.org_y = float(origin.y);
    query.ray.org_z = float(origin.z);
    query.ray.dir_x = float(direction.x);
    query.ray.dir_y = float(direction.y);
    query.ray.dir_z = float(direction.z);
    query.ray.tnear = 0.0f;
    query.ray.tfar = std::numeric_limits<float>::infinity();
    query.ray.mask = ~0u;
    query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    query.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    QueryContext context;
    rtcInitIntersectContext(&context.embree);
    context.salt = salt;
    context.blended_always_hit = blended_always_hit;
    rtcIntersect1(state_->everything, &context.embree, &query);
    if (query.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;

    return hit_at(state_->object_of_geometry[query.hit.geomID], query.hit.primID, query.hit.u, query.hit.v,
                  query.ray.tfar, direction);
}

Hit RayTracer::hit_at(std::size_t object, std::size_t triangle_index, double u, double v, double distance,
                      const glm::dvec3& direction) const {
    const std::vector<glm::vec3>& positions = state_->positions[object];
    const std::vector<glm::vec3>& normals = state_->normals[object];
    const std::uint32_t* triangle = state_->indices[object]->data() + 3 * triangle_index;
    const double w = 1.0 - u - v;
    const glm::dvec3 p0(positions[triangle[0]]), p1(positions[triangle[1]]), p2(positions[triangle[2]]);
    Hit hit;
    hit.object = object;
    hit.triangle = triangle_index;
    hit.distance = distance;
    hit.position = w * p0 + u * p1 + v * p2;
    // A mirroring transform turns the winding round: the front stays the side of the object's winding.
    const glm::dvec3 face = (state_->mirrored[object] ? -1.0 : 1.0) * glm::cross(p1 - p0, p2 - p0);
    const double face_length = glm::length(face);
    hit.geometric_normal = face_length > 0.0 ? face / face_length : -direction;
    const glm::dvec3 n = w * glm::dvec3(normals[triangle[0]]) + u * glm::dvec3(normals[triangle[1]]) +
                         v * glm::dvec3(normals[triangle[2]]);
    const double n_length = glm::length(n);
    hit.shading_normal = n_length > 0.0 ? n / n_length : hit.geometric_normal;
    if (const std::vector<glm::vec4>& t = state_->tangents[object]; !t.empty()) {
        hit.tangent = w * glm::dvec4(t[triangle[0]]) + u * glm::dvec4(t[triangle[1]]) + v * glm::dvec4(t[triangle[2]]);
    }
    if (const std::vector<glm::vec2>& uv = *state_->texcoords[object]; !uv.empty())
        hit.texcoord = glm::vec2(w * glm::dvec2(uv[triangle[0]]) + u * glm::dvec2(uv[triangle[1]]) +
                                 v * glm::dvec2(uv[triangle[2]]));
    return hit;
}

std::optional<glm::dvec3> RayTracer::plane_crossing(const Hit& hit, const glm::dvec3& origin,
                                                    const glm::dvec3& direction) const {
    const std::vector<glm::vec3>& positions = state_->positions[hit.object];
    const std::uint32_t* triangle = state_->indices[hit.object]->data() + 3 * hit.triangle;
    const glm::dvec3 p0(positions[triangle[0]]), p1(positions[triangle[1]]), p2(positions[triangle[2]]);
    const glm::dvec3 e1 = p1 - p0, e2 = p2 - p0, normal = glm::cross(e1, e2);
    const double denominator = glm::dot(normal, direction);
    if (!(std::abs(denominator) > 1e-12 * glm::length(normal))) return std::nullopt;
    const double distance = glm::dot(normal, p0 - origin) / denominator;
    const glm::dvec3 q = origin + distance * direction;
    // Barycentrics of q in the plane (Cramer's rule on the edge vectors).
    const double d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
    const double r1 = glm::dot(q - p0, e1), r2 = glm::dot(q - p0, e2);
    const double det = d11 * d22 - d12 * d12;
    if (!(det > 0.0)) return std::nullopt;
    return glm::dvec3((d22 * r1 - d12 * r2) / det, (d11 * r2 - d12 * r1) / det, distance);
}

std::optional<Hit> RayTracer::hit_on_plane(const Hit& hit, const glm::dvec3& origin,
                                           const glm::dvec3& direction) const {
    const std::optional<glm::dvec3> crossing = plane_crossing(hit, origin, direction);
    if (!crossing || !(crossing->z > 0.0)) return std::nullopt;
    return hit_at(hit.object, hit.triangle, crossing->x, crossing->y, crossing->z, direction);
}

std::optional<glm::dvec2> RayTracer::texcoord_on_plane(const Hit& hit, const glm::dvec3& origin,
                                                       const glm::dvec3& direction) const {
    const std::vector<glm::vec2>& uv = *state_->texcoords[hit.object];
    if (uv.empty()) return std::nullopt;
    const std::optional<glm::dvec3> crossing = plane_crossing(hit, origin, direction);
    if (!crossing) return std::nullopt;
    const std::uint32_t* triangle = state_->indices[hit.object]->data() + 3 * hit.triangle;
    const double u = crossing->x, v = crossing->y;
    return (1.0 - u - v) * glm::dvec2(uv[triangle[0]]) + u * glm::dvec2(uv[triangle[1]]) +
           v * glm::dvec2(uv[triangle[2]]);
}

bool RayTracer::occluded(const glm::dvec3& origin, const glm::dvec3& direction, double t_max) const {
    RTCRay ray{};
    ray.org_x = float(origin.x);
    ray.org_y = float(origin.y);
    ray.org_z = float(origin.z);
    ray.dir_x = float(direction.x);
    ray.dir_y = float(direction.y);
    ray.dir_z = float(direction.z);
    ray.tnear = 0.0f;
    ray.tfar = float(t_max);
    ray.mask = ~0u;
    QueryContext context;
    rtcInitIntersectContext(&context.embree);
    rtcOccluded1(state_->casters, &context.embree, &ray);
    return ray.tfar < 0.0f;  // Embree sets tfar to -inf on a hit
}

}  // namespace envshadow::reference
