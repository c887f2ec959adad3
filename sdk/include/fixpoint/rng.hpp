// Random streams for chains.
//
// Each chain of a render owns the pcg32 stream (seed, chain index): pcg32's stream selector
// makes streams independent, so a chain draws the same numbers whichever thread runs it.
// The distributions are written here, not taken from <random>, whose distributions differ
// between standard libraries (golden images would break elsewhere).
#pragma once

#include <pcg_random.hpp>

#include <cstdint>

namespace fp {

using Rng = pcg32;

/// SplitMix64 finaliser: spreads a user seed over all 64 bits.
constexpr std::uint64_t mix64(std::uint64_t z) {
    z += 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

inline Rng chain_stream(std::uint64_t seed, std::uint64_t chain) { return Rng(mix64(seed), chain); }

/// Uniform in [0, 1) with 24 random bits.
inline float uniform_float(Rng& r) { return float(r() >> 8) * 0x1.0p-24f; }

/// Uniform in [0, 1) with 53 random bits.
inline double uniform_double(Rng& r) {
    const std::uint64_t hi = r() >> 5, lo = r() >> 6; // 27 + 26 bits
    return double((hi << 26) | lo) * 0x1.0p-53;
}

/// Uniform integer in [0, n), n > 0, without bias (Lemire's method).
inline std::uint32_t uniform_below(Rng& r, std::uint32_t n) {
    std::uint64_t m = std::uint64_t(r()) * n;
    auto low = std::uint32_t(m);
    if (low < n) {
        const std::uint32_t threshold = std::uint32_t(-n) % n;
        while (low < threshold) {
            m = std::uint64_t(r()) * n;
            low = std::uint32_t(m);
        }
    }
    return std::uint32_t(m >> 32);
}

} // namespace fp
