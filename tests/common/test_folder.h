#pragma once
// A fresh folder per test, shared by tests/scene and tests/robustness.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

namespace envshadow::test {

// <gtest temp dir>/<area>/<suite>.<test>, emptied: each test starts from nothing and its files stay
// for a look after a failure.
inline std::filesystem::path fresh_test_folder(const std::string& area) {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const auto dir = std::filesystem::path(::testing::TempDir()) / area /
                     (std::string(info->test_suite_name()) + "." + info->name());
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

}  // namespace envshadow::test
