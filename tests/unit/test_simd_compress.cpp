// The SIMD layer's compress (fixpoint/simd-inl.hpp: compress_order, compress,
// compress_blended_store), which replaces Highway's where that copies a table at each call:
// for every mask of a vector, on every target this machine has, in 32- and 64-bit lanes, the
// lanes set in the mask come first and in order (what hn::Compress gives there), and the
// blended store writes those lanes and nothing after them.
#include <fixpoint/simd.hpp>

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "unit/test_simd_compress.cpp"
#include <hwy/foreach_target.h> // IWYU pragma: keep

#include <fixpoint/simd-inl.hpp>

#include <cstddef>
#include <cstdint>

// Per target: for mask `bits` (lane l set where bit l is, among the vector's lanes), the
// compressed vector of 0, 1, 2, ... (as T) into out, and a blended store of it onto `mem`,
// prefilled by the caller; the target's lane count into *lanes.
HWY_BEFORE_NAMESPACE();
namespace fp_test_compress::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
namespace fs = fp::simd::HWY_NAMESPACE;

template <class T>
void run(std::uint64_t bits, T* out, T* mem, std::size_t* lanes) {
    const hn::ScalableTag<T> d;
    const hn::RebindToUnsigned<decltype(d)> du;
    using U = hn::TFromD<decltype(du)>;
    const std::size_t N = hn::Lanes(d);
    alignas(HWY_MAX_BYTES) U set[HWY_MAX_BYTES / sizeof(T)] = {};
    for (std::size_t l = 0; l < N; ++l) set[l] = (bits >> l) & 1 ? U(1) : U(0);
    const auto m = hn::RebindMask(d, hn::Ne(hn::Load(du, set), hn::Zero(du)));
    const auto v = hn::ConvertTo(d, hn::BitCast(hn::RebindToSigned<decltype(d)>(), hn::Iota(du, U(0))));
    const auto order = fs::compress_order(d, m);
    hn::StoreU(fs::compress(d, v, m, order), d, out);
    fs::compress_blended_store(d, v, m, order, mem);
    *lanes = N;
}
void run_f(std::uint64_t bits, float* out, float* mem, std::size_t* lanes) { run(bits, out, mem, lanes); }
void run_d(std::uint64_t bits, double* out, double* mem, std::size_t* lanes) { run(bits, out, mem, lanes); }

} // namespace fp_test_compress::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace fp_test_compress {
HWY_EXPORT(run_f);
HWY_EXPORT(run_d);

template <class T>
std::size_t dispatch(std::uint64_t bits, T* out, T* mem) {
    std::size_t lanes = 0;
    if constexpr (sizeof(T) == 4)
        HWY_DYNAMIC_DISPATCH(run_f)(bits, out, mem, &lanes);
    else
        HWY_DYNAMIC_DISPATCH(run_d)(bits, out, mem, &lanes);
    return lanes;
}

template <class T>
void check_every_mask(const std::string& target) {
    // (Not HWY_MAX_BYTES, which here is the static target's: room for SVE-2048's vectors.)
    constexpr std::size_t most = 256 / sizeof(T);
    T out[most], mem[most];
    const std::size_t N = dispatch<T>(0, out, mem);
    // Every mask for vectors of up to 10 lanes (the table path has up to 8); for wider ones
    // (AVX-512's 16 floats) a pseudo-random thousand.
    const std::uint64_t masks = N <= 10 ? (std::uint64_t(1) << N) : 1000;
    std::uint64_t r = 12345;
    for (std::uint64_t k = 0; k < masks; ++k) {
        std::uint64_t bits = k;
        if (N > 10) {
            r = r * 6364136223846793005ull + 1442695040888963407ull;
            bits = (r >> 20) & ((std::uint64_t(1) << N) - 1);
        }
        for (std::size_t l = 0; l < most; ++l) mem[l] = T(-1);
        ASSERT_EQ(dispatch<T>(bits, out, mem), N);
        std::size_t at = 0;
        for (std::size_t l = 0; l < N; ++l) {
            if (!((bits >> l) & 1)) continue;
            EXPECT_EQ(out[at], T(l)) << target << ", mask " << bits << ", lane " << at;
            EXPECT_EQ(mem[at], T(l)) << target << ", mask " << bits << ", stored lane " << at;
            ++at;
        }
        for (std::size_t l = at; l < N; ++l)
            EXPECT_EQ(mem[l], T(-1)) << target << ", mask " << bits << ": written past the lanes at " << l;
    }
}

TEST(SimdCompress, EveryMaskOnEveryTarget) {
    for (const std::string& target : fp::simd::supported_targets()) {
        ASSERT_TRUE(fp::simd::force_target(target));
        check_every_mask<float>(target);
        check_every_mask<double>(target);
    }
    fp::simd::force_target("");
}

} // namespace fp_test_compress
#endif
