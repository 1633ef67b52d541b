#include "render/shader_interface.h"

#include <cctype>
#include <string_view>

namespace envshadow::render::shader {

namespace {
#define ENVSHADOW_SHADER_ENTRY(kind, name, value) Constant{#kind, #name, value},
constexpr Constant kConstants[] = {ENVSHADOW_SHADER_INTERFACE(ENVSHADOW_SHADER_ENTRY)};
#undef ENVSHADOW_SHADER_ENTRY
}  // namespace

std::string Constant::define_name() const {
    std::string define = std::string_view(kind) == "size" ? "" : std::string(kind) + "_";
    define += name;
    for (char& c : define) c = char(std::toupper(static_cast<unsigned char>(c)));
    return define;
}

std::span<const Constant> constants() {
    return kConstants;
}

std::vector<std::string> defines() {
    std::vector<std::string> out;
    for (const Constant& constant : kConstants)
        out.push_back(constant.define_name() + " " + std::to_string(constant.value));
    return out;
}

}  // namespace envshadow::render::shader
