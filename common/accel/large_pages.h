// Memory for the large arrays that rays read at random: the BVH's nodes and the leaves' blocks of
// triangles and quads.
//
// A ray through a mesh of a million triangles visits a few dozen nodes scattered over tens of
// megabytes. With the usual 4 KiB pages each visit may also miss in the TLB, the cache of
// address translations, and wait for a page-table walk. Linux backs memory with 2 MiB pages
// where a program asks for them (madvise(MADV_HUGEPAGE), "transparent huge pages"); Embree
// does, and so do we. On Linux an array of at least 2 MiB gets a mapping of its own (mmap),
// starting on a 2 MiB boundary, and its whole 2 MiB stretches are marked: they can then be 2 MiB
// pages, while its tail, shorter than one, stays in 4 KiB pages, so no memory is wasted, and
// the marking ends with the mapping. Smaller arrays, and every array elsewhere, are allocated as
// usual. Where the system declines, the memory is ordinary memory: nothing else changes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace lessons {

inline constexpr size_t kLargePageBytes = size_t{2} << 20;

template <class T>
class LargePageAllocator {
public:
    using value_type = T;
    LargePageAllocator() noexcept = default;
    template <class U>
    LargePageAllocator(const LargePageAllocator<U>&) noexcept {}

    T* allocate(size_t n) {
        if (n > static_cast<size_t>(-1) / sizeof(T)) throw std::bad_array_new_length();
        const size_t bytes = n * sizeof(T);
#if defined(__linux__)
        if (bytes >= kLargePageBytes) return static_cast<T*>(map_large(bytes));
#endif
        return static_cast<T*>(::operator new(bytes, std::align_val_t(kAlignment)));
    }
    // An element made without a value is default-initialised: for the plain arrays here (nodes,
    // blocks) that leaves it unwritten, instead of zeroed as std::vector would, since the build
    // fills them, on several threads, and zeroing first would write every page once more, on one.
    template <class U>
    void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
    void deallocate(T* p, size_t n) noexcept {
#if defined(__linux__)
        if (n * sizeof(T) >= kLargePageBytes) {
            munmap(p, mapped_bytes(n * sizeof(T)));
            return;
        }
#endif
        ::operator delete(p, std::align_val_t(kAlignment));
    }

    template <class U>
    friend bool operator==(const LargePageAllocator&, const LargePageAllocator<U>&) noexcept {
        return true;
    }

private:
    static constexpr size_t kAlignment = alignof(T) > __STDCPP_DEFAULT_NEW_ALIGNMENT__
                                             ? alignof(T)
                                             : __STDCPP_DEFAULT_NEW_ALIGNMENT__;

#if defined(__linux__)
    // The mapping's length: the array rounded up to whole 4 KiB (system) pages.
    static size_t mapped_bytes(size_t bytes) {
        const auto page = static_cast<size_t>(sysconf(_SC_PAGESIZE));
        return (bytes + page - 1) / page * page;
    }
    // Maps 2 MiB more than needed, keeps the part that starts on a 2 MiB boundary, and returns
    // the rest; then marks the whole 2 MiB stretches.
    static void* map_large(size_t bytes) {
        const size_t length = mapped_bytes(bytes);
        void* raw = mmap(nullptr, length + kLargePageBytes, PROT_READ | PROT_WRITE,
                         MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (raw == MAP_FAILED) throw std::bad_alloc();
        const auto first = reinterpret_cast<uintptr_t>(raw);
        const uintptr_t start = (first + kLargePageBytes - 1) / kLargePageBytes * kLargePageBytes;
        const uintptr_t end = first + length + kLargePageBytes;
        if (start > first) munmap(raw, start - first);
        if (end > start + length)
            munmap(reinterpret_cast<void*>(start + length), end - start - length);
        void* p = reinterpret_cast<void*>(start);
#if defined(MADV_HUGEPAGE)
        madvise(p, bytes / kLargePageBytes * kLargePageBytes, MADV_HUGEPAGE);  // a request
#endif
        return p;
    }
#endif
};

template <class T>
using LargePageVector = std::vector<T, LargePageAllocator<T>>;

}  // namespace lessons
