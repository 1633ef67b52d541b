#version 450 core
// The shadow atlas as a picture: near depths bright, empty texels (depth 1) black. Depths of a
// fitted orthographic tile crowd into a narrow range, so the tile's own range is stretched.
layout(location = 0) in vec2 v_uv;
layout(binding = UNIT_ATLAS) uniform sampler2D u_atlas;  // the atlas's depth, compare mode off
layout(location = 0) out vec4 o_color;

void main() {
    float d = texture(u_atlas, v_uv).r;
    float shade = d >= 1.0 ? 0.0 : 0.15 + 0.85 * pow(1.0 - d, 0.5);
    o_color = vec4(vec3(shade), 1.0);
}
