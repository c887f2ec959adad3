// The conformance suite.
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/host/conformance/conformance.hpp>
#include <fixpoint/host/core/build.hpp>
#include <fixpoint/host/core/runtime.hpp>

#include "conformance_detail.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <exception>
#include <functional>
#include <limits>
#include <thread>

namespace fp::host {

namespace {

using namespace detail;

bool snake_or_paper(const char* s) {
    if (!s || !*s) return false;
    for (const char* c = s; *c; ++c)
        if (!std::isalnum((unsigned char)*c) && *c != '_') return false;
    return true;
}

// The example (the plugin's own unless `given`) with `type:` added, as a node.
CNode example_node(const PluginDescriptor& d, const std::string* given) {
    CNode n = given ? parse_yaml(*given, "--example")
                    : parse_yaml(d.example ? d.example : "{}", std::string("<example of ") + d.name + ">");
    if (n.type == CNode::Type::Null) n = map_node();
    n.keys.insert(n.keys.begin(), {"type", scalar_node(d.name)});
    n.key_marks.insert(n.key_marks.begin(), n.mark);
    return n;
}

// Expect validation or construction of `n` to be refused with a bad-input error.
void expect_refused(const Registry& reg, const PluginDescriptor& d, const CNode& n, const std::string& what,
                    Findings& f) {
    const std::size_t before = f.size();
    try {
        auto t = validate(reg, d.kind, n, d.name);
        build(reg, *t);
        f.push_back("parameters: " + what + " was accepted");
    } catch (const InputError&) {
        // refused as it should be
    } catch (const std::exception& e) {
        f.push_back("parameters: " + what + " gave a non-parameter error: " + e.what());
    } catch (...) {
        f.push_back("parameters: " + what + " threw " + not_std_exception);
    }
    f.record("parameters: " + what + " is refused", before);
}

void set_param(CNode& n, const std::string& key, CNode v) {
    if (CNode* p = n.find(key))
        *p = std::move(v);
    else {
        n.keys.emplace_back(key, std::move(v));
        n.key_marks.push_back(n.mark);
    }
}

// The kind's checks on an object. Schemes record their checks one by one; the other kinds
// record one check for all of theirs (their findings say which failed).
void check_kind(const Object& obj, Kind kind, Findings& f) {
    const std::size_t before = f.size();
    switch (kind) {
    case Kind::Shape: check_shape(dynamic_cast<const Shape&>(obj), f); break;
    case Kind::Transform: check_transform(dynamic_cast<const Transform&>(obj), f); break;
    case Kind::IterationScheme: detail::check_scheme(dynamic_cast<const IterationScheme&>(obj), f); return;
    case Kind::NumberSystem: check_numbers(dynamic_cast<const NumberSystem&>(obj), f); break;
    case Kind::Trap: check_trap(dynamic_cast<const Trap&>(obj), f); break;
    case Kind::Metric: check_metric(dynamic_cast<const Metric&>(obj), f); break;
    case Kind::Colourer: check_colourer(dynamic_cast<const Colourer&>(obj), f); break;
    case Kind::Renderer: check_renderer(dynamic_cast<const Renderer&>(obj), f); break;
    case Kind::Filter: check_filter(dynamic_cast<const Filter&>(obj), f); break;
    }
    f.record(std::string(kind_name(kind)) + ": the kind's checks", before);
}

// check_kind(), with what the plugin throws reported as a finding.
void checks_of(const Object& obj, Kind kind, Findings& f) {
    try {
        check_kind(obj, kind, f);
    } catch (const std::exception& err) {
        f.check("checks: the plugin does not throw", std::string("checks: the plugin threw: ") + err.what());
    } catch (...) {
        f.check("checks: the plugin does not throw", "checks: the plugin threw " + not_std_exception);
    }
}

// A scheme's behaviour depends on its parameters more than a shape's: besides the example,
// it is checked with a few values drawn from the declared ranges (finite Real and Int
// ranges; sequences, which have no range, as periodic lists of weights in [0, 1]). Each
// draw goes through validate and build like a config; a draw the plugin refuses with a
// bad-input error (values fine alone but not together) is skipped. Findings name the draw.
void check_draws(const Registry& reg, const PluginDescriptor& d, const CNode& ex, Findings& f) {
    Rng rng = chain_stream(20261121, 13);
    // On a grid of a thousandth of the range: short to print, and as good a sample.
    auto draw = [&](double lo, double hi) { return lo + (hi - lo) * uniform_below(rng, 1001) / 1000; };
    constexpr int draws = 3;
    for (int k = 0; k < draws; ++k) {
        CNode n = ex;
        std::string what;
        for (std::uint32_t i = 0; i < d.n_params; ++i) {
            const ParamSpec& s = d.params[i];
            CNode v;
            if ((s.type == ParamType::Real || s.type == ParamType::Int) && std::isfinite(s.lo) &&
                std::isfinite(s.hi)) {
                double x = draw(s.lo, s.hi);
                if (s.type == ParamType::Int)
                    x = std::clamp(std::floor(x + 0.5), std::ceil(s.lo), std::floor(s.hi));
                if ((s.lo_open && x <= s.lo) || (s.hi_open && x >= s.hi)) x = 0.5 * (s.lo + s.hi);
                v = scalar_node(format_real(x));
            } else if (s.type == ParamType::Sequence) {
                // Three values: a list of two reads as one q-number.
                v = seq_node();
                for (int j = 0; j < 3; ++j) v.items.push_back(scalar_node(format_real(draw(0, 1))));
            } else {
                continue;
            }
            what += std::string(what.empty() ? "" : ", ") + s.name + ": " +
                    (v.is_seq()
                         ? "[" + v.items[0].scalar + ", " + v.items[1].scalar + ", " + v.items[2].scalar + "]"
                         : v.scalar);
            set_param(n, s.name, std::move(v));
        }
        if (what.empty()) return; // nothing to draw
        std::shared_ptr<const Object> obj;
        try {
            obj = build(reg, *validate(reg, d.kind, n, d.name));
        } catch (const InputError&) {
            continue; // refused as a whole: not a finding
        } catch (const std::exception& err) {
            f.push_back("build: drawn parameters (" + what + ") gave a non-parameter error: " + err.what());
            continue;
        } catch (...) {
            f.push_back("build: drawn parameters (" + what + ") threw " + not_std_exception);
            continue;
        }
        // A finding the example already gave is not repeated; new ones say the draw.
        Findings g;
        checks_of(*obj, d.kind, g);
        for (auto& c : g.checks) f.checks.push_back({c.name + " (drawn: " + what + ")", c.passed});
        for (auto& m : g.failures)
            if (std::find(f.failures.begin(), f.failures.end(), m) == f.failures.end())
                f.push_back(m + " (with drawn parameters " + what + ")");
    }
}

} // namespace

std::vector<std::string> check_object(const Object& obj, Kind kind) {
    Findings f;
    check_kind(obj, kind, f);
    return f.failures;
}

std::vector<std::string> run_conformance(const Registry& reg, const PluginEntry& e) {
    return conformance_report(reg, e).findings;
}

ConformanceReport conformance_report(const Registry& reg, const PluginEntry& e, const std::string* example) {
    Findings f;
    const PluginDescriptor& d = *e.desc;
    const std::size_t before_meta = f.size();
    if (!d.summary || !*d.summary) f.push_back("metadata: no summary");
    if (!d.version || !*d.version) f.push_back("metadata: no version");
    for (std::uint32_t i = 0; i < d.n_params; ++i) {
        const ParamSpec& s = d.params[i];
        const std::string name = s.name ? s.name : "";
        if (!snake_or_paper(s.name)) f.push_back("metadata: parameter name '" + name + "' is not snake_case");
        if (!s.doc || !*s.doc) f.push_back("metadata: parameter '" + name + "' has no doc line");
        if (s.type == ParamType::Objects)
            for (std::uint32_t j = 0; j < s.n_item_params; ++j)
                if (!s.item_params[j].doc || !*s.item_params[j].doc)
                    f.push_back("metadata: item parameter '" + std::string(s.item_params[j].name) +
                                "' has no doc line");
    }
    f.record("metadata: summary, version, parameter names and docs", before_meta);
    // Builds from its example.
    const std::size_t before_build = f.size();
    CNode ex;
    std::shared_ptr<const Object> obj;
    try {
        ex = example_node(d, example);
        auto t = validate(reg, d.kind, ex, d.name);
        obj = build(reg, *t);
    } catch (const std::exception& err) {
        f.push_back(std::string("build: the example does not build: ") + err.what());
    } catch (...) {
        f.push_back("build: the example does not build: it threw " + not_std_exception);
    }
    f.record("build: the example builds", before_build);
    if (!obj) return {f.failures, f.checks};
    // Bad parameters are refused.
    {
        CNode n = ex;
        set_param(n, "no_such_parameter_zz", scalar_node("1"));
        expect_refused(reg, d, n, "an unknown parameter", f);
    }
    for (std::uint32_t i = 0; i < d.n_params; ++i) {
        const ParamSpec& s = d.params[i];
        const std::string nm = s.name;
        {
            CNode n = ex;
            CNode wrong = s.type == ParamType::Object || s.type == ParamType::String
                              ? map_node()
                              : scalar_node("not-a-value", true);
            if (s.type == ParamType::Object)
                wrong.keys.emplace_back("x", scalar_node("1")), wrong.key_marks.resize(1);
            set_param(n, nm, wrong);
            expect_refused(reg, d, n, "a value of the wrong type for '" + nm + "'", f);
        }
        const bool numeric = s.type == ParamType::Real || s.type == ParamType::Int;
        if (numeric && std::isfinite(s.lo)) {
            CNode n = ex;
            set_param(n, nm, scalar_node(format_real(s.lo_open ? s.lo : s.lo - 1)));
            expect_refused(reg, d, n, "a value below the range of '" + nm + "'", f);
        }
        if (numeric && std::isfinite(s.hi)) {
            CNode n = ex;
            set_param(n, nm, scalar_node(format_real(s.hi_open ? s.hi : s.hi + 1)));
            expect_refused(reg, d, n, "a value above the range of '" + nm + "'", f);
        }
        if ((numeric || s.type == ParamType::Sequence) && !s.allow_nonfinite) {
            CNode n = ex;
            set_param(n, nm, scalar_node(".nan"));
            expect_refused(reg, d, n, "NaN for '" + nm + "'", f);
        }
        if ((s.type == ParamType::Vec2 || s.type == ParamType::Reals) && !s.allow_nonfinite) {
            CNode n = ex;
            CNode v = seq_node();
            const std::size_t len =
                s.type == ParamType::Vec2 ? 2 : std::max<std::size_t>({1, s.count, s.min_count});
            for (std::size_t k = 0; k < len; ++k) v.items.push_back(scalar_node(".nan"));
            set_param(n, nm, v);
            expect_refused(reg, d, n, "NaN in '" + nm + "'", f);
        }
    }
    checks_of(*obj, d.kind, f);
    if (d.kind == Kind::IterationScheme) check_draws(reg, d, ex, f);
    return {f.failures, f.checks};
}

} // namespace fp::host
