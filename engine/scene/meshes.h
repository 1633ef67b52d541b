#pragma once
// Built-in meshes for scene files (docs/SCENES.md): deterministic, indexed, counter-clockwise seen
// from outside, with unit vertex normals and bounds filled in. Closed meshes are closed when welded by
// position (every edge shared by exactly two triangles, in opposite directions). Parameters are
// trusted here; the scene loader checks them against the limits below.
#include <cstdint>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "scene/scene.h"

namespace envshadow {

// Square in the XZ plane at y = 0, centred on the origin, facing +Y. Open.
struct PlaneShape {
    float size = 10.0f;
};

// UV sphere centred on the origin: `segments` around the Y axis, segments / 2 bands from pole to pole,
// one vertex per pole: 2 * segments * (segments / 2 - 1) triangles.
struct SphereShape {
    float radius = 0.5f;
    int segments = 64;
};

// Ring about the Y axis centred on the origin: segments * sides * 2 triangles.
struct TorusShape {
    float major_radius = 0.4f;   // centre of the tube from the axis
    float minor_radius = 0.15f;  // tube radius
    int segments = 64;           // around the Y axis
    int sides = 32;              // around the tube
};

// Axis-aligned box centred on the origin with flat faces: 12 triangles.
struct BoxShape {
    glm::vec3 size{1.0f};
};

// Lumpy sphere: a geodesic sphere of frequency f (20 f^2 triangles, f chosen so that the count is
// the nearest to `triangles`) displaced along its radius by smooth seeded bumps.
struct BlobShape {
    float radius = 0.5f;
    int triangles = 5000;
    float lumpiness = 0.25f;  // bump height relative to the radius, 0 gives a sphere
    std::uint32_t seed = 1;
};

// A standing creature for the flying-figure scenes (the paper's Armadillo is not available): a
// mannequin of overlapping closed ellipsoids (head with ears and snout, body, arms, legs, feet), each a
// geodesic sphere, their frequencies chosen so the total is near `triangles`. Feet on y = 0, centred
// on the Y axis, facing +Z (glTF's front).
struct FigureShape {
    float height = 1.8f;
    int triangles = 15000;
};

// Spiky virus (paper Fig. 9): a geodesic body with `spikes` club-shaped spikes (a tapered stalk with
// a knob), spread evenly over the sphere. Every part is closed.
struct VirusShape {
    float radius = 0.3f;  // body
    int spikes = 48;
    float spike_length = 0.12f;  // from the body surface to the knob's centre
    int detail = 10;             // geodesic frequency of the body (20 detail^2 triangles)
};

// Limits the scene loader enforces on the parameters above.
inline constexpr int kMaxSegments = 4096;
inline constexpr int kMaxBuiltinTriangles = 5'000'000;
inline constexpr int kMaxSpikes = 2000;

Mesh make_mesh(const PlaneShape& shape);
Mesh make_mesh(const SphereShape& shape);
Mesh make_mesh(const TorusShape& shape);
Mesh make_mesh(const BoxShape& shape);
Mesh make_mesh(const BlobShape& shape);
Mesh make_mesh(const FigureShape& shape);
Mesh make_mesh(const VirusShape& shape);

// The geodesic frequency f >= 1 whose 20 f^2 triangles are nearest to `triangles`.
int geodesic_frequency(int triangles);

// Area-weighted vertex normals from the triangles (a vertex used by no triangle, or by degenerate
// ones only, gets +Y). Replaces mesh.normals.
void compute_vertex_normals(Mesh& mesh);

// Per-vertex tangents for normal maps where the file has none (glTF 2.0 §3.7.2.1 asks for MikkTSpace's; this
// is the per-triangle uv gradient summed at each vertex, Lengyel 2001, which agrees with MikkTSpace wherever
// the uv mapping is affine over a vertex's triangles): xyz along +u, made orthogonal to the vertex normal,
// w = +1 where cross(normal, xyz) runs up the image (along -v: glTF's v runs down it, a normal map's +y
// up), -1 where the mapping is mirrored. A vertex whose triangles
// have no uv gradient gets any unit vector orthogonal to its normal. Needs normals and texcoords; replaces
// mesh.tangents.
void compute_vertex_tangents(Mesh& mesh);

// A Mesh::tangents entry through the linear part of a transform: xyz as positions transform (tangents lie in
// the surface), made orthogonal to `normal` (the normal after the same transform: a shear bends the two
// apart) and normalised; w turned round where the transform mirrors. xyz is 0 where it collapses.
glm::vec4 transform_tangent(const glm::dmat3& linear, const glm::vec4& tangent, const glm::dvec3& normal);

}  // namespace envshadow
