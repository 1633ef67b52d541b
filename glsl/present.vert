#version 450 core
// A screen-covering triangle for the 2-D passes (presenting the frame, previews).
layout(location = 0) out vec2 v_uv;

void main() {
    vec2 ndc = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2) * 2.0 - 1.0;  // (-1,-1) (3,-1) (-1,3)
    v_uv = ndc * 0.5 + 0.5;
    gl_Position = vec4(ndc, 0.0, 1.0);
}
