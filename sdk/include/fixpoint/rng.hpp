// Random streams for chains.
//
// Each chain of a render owns the pcg32 stream (seed, chain index): pcg32's stream selector
// makes streams independent, so a chain draws the same numbers whichever thread runs it.
// The distributions are written here, not taken from <random>, whose distributions differ
// between standard libraries (golden images would break elsewhere).
#pragma once

#include <pcg_random.hpp>

#include <bit>
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

/// The random key of chain `chain`'s point at step n, for maps that draw random numbers
/// (fp::Points::key): a counter-based stream of the chain, so that it costs no pcg32 output
/// and leaves the chain's own draws (its map choices) as they are without random maps.
constexpr std::uint64_t map_key(std::uint64_t seed, std::uint64_t chain, std::uint64_t n) {
    return mix64(mix64(seed ^ 0x6A09E667F3BCC909ull) + mix64(chain) * 0x9E3779B97F4A7C15ull + n);
}

/// A key from a point's own bits (x and y as doubles), for batches without keys.
inline std::uint64_t point_key(double x, double y) {
    return mix64(std::bit_cast<std::uint64_t>(x) ^ mix64(std::bit_cast<std::uint64_t>(y)));
}

/// The j-th uniform number in [0, 1) of key k at application `salt` (53 random bits).
constexpr double map_uniform(std::uint64_t k, std::uint32_t salt, std::uint32_t j) {
    const std::uint64_t z = mix64(k + (std::uint64_t(salt) << 32 | j) * 0xD1B54A32D192ED03ull);
    return double(z >> 11) * 0x1.0p-53;
}

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
