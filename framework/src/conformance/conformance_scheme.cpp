// The conformance checks of an iteration scheme.
//
// Schemes are the plugins researchers write most, and their usual mistakes do not show in
// one double step at n = 0: a float path nobody ran, a coefficient wrong only at large n (an
// index squeezed through a float), a per-step cache in a mutable member that threads
// overwrite, state kept between calls, NaN from a square root. So every check runs on both
// precisions, at many step indices, on two maps (a contraction, and a reflection: an
// involution, which some schemes treat apart), and a finding names the step, the precision,
// the map and, where there is one, the point.
#include <fixpoint/host/core/build.hpp>

#include "conformance_detail.hpp"

#include <array>
#include <atomic>
#include <charconv>
#include <chrono>
#include <exception>
#include <functional>
#include <limits>
#include <mutex>
#include <thread>
#include <type_traits>

namespace fp::host::detail {

namespace {

// The test maps, written here so that the checks depend on no other plugin.
class TestAffine final : public TransformBase<TestAffine> {
public:
    template <class T>
    void map_pt(T& x, T& y) const {
        const T nx = T(0.5) * x - T(0.3) * y + T(0.1);
        const T ny = T(0.3) * x + T(0.5) * y - T(0.2);
        x = nx;
        y = ny;
    }
};

// The point reflection through (0.2, -0.1): an involution (Schu takes another path on those).
// Not an inversion in a circle: chains of T inside one step of a scheme would come near its
// centre, where float and double rightly part.
class TestReflection final : public TransformBase<TestReflection> {
public:
    template <class T>
    void map_pt(T& x, T& y) const {
        x = T(0.4) - x;
        y = T(-0.2) - y;
    }
    bool is_involution() const override { return true; }
};

constexpr std::size_t n_points = 300; // a full chunk (fp::chunk_size) and a partial one

// 0..31 (every short period of a periodic sequence, Schu's compositions), and indices where an
// index carried in a narrower type goes wrong: past 2^16, 2^24 + 1 (the first integer a float
// cannot hold), past 2^32.
const std::vector<std::uint64_t>& step_indices() {
    static const std::vector<std::uint64_t> v = [] {
        std::vector<std::uint64_t> s;
        for (std::uint64_t n = 0; n < 32; ++n) s.push_back(n);
        for (std::uint64_t n : {1000ull, 65537ull, 16777217ull, (1ull << 32) + 5}) s.push_back(n);
        return s;
    }();
    return v;
}

template <class T>
const char* precision() {
    return sizeof(T) == 4 ? "float" : "double";
}

// Shortest round-trip text of a value in its own precision.
template <class T>
std::string num(T v) {
    if (std::isnan(v)) return "nan";
    char buf[64];
    auto [p, ec] = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, p);
}
template <class T>
std::string point(T x, T y) {
    return "(" + num(x) + ", " + num(y) + ")";
}

// One precision on one map: the points (in [-1, 1]^2, as [x..., y...]), the step indices the
// scheme accepts on that map, and the reference: one batch step from the points at each index,
// computed serially in ascending order.
template <class T>
struct Lane {
    const Transform* t;
    const char* map;
    std::vector<std::uint64_t> steps;
    std::vector<T> start;
    std::vector<std::vector<T>> ref;

    std::string at(std::size_t i) const {
        return "at step n = " + std::to_string(steps[i]) + " (" + precision<T>() + ", on the test " + map +
               ")";
    }
};

template <class T>
void step_in_place(const IterationScheme& s, const Transform& t, std::vector<T>& v, std::uint64_t n,
                   Mask m = nullptr) {
    const std::size_t k = v.size() / 2;
    s.step(t, Points<T>{v.data(), v.data() + k, k}, m, n);
}
template <class T>
std::vector<T> step_from(const IterationScheme& s, const Lane<T>& l, std::size_t i, Mask m = nullptr) {
    std::vector<T> v = l.start;
    step_in_place(s, *l.t, v, l.steps[i], m);
    return v;
}

constexpr std::size_t none = std::numeric_limits<std::size_t>::max();

// The first point (index into [x..., y...] mod n) where a and b differ; none when equal.
template <class T>
std::size_t first_difference(const std::vector<T>& a, const std::vector<T>& b) {
    for (std::size_t i = 0; i < a.size(); ++i)
        if (!same_bits(a[i], b[i])) return i % (a.size() / 2);
    return none;
}

// ---- the checks; each returns its finding, or "" when it passed

// Finite input in [-1, 1]^2 on these two maps: every output finite.
template <class T>
std::string nonfinite(const IterationScheme&, const Lane<T>& l) {
    const std::size_t n = n_points;
    for (std::size_t i = 0; i < l.steps.size(); ++i)
        for (std::size_t j = 0; j < n; ++j)
            if (!std::isfinite(l.ref[i][j]) || !std::isfinite(l.ref[i][n + j]))
                return "iteration-scheme: step() gives a non-finite result for finite input " + l.at(i) +
                       ": " + point(l.start[j], l.start[n + j]) + " -> " +
                       point(l.ref[i][j], l.ref[i][n + j]);
    return "";
}

// step() is const, and a render calls it on batches of any size, at steps in any order
// (chains restart; threads share the object): a result may depend only on the points, the map
// and n. After the references (ascending n) and a short chain (which feeds the scheme other
// points), the steps again in descending order must give the same bits.
template <class T>
std::string history(const IterationScheme& s, const Lane<T>& l) {
    std::vector<T> p = l.start;
    for (std::uint64_t n = 0; n < 8; ++n) step_in_place(s, *l.t, p, n);
    for (std::size_t i = l.steps.size(); i-- > 0;)
        if (first_difference(step_from(s, l, i), l.ref[i]) != none)
            return "iteration-scheme: step() depends on earlier calls: the same points gave another result " +
                   l.at(i) + " after other steps had run (keep no state between calls)";
    return "";
}

template <class T>
std::string pointwise(const IterationScheme& s, const Lane<T>& l) {
    const std::size_t n = n_points;
    for (std::size_t i = 0; i < l.steps.size(); ++i)
        for (std::size_t j = 0; j < n; ++j) {
            T x = l.start[j], y = l.start[n + j];
            s.step(*l.t, Points<T>{&x, &y, 1}, nullptr, l.steps[i]);
            if (!same_bits(x, l.ref[i][j]) || !same_bits(y, l.ref[i][n + j]))
                return "iteration-scheme: step() on a batch differs from point-by-point " + l.at(i) +
                       ", first for the point " + point(l.start[j], l.start[n + j]);
        }
    return "";
}

// A mask byte of 0 leaves the point exactly as it was; any other byte (not only 1) makes it
// active, with the result it gets without a mask (batch.hpp). Two patterns, each with
// inactive points inside and at the ends of chunks.
template <class T>
std::string masked(const IterationScheme& s, const Lane<T>& l) {
    const std::size_t n = n_points;
    std::vector<unsigned char> m[2] = {std::vector<unsigned char>(n), std::vector<unsigned char>(n)};
    for (std::size_t j = 0; j < n; ++j) {
        m[0][j] = j % 3 == 0 ? 0 : (j % 2 ? 1 : 0xff);
        m[1][j] = j % 3 == 0 ? 7 : 0;
    }
    for (std::size_t i = 0; i < l.steps.size(); ++i)
        for (const auto& mask : m) {
            const std::vector<T> r = step_from(s, l, i, mask.data());
            for (std::size_t j = 0; j < n; ++j) {
                const std::vector<T>& want = mask[j] ? l.ref[i] : l.start;
                if (same_bits(r[j], want[j]) && same_bits(r[n + j], want[n + j])) continue;
                return std::string("iteration-scheme: with a mask, step() ") +
                       (mask[j] ? "gives an active point another result than without a mask "
                                : "changes a masked-out point ") +
                       l.at(i) + ", first the point " + point(l.start[j], l.start[n + j]);
            }
        }
    return "";
}

// The lane's points with an infinity (the first point's x) and a NaN (the second's y): the
// promises of is_picard() and program() hold for special values too.
template <class T>
std::vector<T> with_special_values(const Lane<T>& l) {
    std::vector<T> p = l.start;
    p[0] = std::numeric_limits<T>::infinity();
    p[n_points + 1] = std::numeric_limits<T>::quiet_NaN();
    return p;
}

// The promise renderers rely on (iteration.hpp): step() is exactly T(p), special values too.
template <class T>
std::string picard(const IterationScheme& s, const Lane<T>& l) {
    const std::size_t n = n_points;
    const std::vector<T> p = with_special_values(l);
    std::vector<T> want = p;
    l.t->apply(Points<T>{want.data(), want.data() + n, n}, nullptr);
    for (std::size_t i = 0; i < l.steps.size(); ++i) {
        std::vector<T> r = p;
        step_in_place(s, *l.t, r, l.steps[i]);
        if (const std::size_t j = first_difference(r, want); j != none)
            return "iteration-scheme: is_picard() is true, but step() is not exactly T(p) " + l.at(i) +
                   ", first for the point " + point(p[j], p[n + j]);
    }
    return "";
}

// The promise of program() (iteration.hpp): where a scheme gives a program for a step, the
// program computes step() there, bit for bit, special values too. A SchemeBase kernel that
// reads or writes the points itself, outside c.t, c.copy and c.lin, fails it: its recorded
// program lacks those operations.
template <class T>
std::string program_matches(const IterationScheme& s, const Lane<T>& l) {
    const std::size_t n = n_points;
    const std::vector<T> p = with_special_values(l);
    SchemeProgram prog;
    for (std::size_t i = 0; i < l.steps.size(); ++i) {
        if (!s.program(*l.t, l.steps[i], sizeof(T) == 8, prog)) continue;
        std::vector<T> want = p, got = p;
        step_in_place(s, *l.t, want, l.steps[i]);
        run_program(prog, *l.t, Points<T>{got.data(), got.data() + n, n});
        if (const std::size_t j = first_difference(got, want); j != none)
            return "iteration-scheme: program() does not compute step() " + l.at(i) + ": for the point " +
                   point(p[j], p[n + j]) + " its instructions give " + point(got[j], got[n + j]) +
                   ", step() " + point(want[j], want[n + j]) +
                   " (a kernel that reads or writes the points itself overrides program() to return false)";
    }
    return "";
}

struct MapLanes {
    Lane<double> d;
    Lane<float> f;
};

// The float path computes what the double path does, in float: each output within 1e-3 of
// the double one, relative to its size (a step of a contraction loses far less). Non-finite
// outputs are the finiteness check's.
std::string float_vs_double(const MapLanes& m) {
    const std::size_t n = n_points;
    for (std::size_t i = 0; i < m.d.steps.size(); ++i)
        for (std::size_t j = 0; j < n; ++j) {
            const double dx = m.d.ref[i][j], dy = m.d.ref[i][n + j];
            const float fx = m.f.ref[i][j], fy = m.f.ref[i][n + j];
            if (!std::isfinite(dx) || !std::isfinite(dy) || !std::isfinite(fx) || !std::isfinite(fy))
                continue;
            if (std::fabs(fx - dx) <= 1e-3 * (1 + std::fabs(dx)) &&
                std::fabs(fy - dy) <= 1e-3 * (1 + std::fabs(dy)))
                continue;
            return "iteration-scheme: the float path differs from double at step n = " +
                   std::to_string(m.d.steps[i]) + " (on the test " + m.d.map + "): the point " +
                   point(m.d.start[j], m.d.start[n + j]) + " goes to " + point(fx, fy) + " in float, " +
                   point(dx, dy) + " in double";
        }
    return "";
}

constexpr unsigned stress_threads = 6;
constexpr std::size_t stress_len = 4; // points per batch in the stress

// Several threads step the one object at once, each through every (map, precision, n) in
// its own rotated order, round after round, and compare each result with a serial one. Two
// threads at the same n (the old check) never showed a per-step cache in a mutable member:
// both wrote the same values. Here one thread overwrites such a cache with another n's values
// while another reads it. The batches are small (a few points), so that calls, and with them
// the moments such a cache changes, come often. Bounded in rounds and in time (150 ms).
std::string threads(const IterationScheme& s, const std::vector<MapLanes>& maps) {
    struct Job {
        std::function<bool()> same; // step a small batch once, compare with the serial result
        std::string at;
    };
    std::vector<Job> jobs;
    auto add = [&](const auto& l) {
        using T = typename std::decay_t<decltype(l.start)>::value_type;
        for (std::size_t i = 0; i < l.steps.size(); ++i)
            for (std::size_t o : {std::size_t(0), n_points / 2, n_points - stress_len}) {
                std::array<T, 2 * stress_len> start, want;
                for (std::size_t j = 0; j < stress_len; ++j)
                    start[j] = l.start[o + j], start[stress_len + j] = l.start[n_points + o + j];
                want = start;
                s.step(*l.t, Points<T>{want.data(), want.data() + stress_len, stress_len}, nullptr,
                       l.steps[i]);
                auto same = [&s, &l, i, start, want] {
                    std::array<T, 2 * stress_len> p = start;
                    s.step(*l.t, Points<T>{p.data(), p.data() + stress_len, stress_len}, nullptr, l.steps[i]);
                    for (std::size_t j = 0; j < 2 * stress_len; ++j)
                        if (!same_bits(p[j], want[j])) return false;
                    return true;
                };
                jobs.push_back({same, l.at(i)});
            }
    };
    for (const auto& m : maps) add(m.d), add(m.f);
    constexpr int rounds = 1500;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(150);
    std::atomic<bool> stop{false};
    std::atomic<unsigned> ready{0};
    std::mutex mu;
    std::string found;
    std::exception_ptr error;
    auto work = [&](unsigned k) {
        // All start together, each at its own place in the list (odd threads walk it backwards).
        ready.fetch_add(1);
        while (ready.load() < stress_threads) std::this_thread::yield();
        const std::size_t J = jobs.size(), offset = k * J / stress_threads;
        try {
            for (int r = 0; r < rounds && !stop.load(std::memory_order_relaxed); ++r) {
                for (std::size_t j = 0; j < J && !stop.load(std::memory_order_relaxed); ++j) {
                    const std::size_t q = (k % 2 ? J - 1 - j : j) + offset;
                    const Job& job = jobs[q % J];
                    if (!job.same()) {
                        std::lock_guard<std::mutex> lock(mu);
                        if (found.empty()) found = job.at;
                        stop = true;
                    }
                    if (j % 16 == 15 && std::chrono::steady_clock::now() > deadline) stop = true;
                }
            }
        } catch (...) {
            // An exception escaping a std::thread ends the process: carry it out instead.
            std::lock_guard<std::mutex> lock(mu);
            if (!error) error = std::current_exception();
            stop = true;
        }
    };
    std::vector<std::thread> pool;
    for (unsigned k = 0; k < stress_threads; ++k) pool.emplace_back(work, k);
    for (auto& t : pool) t.join();
    if (error) std::rethrow_exception(error);
    if (found.empty()) return "";
    return "iteration-scheme: results differ when " + std::to_string(stress_threads) +
           " threads step at once: a thread got another result than the serial one " + found +
           " (state shared between calls without synchronisation, such as a per-step cache in a mutable "
           "member?)";
}

// The steps of step_indices() the scheme accepts on map t: Schu refuses, in check_steps(),
// steps that compose a map that is not an involution too often; a render would refuse them.
std::vector<std::uint64_t> accepted_steps(const IterationScheme& s, const Transform& t) {
    std::vector<std::uint64_t> v;
    for (std::uint64_t n : step_indices()) {
        try {
            s.check_steps(t, n);
        } catch (const InputError&) {
            continue;
        }
        v.push_back(n);
    }
    return v;
}

template <class T>
Lane<T> make_lane(const IterationScheme& s, const Transform& t, const char* map,
                  const std::vector<std::uint64_t>& steps, const std::vector<double>& start) {
    Lane<T> l{&t, map, steps, std::vector<T>(start.begin(), start.end()), {}};
    for (std::size_t i = 0; i < steps.size(); ++i) l.ref.push_back(step_from(s, l, i));
    return l;
}

} // namespace

void check_scheme(const IterationScheme& s, Findings& f) {
    Sampler smp;
    std::vector<double> start(2 * n_points);
    for (double& v : start) v = smp.in(-1, 1);
    static const TestAffine affine;
    static const TestReflection reflection;
    std::vector<MapLanes> maps;
    for (const auto& [t, name] : {std::pair<const Transform*, const char*>{&affine, "contraction"},
                                  std::pair<const Transform*, const char*>{&reflection, "reflection"}}) {
        const auto steps = accepted_steps(s, *t);
        maps.push_back(
            {make_lane<double>(s, *t, name, steps, start), make_lane<float>(s, *t, name, steps, start)});
    }
    // A check over every lane: the first finding (double before float, map by map).
    auto each = [&](auto check) {
        for (const auto& m : maps) {
            if (auto r = check(s, m.d); !r.empty()) return r;
            if (auto r = check(s, m.f); !r.empty()) return r;
        }
        return std::string();
    };
    f.check("iteration-scheme: finite output for finite input",
            each([](auto& sc, auto& l) { return nonfinite(sc, l); }));
    const std::string state = each([](auto& sc, auto& l) { return history(sc, l); });
    f.check("iteration-scheme: no state kept between calls", state);
    if (!state.empty()) return; // every later check would fail for this reason alone
    f.check("iteration-scheme: a batch equals point-by-point, bit for bit",
            each([](auto& sc, auto& l) { return pointwise(sc, l); }));
    f.check("iteration-scheme: masked-out points stay, active ones get the unmasked result",
            each([](auto& sc, auto& l) { return masked(sc, l); }));
    std::string fd;
    for (const auto& m : maps)
        if (fd.empty()) fd = float_vs_double(m);
    f.check("iteration-scheme: the float path agrees with the double path", fd);
    if (SchemeProgram prog; s.program(affine, 0, true, prog) || s.program(reflection, 0, true, prog))
        f.check("iteration-scheme: program(): its instructions compute step(), bit for bit",
                each([](auto& sc, auto& l) { return program_matches(sc, l); }));
    if (s.is_picard())
        f.check("iteration-scheme: is_picard(): step() is exactly T(p)",
                each([](auto& sc, auto& l) { return picard(sc, l); }));
    f.check("iteration-scheme: the same results when " + std::to_string(stress_threads) +
                " threads step at once",
            threads(s, maps));
}

} // namespace fp::host::detail
