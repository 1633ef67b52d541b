#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <gtest/gtest.h>

#include "core/atomic_file.h"
#include "core/error.h"

namespace envshadow {
namespace {

std::filesystem::path fresh_dir(const char* name) {
    auto dir = std::filesystem::temp_directory_path() / name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

TEST(AtomicFile, AFailedWriteLeavesNoFileAndNoTemporary) {
    const auto dir = fresh_dir("envshadow_atomic_fail");
    const auto target = dir / "out.png";
    EXPECT_THROW(write_atomically(target,
                                  [](const std::filesystem::path& tmp) {
                                      std::ofstream(tmp) << "half of it";
                                      throw std::runtime_error("interrupted");
                                  }),
                 std::runtime_error);
    EXPECT_FALSE(std::filesystem::exists(target));
    EXPECT_TRUE(std::filesystem::is_empty(dir));
}

TEST(AtomicFile, AFailedWriteKeepsThePreviousFile) {
    const auto dir = fresh_dir("envshadow_atomic_keep");
    const auto target = dir / "out.json";
    write_file_atomically(target, "old");
    EXPECT_THROW(write_atomically(target, [](const std::filesystem::path&) { throw InputError("bad"); }), InputError);
    std::ifstream in(target);
    std::string contents;
    in >> contents;
    EXPECT_EQ(contents, "old");
}

TEST(AtomicFile, WritesIntoAMissingFolderFailWithAnInputError) {
    EXPECT_THROW(write_file_atomically("/nonexistent-folder-envshadow/x.json", "{}"), InputError);
}

}  // namespace
}  // namespace envshadow
