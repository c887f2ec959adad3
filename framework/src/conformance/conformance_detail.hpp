// What the conformance suite's files share (conformance.cpp: the suite and the other kinds;
// conformance_scheme.cpp: iteration schemes).
#pragma once

#include <fixpoint/fixpoint.hpp>
#include <fixpoint/host/conformance/conformance.hpp>

#include <cmath>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

namespace fp::host::detail {

/// The failures found so far, and the list of checks run (for `conformance --verbose`).
struct Findings {
    std::vector<std::string> failures;
    std::vector<CheckResult> checks;

    void push_back(std::string s) { failures.push_back(std::move(s)); }
    std::size_t size() const { return failures.size(); }
    /// Records check `name`: it passed when it added no failure since `before` (= size()).
    void record(std::string name, std::size_t before) {
        checks.push_back({std::move(name), failures.size() == before});
    }
    /// Records check `name` with its finding ("" when it passed).
    void check(std::string name, std::string finding) {
        checks.push_back({std::move(name), finding.empty()});
        if (!finding.empty()) failures.push_back(std::move(finding));
    }
};

/// Deterministic sample points.
struct Sampler {
    Rng rng = chain_stream(20261121, 7);
    double in(double a, double b) { return a + (b - a) * uniform_double(rng); }
};

/// Equal to the bit, except that any NaN equals any NaN (a NaN's payload is not a result).
template <class T>
bool same_bits(T a, T b) {
    return std::memcmp(&a, &b, sizeof(T)) == 0 || (std::isnan(a) && std::isnan(b));
}

void check_scheme(const IterationScheme& s, Findings& f);

} // namespace fp::host::detail
