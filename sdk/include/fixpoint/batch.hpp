// Point batches: structure of arrays, so that plugin loops vectorise.
//
// Every hot-path method of an interface takes a whole batch. An optional `mask` (one byte
// per point, non-zero = active) marks the orbits still running where they retire at
// different times; a method must leave inactive points unchanged. A null mask means all
// points are active.
//
// Maps that draw random numbers (flam3's julia, blur, ...) take them from `key`: one 64-bit
// key per point, drawn by the renderer from the point's chain (fixpoint/rng.hpp's map_key),
// so that a render stays a pure function of its recipe whichever thread or lane runs a chain.
// `salt` tells apart the applications of one map within one step (a scheme that applies T
// twice). A batch without keys (a caller that is not a chain game: the conformance suite, a
// view fit) gets randoms from the points' own bits instead (fp::point_key).
#pragma once

#include <cstddef>
#include <cstdint>

namespace fp {

template <class T>
struct Points {
    T* x = nullptr;
    T* y = nullptr;
    std::size_t n = 0;
    const std::uint64_t* key = nullptr; ///< per-point random keys, or null (see above)
    std::uint32_t salt = 0;             ///< which application of the map within the step

    /// The sub-batch [begin, begin + count).
    Points sub(std::size_t begin, std::size_t count) const {
        return {x + begin, y + begin, count, key ? key + begin : nullptr, salt};
    }
};

using Mask = const unsigned char*;

/// Batches inside plugins are processed in chunks of this many points, so that scratch
/// space fits on the stack (no allocation per batch) and stays in L1.
constexpr std::size_t chunk_size = 256;

} // namespace fp
