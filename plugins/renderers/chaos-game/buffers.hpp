// chaos-game's buffers: a block's small aligned arrays (Buf) and the workers' large zeroed
// histograms (HugeBuf, assign_huge), 2 MiB aligned and advised into transparent huge pages so that
// the deposits, random over megabytes, do not miss the TLB on every point.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

// HugeBuf maps its memory itself on Linux (a fresh mapping comes zeroed), except under
// AddressSanitizer, which checks the bounds of operator new's blocks but not of a mapping: the
// sanitizer build keeps its checks on the deposits into the histograms.
#if defined(__SANITIZE_ADDRESS__)
#define FP_HUGEBUF_MAPPED 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define FP_HUGEBUF_MAPPED 0
#endif
#endif
#if !defined(FP_HUGEBUF_MAPPED)
#if defined(__linux__)
#define FP_HUGEBUF_MAPPED 1
#else
#define FP_HUGEBUF_MAPPED 0
#endif
#endif

namespace fp_chaos {

using std::size_t;
using std::uint32_t;
using std::uint64_t;

// ---------------------------------------------------------------- aligned buffers
struct AlignedFree {
    void operator()(void* p) const { ::operator delete(p, std::align_val_t(64)); }
};

/// Frees a HugeBuf: its mapping (FP_HUGEBUF_MAPPED), else its aligned allocation.
struct HugeFree {
    size_t bytes = 0;
    void operator()(void* p) const {
#if FP_HUGEBUF_MAPPED
        ::munmap(p, bytes);
#else
        ::operator delete(p, std::align_val_t(2u << 20));
#endif
    }
};

template <class U>
struct Buf {
    std::unique_ptr<U[], AlignedFree> p;
    void alloc(size_t n) {
        p.reset(static_cast<U*>(::operator new(std::max<size_t>(n, 1) * sizeof(U), std::align_val_t(64))));
        std::memset(static_cast<void*>(p.get()), 0, std::max<size_t>(n, 1) * sizeof(U));
    }
    U* get() const { return p.get(); }
};

/// A large zeroed buffer for random access (the histograms): 2 MiB aligned and, on Linux,
/// backed by transparent huge pages where the system allows, so that the deposits do not
/// miss the TLB on every point (a 1024 x 1024 histogram spans 8192 pages of 4 KiB). On Linux
/// (not under AddressSanitizer: FP_HUGEBUF_MAPPED) it is a fresh anonymous mapping, which the
/// kernel hands out zeroed as it faults it in: no memset, which would write every page once
/// more before the deposits do (a worker's 16 MiB of colour bins at 1024 x 1024: part of the
/// fixed cost of every render).
template <class U>
struct HugeBuf {
    std::unique_ptr<U[], HugeFree> p;
    /// `poll` is called between pieces of 64 MiB of zeroing where there is any (not mapped): a
    /// worker's histogram of an 8000 x 8000 render is 1 GiB, and a cancel must not wait for
    /// the whole memset.
    template <class Poll>
    void alloc(size_t n, Poll poll) {
        constexpr size_t huge = 2u << 20;
        const size_t bytes = (std::max<size_t>(n, 1) * sizeof(U) + huge - 1) / huge * huge;
        p.reset();
#if FP_HUGEBUF_MAPPED
        (void)poll;
        // Mapped with a huge page to spare, whose unaligned head and tail are unmapped.
        void* m = ::mmap(nullptr, bytes + huge, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (m == MAP_FAILED) throw std::bad_alloc();
        // (Pointer arithmetic on the mapping, not integers cast back to pointers.)
        char* const base = static_cast<char*>(m);
        const size_t lead = (huge - reinterpret_cast<uintptr_t>(m) % huge) % huge;
        char* const a = base + lead;
        if (lead > 0) ::munmap(base, lead);
        ::munmap(a + bytes, huge - lead);   // (lead < huge: never empty)
        ::madvise(a, bytes, MADV_HUGEPAGE); // advice only: failure is harmless
        p = std::unique_ptr<U[], HugeFree>(reinterpret_cast<U*>(a), HugeFree{bytes});
#else
        p = std::unique_ptr<U[], HugeFree>(static_cast<U*>(::operator new(bytes, std::align_val_t(huge))),
                                           HugeFree{bytes});
#if defined(__linux__) && defined(MADV_HUGEPAGE)
        ::madvise(static_cast<void*>(p.get()), bytes, MADV_HUGEPAGE); // advice only: failure is harmless
#endif
        constexpr size_t piece = size_t(64) << 20;
        for (size_t done = 0; done < bytes; done += piece) {
            poll();
            std::memset(reinterpret_cast<char*>(p.get()) + done, 0, std::min(piece, bytes - done));
        }
#endif
    }
    U* get() const { return p.get(); }
};

/// v.assign(n, {}) with the new buffer advised into transparent huge pages before it is
/// written (reserve, madvise the 2 MiB-aligned part, then assign): the 32 MiB total histogram
/// and the 12 MiB image of a 1024 x 1024 render fault in as about 22 huge pages instead of
/// 11264 small ones. Part of the fixed cost per render that does not scale with the threads.
/// `poll` is called between pieces of 64 MiB: filling gigabytes (an 8000 x 8000 histogram is
/// 2 GiB) takes seconds, and a cancel must not wait for it.
template <class V, class Poll>
void assign_huge(V& v, size_t n, Poll poll) {
    v.clear();
    v.shrink_to_fit();
    v.reserve(n);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    constexpr uintptr_t huge = 2u << 20;
    char* const data = reinterpret_cast<char*>(v.data());
    const uintptr_t start = reinterpret_cast<uintptr_t>(data);
    const uintptr_t b = (start + huge - 1) & ~(huge - 1);
    const uintptr_t e = (start + n * sizeof(typename V::value_type)) & ~(huge - 1);
    if (e > b) ::madvise(data + (b - start), e - b, MADV_HUGEPAGE); // advice only
#endif
    // Filled piece by piece within the reserved capacity (no reallocation), value-initialised:
    // for fp::HistBin the compilers make that a memset, where a fill with a copy of
    // HistBin{} is a loop of 32-byte stores (at 1024 x 1024, 4 ms against 10).
    const size_t piece = std::max<size_t>(1, (size_t(64) << 20) / sizeof(typename V::value_type));
    for (size_t done = 0; done < n; done = v.size()) {
        poll();
        v.resize(std::min(n, done + piece));
    }
}

} // namespace fp_chaos
