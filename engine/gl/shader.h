#pragma once
// GLSL programs assembled from named sources with `#include "file"` (each file included once),
// generated `#define`s after `#version`, and `#line` directives so that a compile error names the
// file and line it came from ("shade.frag:42: error: ...").
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "gl/objects.h"

namespace envshadow::gl {

struct ShaderStage {
    GLenum type;       // GL_VERTEX_SHADER, ...
    std::string file;  // name in the library, e.g. "shade.frag"
};

struct AssembledSource {
    std::string text;
    std::vector<std::string> files;  // index = the source-string number used in #line
};

class ShaderLibrary {
public:
    void add(std::string name, std::string source) { sources_[std::move(name)] = std::move(source); }
    bool contains(const std::string& name) const { return sources_.count(name) != 0; }
    // A #define ("NAME" or "NAME VALUE") for every stage assembled from this library, after
    // #version and before the defines given to assemble() or build().
    void define(std::string definition) { defines_.push_back(std::move(definition)); }

    // `defines` are "NAME" or "NAME VALUE". Throws PlatformError for a missing file, a missing
    // #version or an include cycle.
    AssembledSource assemble(const std::string& name, const std::vector<std::string>& defines = {}) const;

    // Compiles and links; errors are rewritten to name file and line. Throws PlatformError.
    // `transform_feedback` names varyings captured (interleaved) when non-empty.
    Program build(const std::vector<ShaderStage>& stages, const std::vector<std::string>& defines = {},
                  const std::vector<std::string>& transform_feedback = {}) const;
    // Programs build() has linked so far.
    std::size_t programs_built() const { return programs_built_; }

private:
    void append(const std::string& name, AssembledSource& out, std::vector<std::string>& stack) const;
    std::map<std::string, std::string> sources_;
    std::vector<std::string> defines_;
    mutable std::size_t programs_built_ = 0;  // a count, not state: build() stays const
};

// Rewrites a driver's info log ("0:12(3): error: x" from Mesa, "0(12) : error C0000: x" from NVIDIA)
// so that source-string numbers become file names: "shade.frag:12: error: x".
std::string rewrite_info_log(const std::string& log, const std::vector<std::string>& files);

}  // namespace envshadow::gl
