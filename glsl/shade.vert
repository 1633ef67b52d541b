#version 450 core
// Objects in the camera's view: world position, normal, texture coordinates and tangent for shade.frag.

layout(location = ATTRIB_POSITION) in vec3 a_position;
layout(location = ATTRIB_NORMAL) in vec3 a_normal;
layout(location = ATTRIB_TEXCOORD) in vec2 a_texcoord;
layout(location = ATTRIB_TANGENT) in vec4 a_tangent;  // (0, 0, 0, 1) on meshes without tangents

layout(location = LOC_WORLD_FROM_OBJECT) uniform mat4 u_world_from_object;
layout(location = LOC_WORLD_NORMAL_FROM_OBJECT) uniform mat3 u_world_normal_from_object;  // inverse transpose
layout(location = LOC_CLIP_FROM_WORLD) uniform mat4 u_clip_from_world;

invariant gl_Position;  // the depth pre-pass and the shading pass must give equal depths

layout(location = 0) out vec3 v_world_position;
layout(location = 1) out vec3 v_world_normal;
layout(location = 2) out vec2 v_texcoord;
layout(location = 3) out vec3 v_world_position_at_centre;  // the same, read at the pixel centre
layout(location = 4) out vec4 v_world_tangent;              // w: the handedness in world space

void main() {
    vec4 world = u_world_from_object * vec4(a_position, 1.0);
    v_world_position = world.xyz;
    v_world_position_at_centre = world.xyz;
    v_world_normal = u_world_normal_from_object * a_normal;
    v_texcoord = a_texcoord;
    // A tangent lies in the surface: it transforms as positions do, and a mirroring transform turns the
    // handedness round.
    mat3 linear = mat3(u_world_from_object);
    v_world_tangent = vec4(linear * a_tangent.xyz, determinant(linear) < 0.0 ? -a_tangent.w : a_tangent.w);
    gl_Position = u_clip_from_world * world;
}
