#include "gl/shader.h"

#include <algorithm>
#include <regex>
#include <sstream>

#include "core/error.h"

namespace envshadow::gl {

namespace {
int file_index(AssembledSource& out, const std::string& name) {
    auto it = std::find(out.files.begin(), out.files.end(), name);
    if (it != out.files.end()) return int(it - out.files.begin());
    out.files.push_back(name);
    return int(out.files.size() - 1);
}

bool parse_include(const std::string& line, std::string& target) {
    static const std::regex include_re(R"re(^\s*#\s*include\s+"([^"]+)"\s*$)re");
    std::smatch m;
    if (!std::regex_match(line, m, include_re)) return false;
    target = m[1];
    return true;
}
// The info log of a shader or program: `get_iv` and `get_log` are glGetShaderiv and glGetShaderInfoLog,
// or the program's pair.
template <typename GetIv, typename GetLog>
std::string info_log(GLuint id, GetIv get_iv, GetLog get_log) {
    GLint length = 0;
    get_iv(id, GL_INFO_LOG_LENGTH, &length);
    std::string log(size_t(std::max(length, 1)), '\0');
    get_log(id, length, nullptr, log.data());
    log.resize(std::char_traits<char>::length(log.c_str()));
    return log;
}
}  // namespace

void ShaderLibrary::append(const std::string& name, AssembledSource& out, std::vector<std::string>& stack) const {
    if (std::find(stack.begin(), stack.end(), name) != stack.end())
        throw PlatformError(name + ": #include cycle through " + stack.back());
    auto it = sources_.find(name);
    if (it == sources_.end())
        throw PlatformError((stack.empty() ? std::string("shader") : stack.back()) + ": cannot find '" + name + "'");
    const bool first_time = std::find(out.files.begin(), out.files.end(), name) == out.files.end();
    const int id = file_index(out, name);
    if (!first_time && !stack.empty()) return;  // each include once
    stack.push_back(name);
    const std::string resume = " " + std::to_string(id) + "\n";
    out.text += "#line 1" + resume;
    std::istringstream in(it->second);
    std::string line;
    int number = 0;
    bool version_pending = stack.size() == 1;  // the top-level #version is emitted by assemble()
    while (std::getline(in, line)) {
        ++number;
        std::string target;
        if (version_pending && line.rfind("#version", 0) == 0) {
            version_pending = false;
            out.text += "#line " + std::to_string(number + 1) + resume;
        } else if (parse_include(line, target)) {
            append(target, out, stack);
            out.text += "#line " + std::to_string(number + 1) + resume;
        } else {
            out.text += line;
            out.text += '\n';
        }
    }
    stack.pop_back();
}

AssembledSource ShaderLibrary::assemble(const std::string& name, const std::vector<std::string>& defines) const {
    auto it = sources_.find(name);
    if (it == sources_.end()) throw PlatformError("shader: cannot find '" + name + "'");
    std::istringstream in(it->second);
    std::string version;
    int version_line = 0;
    for (std::string line; std::getline(in, line);) {
        ++version_line;
        if (line.rfind("#version", 0) == 0) {
            version = line;
            break;
        }
        if (line.find_first_not_of(" \t\r") != std::string::npos && line.rfind("//", 0) != 0)
            throw PlatformError(name + ":" + std::to_string(version_line) + ": #version must come first");
    }
    if (version.empty()) throw PlatformError(name + ": no #version line");

    AssembledSource out;
    out.text = version + "\n";
    for (const std::vector<std::string>* list : {&defines_, &defines})
        for (const std::string& d : *list) out.text += "#define " + d + "\n";
    std::vector<std::string> stack;
    append(name, out, stack);
    return out;
}

std::string rewrite_info_log(const std::string& log, const std::vector<std::string>& files) {
    // Mesa: "0:12(3): error: ..."; NVIDIA: "0(12) : error C0000: ...".
    static const std::regex mesa_re(R"(^(\d+):(\d+)\(\d+\):\s*(.*)$)");
    static const std::regex nvidia_re(R"(^(\d+)\((\d+)\)\s*:\s*(.*)$)");
    std::istringstream in(log);
    std::string out, line;
    while (std::getline(in, line)) {
        std::smatch m;
        if (std::regex_match(line, m, mesa_re) || std::regex_match(line, m, nvidia_re)) {
            const size_t index = std::stoul(m[1]);
            const std::string file = index < files.size() ? files[index] : "source " + m[1].str();
            out += file + ":" + m[2].str() + ": " + m[3].str() + "\n";
        } else if (!line.empty()) {
            out += line + "\n";
        }
    }
    if (!out.empty() && out.back() == '\n') out.pop_back();
    return out;
}

Program ShaderLibrary::build(const std::vector<ShaderStage>& stages, const std::vector<std::string>& defines,
                             const std::vector<std::string>& transform_feedback) const {
    std::vector<Shader> shaders;
    Program program(glCreateProgram());
    std::string names;
    for (const ShaderStage& stage : stages) {
        names += (names.empty() ? "" : "+") + stage.file;
        const AssembledSource source = assemble(stage.file, defines);
        Shader shader(glCreateShader(stage.type));
        const char* text = source.text.c_str();
        glShaderSource(shader.id(), 1, &text, nullptr);
        glCompileShader(shader.id());
        GLint ok = GL_FALSE;
        glGetShaderiv(shader.id(), GL_COMPILE_STATUS, &ok);
        if (!ok)
            throw PlatformError(
                "shader compile error\n" +
                rewrite_info_log(info_log(shader.id(), glGetShaderiv, glGetShaderInfoLog), source.files));
        glAttachShader(program.id(), shader.id());
        shaders.push_back(std::move(shader));
    }
    if (!transform_feedback.empty()) {
        std::vector<const char*> varyings;
        for (const std::string& v : transform_feedback) varyings.push_back(v.c_str());
        glTransformFeedbackVaryings(program.id(), GLsizei(varyings.size()), varyings.data(), GL_INTERLEAVED_ATTRIBS);
    }
    glLinkProgram(program.id());
    GLint ok = GL_FALSE;
    glGetProgramiv(program.id(), GL_LINK_STATUS, &ok);
    if (!ok)
        throw PlatformError(names + ": link error\n" + info_log(program.id(), glGetProgramiv, glGetProgramInfoLog));
    for (const Shader& s : shaders) glDetachShader(program.id(), s.id());
    ++programs_built_;
    return program;
}

}  // namespace envshadow::gl
