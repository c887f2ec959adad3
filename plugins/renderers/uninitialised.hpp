// Buffers whose new elements are left uninitialised: the renderers' largest arrays (gigabytes
// of points or polygons) are written in full before anything reads them, and zeroing them
// first cost seconds of memset that no cancel check could interrupt. A large allocation comes
// from fresh pages, which the kernel zeroes lazily as the real writes touch them.
#pragma once

#include <memory>
#include <new>
#include <utility>
#include <vector>

namespace fp_render {

template <class T>
struct Uninitialised : std::allocator<T> {
    template <class U>
    struct rebind {
        using other = Uninitialised<U>;
    };
    Uninitialised() = default;
    template <class U>
    Uninitialised(const Uninitialised<U>&) noexcept {}
    template <class U>
    void construct(U* p) noexcept {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... A>
    void construct(U* p, A&&... a) {
        ::new (static_cast<void*>(p)) U(std::forward<A>(a)...);
    }
};

/// A vector whose resize() leaves the new elements uninitialised.
template <class T>
using Buffer = std::vector<T, Uninitialised<T>>;

} // namespace fp_render
