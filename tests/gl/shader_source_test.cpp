// Shader assembly (#include, #define, #line) and error-log rewriting, without a context.
#include <gtest/gtest.h>

#include "core/error.h"
#include "gl/shader.h"

namespace envshadow::gl {
namespace {

size_t count(const std::string& text, const std::string& what) {
    size_t n = 0;
    for (size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
    return n;
}

TEST(ShaderSource, IncludesAreResolvedOnceAndDefinesFollowVersion) {
    ShaderLibrary library;
    library.add("common.glsl", "float common_value() { return 1.0; }\n");
    library.add("other.glsl", "#include \"common.glsl\"\nfloat other() { return common_value(); }\n");
    library.add("main.frag", "#version 450 core\n#include \"common.glsl\"\n#include \"other.glsl\"\nvoid main() {}\n");
    const AssembledSource s = library.assemble("main.frag", {"LIGHTS 64"});
    EXPECT_EQ(s.text.rfind("#version 450 core\n#define LIGHTS 64\n", 0), 0u) << s.text;
    EXPECT_EQ(count(s.text, "float common_value()"), 1u) << s.text;
    EXPECT_EQ(count(s.text, "float other()"), 1u);
    EXPECT_EQ(count(s.text, "#include"), 0u);
    ASSERT_EQ(s.files.size(), 3u);
    EXPECT_EQ(s.files[0], "main.frag");
}

TEST(ShaderSource, LibraryDefinesReachEveryStageBeforeTheBuildsOwn) {
    ShaderLibrary library;
    library.define("LOC_EYE 12");
    library.define("MAX_LIGHTS 256");
    library.add("a.vert", "// a comment first\n#version 450 core\nvoid main() {}\n");
    library.add("b.frag", "#version 450 core\nvoid main() {}\n");
    EXPECT_EQ(
        library.assemble("a.vert").text.rfind("#version 450 core\n#define LOC_EYE 12\n#define MAX_LIGHTS 256\n", 0),
        0u);
    const AssembledSource b = library.assemble("b.frag", {"SHADOW_TILE_LISTS"});
    EXPECT_EQ(
        b.text.rfind("#version 450 core\n#define LOC_EYE 12\n#define MAX_LIGHTS 256\n#define SHADOW_TILE_LISTS\n", 0),
        0u)
        << b.text;
}

TEST(ShaderSource, MissingIncludeAndCycleAreErrors) {
    ShaderLibrary library;
    library.add("a.frag", "#version 450\n#include \"nope.glsl\"\n");
    EXPECT_THROW(library.assemble("a.frag"), PlatformError);
    library.add("x.glsl", "#include \"y.glsl\"\n");
    library.add("y.glsl", "#include \"x.glsl\"\n");
    library.add("b.frag", "#version 450\n#include \"x.glsl\"\n");
    EXPECT_THROW(library.assemble("b.frag"), PlatformError);
}

TEST(ShaderSource, InfoLogsNameFileAndLine) {
    const std::vector<std::string> files = {"shade.frag", "brdf.glsl"};
    EXPECT_EQ(rewrite_info_log("1:17(5): error: `foo' undeclared", files), "brdf.glsl:17: error: `foo' undeclared");
    EXPECT_EQ(rewrite_info_log("0(12) : error C1008: undefined variable", files),
              "shade.frag:12: error C1008: undefined variable");
}

}  // namespace
}  // namespace envshadow::gl
