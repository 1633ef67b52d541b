#version 450 core
// One triangle covering the screen at the far plane; the environment fills what no object covers.

layout(location = 0) sample out vec2 v_ndc;  // per sample: background.frag

void main() {
    vec2 ndc = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2) * 2.0 - 1.0;  // (-1,-1) (3,-1) (-1,3)
    v_ndc = ndc;
    gl_Position = vec4(ndc, 1.0, 1.0);
}
