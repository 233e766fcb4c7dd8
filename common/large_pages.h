// Memory for the large arrays that rays read at random: the BVH's nodes and the leaves' blocks of
// triangles and quads.
//
// A ray through a mesh of a million triangles visits a few dozen nodes scattered over tens of
// megabytes. With the usual 4 KiB pages each visit may also miss in the TLB, the cache of
// address translations, and wait for a page-table walk. Linux backs memory with 2 MiB pages
// where a program asks for them (madvise(MADV_HUGEPAGE), "transparent huge pages"); Embree
// does, and so do we. An array of at least 2 MiB starts on a 2 MiB boundary and its whole 2 MiB
// stretches are marked: they can then be 2 MiB pages, while its tail, shorter than one, stays in
// 4 KiB pages, so no memory is wasted. Smaller arrays are allocated as usual. Where the system
// declines (or is not Linux), the memory is ordinary memory: nothing else changes.
#pragma once

#include <stdlib.h>  // posix_memalign

#include <cstddef>
#include <cstdlib>
#include <new>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace lessons {

inline constexpr size_t kLargePageBytes = size_t{2} << 20;

template <class T>
class LargePageAllocator {
public:
    using value_type = T;
    LargePageAllocator() = default;
    template <class U>
    LargePageAllocator(const LargePageAllocator<U>&) {}

    T* allocate(size_t n) {
        if (n > static_cast<size_t>(-1) / sizeof(T)) throw std::bad_array_new_length();
        const size_t bytes = n * sizeof(T);
        if (bytes < kLargePageBytes)
            return static_cast<T*>(::operator new(bytes, std::align_val_t(kAlignment)));
        void* p = nullptr;
        if (posix_memalign(&p, kLargePageBytes, bytes) != 0) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
        // Whole 2 MiB stretches only, so the tail is never rounded up to a page of 2 MiB. A
        // request: if the system declines, the pages stay 4 KiB.
        madvise(p, bytes / kLargePageBytes * kLargePageBytes, MADV_HUGEPAGE);
#endif
        return static_cast<T*>(p);
    }
    void deallocate(T* p, size_t n) {
        if (n * sizeof(T) < kLargePageBytes)
            ::operator delete(p, std::align_val_t(kAlignment));
        else
            std::free(p);
    }

    friend bool operator==(const LargePageAllocator&, const LargePageAllocator&) {
        return true;
    }

private:
    static constexpr size_t kAlignment = alignof(T) > __STDCPP_DEFAULT_NEW_ALIGNMENT__
                                             ? alignof(T)
                                             : __STDCPP_DEFAULT_NEW_ALIGNMENT__;
};

template <class T>
using LargePageVector = std::vector<T, LargePageAllocator<T>>;

}  // namespace lessons
