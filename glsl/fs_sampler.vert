#version 450 core
// Feeds the Floyd-Steinberg sampler (fs_sampler.geom) one point per slice; it needs no vertex data.
void main() {}
