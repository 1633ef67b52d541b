#include "env/level_storage.h"

#include <algorithm>
#include <cstdlib>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace envshadow {

namespace detail {

void* allocate_level_storage(std::size_t bytes) {
    constexpr std::size_t kHugePage = std::size_t(2) << 20;
    void* storage = nullptr;
    if (bytes >= kHugePage / 2) {
        const std::size_t rounded = (bytes + kHugePage - 1) & ~(kHugePage - 1);
        storage = std::aligned_alloc(kHugePage, rounded);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
        if (storage) madvise(storage, rounded, MADV_HUGEPAGE);  // advice only
#endif
    } else {
        storage = std::malloc(std::max<std::size_t>(bytes, 1));
    }
    if (!storage) throw std::bad_alloc();
    return storage;
}

void free_level_storage(void* storage) noexcept {
    std::free(storage);
}

}  // namespace detail

}  // namespace envshadow
