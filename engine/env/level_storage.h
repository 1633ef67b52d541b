#pragma once
#include <cstddef>
#include <memory>
#include <new>
#include <utility>

namespace envshadow {

// Storage of the levels (and the prefiltering's scratch): at least 1 MB is 2 MB-aligned, on transparent huge
// pages where the kernel offers them (Linux, THP in madvise mode), and resize leaves the texels uninitialised
// (the prefiltering writes each once, from the worker threads). First-touching tens of MB of fresh 4 KiB pages
// cost more than the arithmetic (docs/PERFORMANCE.md, "Prefiltering").
namespace detail {
void* allocate_level_storage(std::size_t bytes);
void free_level_storage(void* storage) noexcept;
}  // namespace detail

template <class T>
struct LevelAllocator {
    using value_type = T;
    LevelAllocator() = default;
    template <class U>
    LevelAllocator(const LevelAllocator<U>&) noexcept {}
    T* allocate(std::size_t count) { return static_cast<T*>(detail::allocate_level_storage(count * sizeof(T))); }
    void deallocate(T* storage, std::size_t) noexcept { detail::free_level_storage(storage); }
    template <class U, class... Args>
    void construct(U* at, Args&&... args) {
        if constexpr (sizeof...(Args) == 0)
            ::new (static_cast<void*>(at)) U;  // default-initialised: no zeroing
        else
            ::new (static_cast<void*>(at)) U(std::forward<Args>(args)...);
    }
    template <class U>
    bool operator==(const LevelAllocator<U>&) const noexcept {
        return true;
    }
};

// Scratch arrays, uninitialised, on the same storage (huge pages from 1 MB).
struct StorageDeleter {
    void operator()(void* storage) const noexcept { detail::free_level_storage(storage); }
};
template <class T>
using Scratch = std::unique_ptr<T[], StorageDeleter>;
template <class T>
Scratch<T> scratch(std::size_t count) {
    return Scratch<T>(static_cast<T*>(detail::allocate_level_storage(count * sizeof(T))));
}

}  // namespace envshadow
