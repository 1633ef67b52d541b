#pragma once
// Whether a mesh's triangles enclose volumes: the shadow atlas draws closed casters with back faces culled
// (render/caster_lod.h), and both renderers cull the back faces of closed single-sided objects (glTF's
// doubleSided false, docs/SCENES.md "Sides"). No GL.
#include <cstdint>
#include <span>

#include "scene/scene.h"

namespace envshadow {

// Whether the triangles form closed surfaces, consistently wound: every directed edge (a, b) occurs
// once and its reverse (b, a) once. Degenerate triangles make it false.
bool is_closed(std::span<const std::uint32_t> indices);

// is_closed once the vertices that share a position are welded (seams of normals or texture coordinates
// split a closed surface's vertices).
bool is_closed_surface(const Mesh& mesh);

}  // namespace envshadow
