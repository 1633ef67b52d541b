// tinygltf compiled into the fuzzers themselves, so that libFuzzer sees its branches and the
// sanitizers check its memory accesses (Debian's libtinygltf.so is built without either). Its image
// functions call Debian's stb, which stays uninstrumented: load_gltf never decodes textures.
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
