// flame-ref.cpp - a hand-written kernel of the `flame` rows' whole work: what a chaos game with
// fixpoint's `flame` colouring costs when written by hand, for bench/targets.sh to set beside
// the hit-count reference (../shared/perf-reference/ifs.cpp, the yardstick issue 11 names).
//
// The same orbits as ifs.cpp's simd variant: 64 orbits in float lanes (GCC vector extensions
// sized to the ISA it is built for), xoshiro128+ per lane, a map by cumulative thresholds,
// the maps' coefficients picked per lane, a branch-free bin index with a dump bin. Added, the
// work of fixpoint's `flame` colourer (plugins/colourers/flame.cpp, mode mean) on every
// point:
//   - each orbit carries a colour (r, g, b), after a step by map j c = (c + c_j) * 0.5;
//   - the colour clamped to [0, 1] and quantised, round(c * 65535);
//   - each point adds {1, r, g, b} to a 16-byte bin of 32-bit sums, and a bin whose hit count
//     reaches 2^16 is spilled into 64-bit sums (before a colour sum can wrap).
// Build: g++ -O3 -march=native -o flame-ref bench/flame-ref.cpp
// Usage: flame-ref map=sierpinski|fern n=1e8 reps=5 layout=rows|tiles
//        (one thread; prints a SUMMARY line; layout: bin_of below, rows unless asked)
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <sys/mman.h>

namespace {

double now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

uint64_t splitmix64(uint64_t& s) {
    uint64_t z = (s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

std::string arg(int argc, char** argv, const char* key, const char* def) {
    const size_t k = std::strlen(key);
    for (int i = 1; i < argc; ++i)
        if (!std::strncmp(argv[i], key, k) && argv[i][k] == '=') return argv[i] + k + 1;
    return def;
}

constexpr int W = 1024, H = 1024;
constexpr int DUMP = W * H;

// The vectors are as wide as the widest the build's target aligns (the compiler's own
// __BIGGEST_ALIGNMENT__: 64 bytes with AVX-512, 32 with AVX, 16 with SSE or NEON), capped to
// 16..64: wider vectors than the hardware's make GCC fall back to scalar code.
constexpr int VBYTES = __BIGGEST_ALIGNMENT__ > 64   ? 64
                       : __BIGGEST_ALIGNMENT__ < 16 ? 16
                                                    : __BIGGEST_ALIGNMENT__;
constexpr int L = VBYTES / 4;
typedef float vf __attribute__((vector_size(VBYTES)));
typedef int32_t vi __attribute__((vector_size(VBYTES)));
typedef uint32_t vu __attribute__((vector_size(VBYTES)));

vf splat(float v) {
    vf r;
    for (int l = 0; l < L; ++l) r[l] = v;
    return r;
}

/// A per-lane lookup among at most L values (one permute where the ISA has one).
struct Table {
    vf t{};
    vf pick(vi idx) const { return __builtin_shuffle(t, idx); }
};

struct VRng { // xoshiro128+ in L lanes
    vu s0, s1, s2, s3;
    void seed(uint64_t sd) {
        for (int l = 0; l < L; ++l) {
            const uint64_t a = splitmix64(sd), b = splitmix64(sd);
            s0[l] = uint32_t(a), s1[l] = uint32_t(a >> 32), s2[l] = uint32_t(b),
            s3[l] = uint32_t(b >> 32) | 1u;
        }
    }
    vu next() {
        const vu r = s0 + s3, t = s1 << 9;
        s2 ^= s0, s3 ^= s1, s1 ^= s2, s0 ^= s3, s2 ^= t;
        s3 = (s3 << 11) | (s3 >> 21);
        return r;
    }
};

struct Ifs {
    int m;
    float a[4], b[4], c[4], d[4], e[4], f[4], w[4];
    float cr[4], cg[4], cb[4];
    float cx, cy, ppu;
};

Ifs make_ifs(const std::string& name) {
    Ifs s{};
    if (name == "sierpinski") {
        s.m = 3;
        const float ox[3] = {0, 0.5f, 0.25f}, oy[3] = {0, 0, -0.5f};
        for (int i = 0; i < 3; ++i) s.a[i] = s.d[i] = 0.5f, s.e[i] = ox[i], s.f[i] = oy[i], s.w[i] = 1;
        s.cx = 0.5f, s.cy = -0.5f, s.ppu = 1000;
    } else if (name == "fern") {
        s.m = 4;
        const float A[4][7] = {{0, 0, 0, 0.16f, 0, 0, 0.01f},
                               {0.85f, -0.04f, 0.04f, 0.85f, 0, -1.6f, 0.85f},
                               {0.20f, 0.26f, -0.23f, 0.22f, 0, -1.6f, 0.07f},
                               {-0.15f, -0.28f, -0.26f, 0.24f, 0, -0.44f, 0.07f}};
        for (int i = 0; i < 4; ++i)
            s.a[i] = A[i][0], s.b[i] = A[i][1], s.c[i] = A[i][2], s.d[i] = A[i][3], s.e[i] = A[i][4],
            s.f[i] = A[i][5], s.w[i] = A[i][6];
        s.cx = 0.24f, s.cy = -5.0f, s.ppu = 97.5f;
    } else {
        std::fprintf(stderr, "unknown map %s\n", name.c_str());
        std::exit(2);
    }
    const float pal[4][3] = {{0.9f, 0.2f, 0.1f}, {0.1f, 0.7f, 0.3f}, {0.2f, 0.3f, 0.9f}, {0.9f, 0.8f, 0.2f}};
    for (int i = 0; i < s.m; ++i) s.cr[i] = pal[i][0], s.cg[i] = pal[i][1], s.cb[i] = pal[i][2];
    return s;
}

/// The 16-byte bins {hits, r, g, b} in 2 MiB pages where the kernel grants them, as fixpoint's
/// worker histograms are (plugins/renderers/chaos-game/histogram.hpp): 16 MiB of bins in 4 KiB
/// pages would make most deposits a TLB miss as well as a cache miss, and measure the pages,
/// not the kernel.
struct Bins {
    static constexpr size_t words = 4 * (size_t(W) * H + 1);
    static constexpr size_t huge = size_t(2) << 20;
    static constexpr size_t bytes = (words * 4 + huge - 1) / huge * huge;
    uint32_t* sums = static_cast<uint32_t*>(std::aligned_alloc(huge, bytes));
    std::vector<uint64_t> wide = std::vector<uint64_t>(words);
    Bins() {
        if (!sums) std::abort();
#ifdef MADV_HUGEPAGE
        ::madvise(sums, bytes, MADV_HUGEPAGE); // advice: without it, 4 KiB pages
#endif
        std::memset(sums, 0, bytes); // touched before the clock starts, as ifs.cpp's histogram
    }
    ~Bins() { std::free(sums); }
    Bins(const Bins&) = delete;
    Bins& operator=(const Bins&) = delete;
    [[gnu::noinline, gnu::cold]] void spill(uint32_t* b) {
        uint64_t* o = wide.data() + (b - sums);
        for (int j = 0; j < 4; ++j) o[j] += b[j], b[j] = 0;
    }
    uint64_t hits(size_t bin) const { return sums[4 * bin] + wide[4 * bin]; }
};

constexpr int U = 64 / L; // 64 orbits in flight whatever the vector width

/// A point's bin: rows of W bins (fixpoint's layout), or with Tiles 2 x 2 blocks of bins, one
/// 64-byte cache line each, in rows of blocks (a layout fixpoint does not have: for the
/// ceiling of a hand-written kernel; DUMP stays the bin past the image either way).
template <bool Tiles>
vi bin_of(vi ix, vi iy) {
    if constexpr (Tiles) return ((iy >> 1) * (W / 2) + (ix >> 1)) * 4 + (iy & 1) * 2 + (ix & 1);
    return iy * W + ix;
}

template <int M, bool Tiles>
void run(const Ifs& s, uint64_t n, uint64_t seed, Bins& bins) {
    Table A, B, C, D, E, F, CR, CG, CB;
    for (int i = 0; i < M; ++i) {
        A.t[i] = s.a[i], B.t[i] = s.b[i], C.t[i] = s.c[i], D.t[i] = s.d[i], E.t[i] = s.e[i], F.t[i] = s.f[i];
        CR.t[i] = s.cr[i], CG.t[i] = s.cg[i], CB.t[i] = s.cb[i];
    }
    float tot = 0, acc = 0;
    for (int i = 0; i < M; ++i) tot += s.w[i];
    int32_t thr[4] = {}; // compared with r >> 1 as signed (2^-31 resolution), as ifs.cpp
    for (int i = 0; i < M - 1; ++i) acc += s.w[i] / tot, thr[i] = int32_t(double(acc) * 2147483648.0);
    const vf sc = splat(s.ppu), ox = splat(W / 2 - s.cx * s.ppu), oy = splat(H / 2 - s.cy * s.ppu);
    const vf fw = splat(float(W)), fh = splat(float(H)), zero = splat(0.f), one = splat(1.f);
    const vf half = splat(0.5f), q = splat(65535.f);
    VRng rng[U];
    vf X[U], Y[U], R[U], G[U], Bc[U];
    for (int u = 0; u < U; ++u) {
        rng[u].seed(splitmix64(seed));
        for (int l = 0; l < L; ++l) {
            X[u][l] = float(splitmix64(seed) >> 40) * 0x1.0p-24f;
            Y[u][l] = -float(splitmix64(seed) >> 40) * 0x1.0p-24f;
        }
        R[u] = G[u] = Bc[u] = splat(0.5f);
    }
    auto step = [&](int u) {
        const vi rs = vi(rng[u].next() >> 1);
        vi k = vi{} + 0;
        for (int j = 0; j < M - 1; ++j) k -= (rs >= thr[j]);
        const vf nx = A.pick(k) * X[u] + (B.pick(k) * Y[u] + E.pick(k));
        const vf ny = D.pick(k) * Y[u] + (C.pick(k) * X[u] + F.pick(k));
        X[u] = nx, Y[u] = ny;
        R[u] = (R[u] + CR.pick(k)) * half, G[u] = (G[u] + CG.pick(k)) * half,
        Bc[u] = (Bc[u] + CB.pick(k)) * half;
    };
    const auto quant = [&](vf c) {
        c = c > zero ? c : zero;
        c = c < one ? c : one;
        return __builtin_convertvector(c * q + half, vi);
    };
    for (int i = 0; i < 32; ++i)
        for (int u = 0; u < U; ++u) step(u);
    alignas(64) int32_t ib[U * L], rb[U * L], gb[U * L], bb[U * L];
    uint32_t* const sums = bins.sums;
    for (uint64_t i = 0, steps = n / (L * U); i < steps; ++i) {
        for (int u = 0; u < U; ++u) {
            step(u);
            const vf fx = X[u] * sc + ox, fy = Y[u] * sc + oy;
            const vi ok = (fx >= zero) & (fx < fw) & (fy >= zero) & (fy < fh);
            const vi ix = __builtin_convertvector(fx, vi), iy = __builtin_convertvector(fy, vi);
            *(vi*)(ib + u * L) = ok ? bin_of<Tiles>(ix, iy) : (vi{} + DUMP);
            *(vi*)(rb + u * L) = quant(R[u]);
            *(vi*)(gb + u * L) = quant(G[u]);
            *(vi*)(bb + u * L) = quant(Bc[u]);
        }
        for (int j = 0; j < U * L; ++j) {
            uint32_t* b = sums + 4 * size_t(ib[j]);
            b[1] += uint32_t(rb[j]), b[2] += uint32_t(gb[j]), b[3] += uint32_t(bb[j]);
            if (__builtin_expect(++b[0] == 65536u, 0)) bins.spill(b);
        }
    }
}

} // namespace

int main(int argc, char** argv) {
    const std::string map = arg(argc, argv, "map", "sierpinski");
    const uint64_t n = uint64_t(std::atof(arg(argc, argv, "n", "1e8").c_str()));
    const int reps = std::atoi(arg(argc, argv, "reps", "5").c_str());
    const std::string layout = arg(argc, argv, "layout", "rows");
    if (layout != "rows" && layout != "tiles") {
        std::fprintf(stderr, "layout=%s: rows or tiles\n", layout.c_str());
        return 2;
    }
    const bool tiles = layout == "tiles";
    const Ifs s = make_ifs(map);
    std::vector<double> times;
    uint64_t inwin = 0;
    for (int r = 0; r < reps; ++r) {
        Bins bins;
        const double t0 = now();
        const uint64_t seed = 1234567ull + 7919ull * r;
        if (s.m == 3)
            tiles ? run<3, true>(s, n, seed, bins) : run<3, false>(s, n, seed, bins);
        else
            tiles ? run<4, true>(s, n, seed, bins) : run<4, false>(s, n, seed, bins);
        times.push_back(now() - t0);
        inwin = 0; // the points in the window (outside the timing)
        for (size_t i = 0; i < size_t(W) * H; ++i) inwin += bins.hits(i);
        std::printf("rep=%d time_s=%.4f rate=%.4g\n", r, times.back(), double(n) / times.back());
    }
    std::sort(times.begin(), times.end());
    const double med = times[times.size() / 2];
    std::printf("SUMMARY kernel=flame-ref case=%s layout=%s lanes=%d n=%llu median_s=%.4f median_rate=%.4g "
                "inwin=%llu\n",
                map.c_str(), layout.c_str(), L, (unsigned long long)n, med, double(n) / med,
                (unsigned long long)inwin);
}
