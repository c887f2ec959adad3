// `fixpoint explore`'s searched parameters (explore.hpp): the dimensions of the search parsed
// from --param and --random, and their genes (drawn, mutated, written as --set values).
#pragma once

#include <fixpoint/host/core/build.hpp>
#include <fixpoint/host/core/config.hpp>
#include <fixpoint/rng.hpp>

#include <array>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace fp::host::explore_detail {

struct Dim {
    /// Pair: a vector parameter of two reals written [a, b] (paper 04's S-iteration alpha and
    /// beta), each component searched on its own.
    enum class Kind { Real, Int, QNum, Pair, Choice } kind = Kind::Real;
    /// The components a gene of this kind has.
    int components() const { return kind == Kind::QNum || kind == Kind::Pair ? 2 : 1; }
    std::string path;
    std::array<double, 2> lo{}, hi{};
    std::vector<std::string> choices;
    bool lo_open = false, hi_open = false;
    int digits = 4; ///< significant digits written for reals
};

using Gene = std::array<double, 2>;

/// The validated tree's parameters and plugin instances by path.
struct Index {
    std::map<std::string, const TParam*> params;
    std::map<std::string, const TObject*> objects;
    void add(const TObject& t) {
        objects[t.path] = &t;
        for (const auto& p : t.params) {
            params[p.path] = &p;
            if (p.object) add(*p.object);
            for (const auto& it : p.items) {
                add(*it.object);
                for (const auto& e : it.extras) params[e.path] = &e;
            }
        }
    }
};

/// The parameter `name` of a validated object, or null.
const TParam* param_of(const TObject& t, const std::string& name);
/// A gene as --set writes it for its dimension.
std::string gene_text(const Dim& d, const Gene& g);
/// A gene drawn within its dimension's range.
Gene draw(const Dim& d, Rng& r);
/// A gene moved a little (a choice drawn anew).
void mutate(const Dim& d, Gene& g, Rng& r);
/// --param PATH=RANGE, checked against the config's tree (`idx`) and the plugin's schema.
Dim parse_param(const Registry& reg, const CNode& base, const Index& idx, const std::string& spec,
                const std::string& config);
/// --random PATH: every ranged parameter of the plugin there not `taken` already.
std::vector<Dim> random_dims(const Index& idx, const std::string& path, const std::string& config,
                             const std::set<std::string>& taken);
/// A number read whole (no trailing text).
bool parse_double(std::string_view t, double& v);

} // namespace fp::host::explore_detail
