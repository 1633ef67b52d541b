#pragma once
// Shading-normal geometry shared by the reference and the tests (glsl/shade_surface.glsl holds the GLSL twin;
// docs/DESIGN.md §5.4). Double precision, no GL.
#include <glm/vec3.hpp>

namespace envshadow {

// The shading normal adaptation of Iray (Keller et al. 2017) and Cycles, for normal-mapped normals: where the
// mirror direction of `view` about unit n dips below t = min(0.9 view.ng, 0.01) over the triangle's plane (ng,
// unit, on the viewer's side), n turned towards ng, in the plane of the two, until the mirror direction's
// height is t. With n(a) = cos a ng + sin a x (x the unit part of n across ng) and the view's parts v_z along
// ng and v_x along x, that height is v_z cos 2a + v_x sin 2a = r cos(2a - phi): the turned normal is at
// 2a = phi + acos(t / r), where it falls through t. n itself where its mirror direction clears the plane; ng
// where n is parallel to it.
glm::dvec3 mirror_above_surface(const glm::dvec3& n, const glm::dvec3& ng, const glm::dvec3& view);

}  // namespace envshadow
