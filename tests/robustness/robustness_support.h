#pragma once
// Helpers of the malformed-input tests: a fresh folder per test, the one-line error contract, byte
// mutations with a fixed seed (so a failure names an input that can be made again).
#include <cstdint>
#include <filesystem>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/test_folder.h"
#include "core/error.h"

namespace envshadow::test {

inline std::filesystem::path fresh_folder() {
    return fresh_test_folder("envshadow_robustness");
}

// "<file>: <reason>" on one line, the reason not empty.
inline ::testing::AssertionResult is_one_line_naming(const std::string& message, const std::filesystem::path& file) {
    if (message.rfind(file.string() + ": ", 0) != 0)
        return ::testing::AssertionFailure() << "does not start with \"" << file.string() << ": \": " << message;
    if (message.find_first_of("\r\n") != std::string::npos)
        return ::testing::AssertionFailure() << "spans lines: " << message;
    if (message.size() <= file.string().size() + 2) return ::testing::AssertionFailure() << "no reason: " << message;
    return ::testing::AssertionSuccess();
}

// Runs `load` on `file`: it must either succeed (and then `check` must hold) or throw an InputError
// of one line naming the file. Anything else (another exception, a crash, a sanitizer report)
// fails. Returns true when it loaded.
inline bool loads_or_fails_cleanly(const std::filesystem::path& file, const std::function<void()>& load,
                                   const std::string& what) {
    try {
        load();
        return true;
    } catch (const InputError& e) {
        EXPECT_TRUE(is_one_line_naming(e.what(), file)) << what;
        return false;
    } catch (const std::exception& e) {
        ADD_FAILURE() << what << ": " << typeid(e).name() << " instead of InputError: " << e.what();
        return false;
    }
}

// `count` copies of `original`, each with 1 to 4 bits flipped at random places (seeded).
inline std::vector<std::vector<std::uint8_t>> bit_flipped(const std::vector<std::uint8_t>& original, int count,
                                                          std::uint32_t seed) {
    std::mt19937 random(seed);
    std::vector<std::vector<std::uint8_t>> out;
    for (int k = 0; k < count; ++k) {
        std::vector<std::uint8_t> bytes = original;
        const int flips = 1 + int(random() % 4);
        for (int f = 0; f < flips; ++f) {
            const std::size_t at = random() % bytes.size();
            bytes[at] ^= std::uint8_t(1u << (random() % 8));
        }
        out.push_back(std::move(bytes));
    }
    return out;
}

// Prefix lengths to truncate a file of `size` bytes at: every length up to `dense`, then `sparse`
// lengths spread evenly over the rest (always including size - 1).
inline std::vector<std::size_t> truncation_lengths(std::size_t size, std::size_t dense, std::size_t sparse) {
    std::vector<std::size_t> lengths;
    for (std::size_t n = 0; n < size && n <= dense; ++n) lengths.push_back(n);
    if (size > dense + 1)
        for (std::size_t k = 1; k <= sparse; ++k) lengths.push_back(dense + (size - 1 - dense) * k / sparse);
    return lengths;
}

}  // namespace envshadow::test
