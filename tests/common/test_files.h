#pragma once
// Files for the tests (tests/scene, tests/robustness, the robustness sample library and the fuzz
// seed writer): whole files written and read at once. No gtest here (test_folder.h has it).
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

namespace envshadow::test {

inline void write_bytes(const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes) {
    // Removed first: truncating a file in place makes ext4 flush it to disk on close (auto_da_alloc),
    // about 3 ms each, which the tests that write thousands of mutants cannot afford.
    std::error_code ignored;
    std::filesystem::remove(path, ignored);
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    out.close();
    if (!out) throw std::runtime_error("cannot write " + path.string());
}

inline void write_text(const std::filesystem::path& path, const std::string& text) {
    write_bytes(path, std::vector<std::uint8_t>(text.begin(), text.end()));
}

inline std::vector<std::uint8_t> read_bytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("cannot read " + path.string());
    return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The file's contents, "" when it cannot be read (an output that should not exist).
inline std::string read_text(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace envshadow::test
