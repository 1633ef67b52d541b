#version 450 core
// Depth pre-pass (with shade.vert): only the depth buffer is written, so the N-light shading of
// shade.frag then runs once per visible pixel (engine/render/renderer.cpp).
void main() {}
