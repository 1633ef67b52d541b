#pragma once
#include <filesystem>
#include <functional>
#include <string_view>

namespace envshadow {

// Writes `target` through `write_to`, which receives a temporary path in the same folder. The
// temporary is renamed over `target` only when `write_to` returns; if it throws, the temporary is
// removed and the exception propagates, so no half-written file is ever left under `target`.
void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path& temporary)>& write_to);

// Convenience for text and binary blobs.
void write_file_atomically(const std::filesystem::path& target, std::string_view contents);

}  // namespace envshadow
