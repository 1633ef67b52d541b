#pragma once
// One facility for the names of an enum's values (the command line's spelling), so that an enum
// declares its names once, in one table beside it, and is printed, parsed and listed from that table:
//
//   enum class PcfKernel { hardware_2x2, wide };
//   inline constexpr EnumName<PcfKernel> kPcfKernelNames[] = {{PcfKernel::hardware_2x2, "2x2"},
//                                                             {PcfKernel::wide, "wide"}};
//   constexpr std::span<const EnumName<PcfKernel>> enum_names(PcfKernel) { return kPcfKernelNames; }
//
//   to_string(PcfKernel::wide) == "wide";  parse_enum<PcfKernel>("2x2");  enum_value_names<PcfKernel>();
//   enum_values<PcfKernel>()
//
// enum_names() is found by argument-dependent lookup, in the enum's own namespace.
#include <concepts>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "core/error.h"

namespace envshadow {

template <typename Enum>
struct EnumName {
    Enum value;
    std::string_view name;
};

// An enum whose namespace declares `std::span<const EnumName<Enum>> enum_names(Enum)`.
template <typename Enum>
concept NamedEnum = std::is_enum_v<Enum> && requires(Enum e) {
    { enum_names(e) } -> std::convertible_to<std::span<const EnumName<Enum>>>;
};

template <NamedEnum Enum>
std::string_view to_string(Enum value) {
    for (const auto& [v, name] : enum_names(Enum{}))
        if (v == value) return name;
    return "?";
}

// The names in the table's order: for help texts and the command line's validators.
template <NamedEnum Enum>
std::vector<std::string> enum_value_names() {
    std::vector<std::string> names;
    for (const auto& entry : enum_names(Enum{})) names.emplace_back(entry.name);
    return names;
}

// The values in the table's order: for loops over every value.
template <NamedEnum Enum>
std::vector<Enum> enum_values() {
    std::vector<Enum> values;
    for (const auto& entry : enum_names(Enum{})) values.push_back(entry.value);
    return values;
}

// "a, b, c": the names as a message lists them.
template <NamedEnum Enum>
std::string enum_names_list() {
    std::string list;
    for (const auto& entry : enum_names(Enum{})) list += (list.empty() ? "" : ", ") + std::string(entry.name);
    return list;
}

// The value named `name`; UsageError "'x' is not one of a, b, c" otherwise.
template <NamedEnum Enum>
Enum parse_enum(std::string_view name) {
    for (const auto& [value, text] : enum_names(Enum{}))
        if (text == name) return value;
    throw UsageError("'" + std::string(name) + "' is not one of " + enum_names_list<Enum>());
}

}  // namespace envshadow
