#include "core/atomic_file.h"

#include <atomic>
#include <fstream>
#include <system_error>

#include <unistd.h>

#include "core/error.h"

namespace envshadow {

void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path& temporary)>& write_to) {
    static std::atomic<unsigned> counter{0};
    std::filesystem::path temporary = target;
    // Keep the extension last: some writers (OpenEXR, stb) do not care, but people looking at a
    // folder mid-run should see what the file is.
    temporary.replace_filename("." + target.filename().string() + ".tmp" + std::to_string(::getpid()) + "-" +
                               std::to_string(counter++));
    try {
        write_to(temporary);
        std::error_code ec;
        std::filesystem::rename(temporary, target, ec);
        if (ec) throw InputError(target.string() + ": cannot write: " + ec.message());
    } catch (...) {
        std::error_code ignored;
        std::filesystem::remove(temporary, ignored);
        throw;
    }
}

void write_file_atomically(const std::filesystem::path& target, std::string_view contents) {
    write_atomically(target, [&](const std::filesystem::path& temporary) {
        std::ofstream out(temporary, std::ios::binary);
        out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
        out.close();
        if (!out) throw InputError(target.string() + ": cannot write (check the folder exists and is writable)");
    });
}

}  // namespace envshadow
