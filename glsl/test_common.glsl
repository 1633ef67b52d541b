// Shared by the test triangle's stages: proves #include works.
layout(location = 0) uniform float u_depth;
layout(location = 1) uniform float u_scale;
layout(location = 2) uniform vec3 u_tint;

vec3 test_color(int corner) { return corner == 0 ? vec3(1, 0, 0) : corner == 1 ? vec3(0, 1, 0) : vec3(0, 0, 1); }
