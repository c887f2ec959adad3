// Point batches: structure of arrays, so that plugin loops vectorise.
//
// Every hot-path method of an interface takes a whole batch. An optional `mask` (one byte
// per point, non-zero = active) marks the orbits still running where they retire at
// different times; a method must leave inactive points unchanged. A null mask means all
// points are active.
#pragma once

#include <cstddef>

namespace fp {

template <class T>
struct Points {
    T* x = nullptr;
    T* y = nullptr;
    std::size_t n = 0;

    /// The sub-batch [begin, begin + count).
    Points sub(std::size_t begin, std::size_t count) const { return {x + begin, y + begin, count}; }
};

using Mask = const unsigned char*;

/// Batches inside plugins are processed in chunks of this many points, so that scratch
/// space fits on the stack (no allocation per batch) and stays in L1.
constexpr std::size_t chunk_size = 256;

} // namespace fp
