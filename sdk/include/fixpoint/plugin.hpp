// What every plugin binary exports: an ABI integer and a descriptor.
//
// A plugin is one .cpp that defines its class, its parameter schema and ends with
//
//   FIXPOINT_PLUGIN(fp::describe<Circle>(fp::Kind::Shape, "circle", "summary", params))
//
// The descriptor is constant-initialised plain data: loading a plugin runs no code of it
// before the host has checked the ABI integer.
#pragma once

#include <fixpoint/object.hpp>
#include <fixpoint/params.hpp>
#include <fixpoint/types.hpp>
#include <fixpoint/version.hpp>

#include <boost/dll/alias.hpp>

#include <cstddef>
#include <cstdint>

namespace fp {

/// Raised whenever the layout of the interfaces, the descriptor or the parameter bag changes,
/// and whenever the SDK's public headers do (ABI 6: fixpoint/scheme.hpp, the schemes' helper;
/// ABI 7: Colourer::pixel_rule and Histogram::last, paper 02's eq. (28) as written; ABI 8:
/// Transform::periods, for seamless tiles; ABI 9: Renderer::region, for the preview's pan
/// and zoom where the region is fitted; ABI 10: RenderContext::rank, ranks and combine, for
/// renders over Open MPI ranks; ABI 11: RenderContext::memory_budget, Renderer::memory_within,
/// streams_rows and render_rows, RowSink,
/// Colourer::resolve_rows and HistogramSummary, for renders in strips; ABI 12:
/// RenderContext::checkpointing, checkpoint_due, write_checkpoint and resume_from, CheckpointSink and
/// CheckpointSource, Renderer::keeps_checkpoints, for checkpoints; ABI 13:
/// IterationScheme::program and SchemeProgram, for the chaos game's fused step with any
/// scheme; ABI 14: Histogram::hits, size and hits_at, Colourer::reads_hits_only, histograms of
/// hit counts alone; ABI 15: PluginDescriptor::runs_code, so that the host refuses code from
/// a recipe read from an image; ABI 16: ParamSpec::role and builtins, PluginDescriptor::abilities,
/// so that the host asks what a plugin can do instead of testing its name; ABI 17: Kind::Filter
/// and fp::Filter, Colourer::finishes, linear and display, the finishing stage (finish.hpp);
/// ABI 18: ParamRole::finish, RenderContext::keeps_histogram and keep_histogram,
/// Renderer::histogram_shape and finish_histogram, for kept histograms and `fixpoint tone`;
/// ColourState::index, map_index and map_speed, Colourer::palette_index, fixpoint/palette.hpp,
/// for flam3's palettes):
/// ABI 19: fp::Points::key and salt, Transform::uses_random, fixpoint/rng.hpp's map_key and
/// map_uniform, for maps that draw random numbers (flam3's variations); FIXPOINT_PLUGIN_FAMILY,
/// for a library of many plugins built from one table; ABI 20: HistogramSummary::density, for
/// flam3's tone; ABI 21: RenderContext::shard, Histogram::last_order and LastOrder, for shards
/// that `fixpoint merge` sums;
/// the host refuses a plugin built for another value ("rebuild it against this SDK"), so a
/// plugin always matches the headers the host was built with.
constexpr std::uint32_t abi_version = 21;

/// What a plugin can do that the host asks of its descriptor, as bits of
/// PluginDescriptor::abilities: data, so that a new ability adds a bit here rather than a
/// virtual function to an interface (and to every plugin of it).
namespace ability {
/// A renderer whose `maps` (transforms, each with a `weight`) are drawn by weight at each step
/// and applied through its `iteration` scheme from its `start` or its `view`: a chaos game.
/// `fixpoint explore` measures the Lyapunov exponent of such maps.
constexpr std::uint32_t weighted_maps = 1u << 0;
/// Its batches run one at a time, whatever the threads (python-scheme: Python's global lock), so
/// more threads only wait for each other: a render takes one thread unless asked for more.
constexpr std::uint32_t one_batch_at_a_time = 1u << 1;
} // namespace ability

struct PluginDescriptor {
    std::uint32_t abi = abi_version;
    const char* name = nullptr; ///< kebab-case, unique
    Kind kind = Kind::Shape;
    const char* version = "1.0.0";
    const char* summary = nullptr; ///< one line
    const ParamSpec* params = nullptr;
    std::uint32_t n_params = 0;
    /// A YAML flow mapping of parameters that builds a valid instance; the conformance suite
    /// builds from it (defaults fill the rest). "{}" when the defaults suffice.
    const char* example = "{}";
    Object* (*create)(const ParamBag&) = nullptr;
    /// Building an instance runs code its parameters carry (python-scheme's Python). The host
    /// refuses such a plugin in a recipe read from an image (a file from anywhere) unless the
    /// user allows it (--allow-python), as it refuses it in serve's configs.
    bool runs_code = false;
    /// Bits of fp::ability.
    std::uint32_t abilities = 0;

    constexpr PluginDescriptor with_abilities(std::uint32_t bits) const {
        auto d = *this;
        d.abilities |= bits;
        return d;
    }
    constexpr PluginDescriptor with_runs_code() const {
        auto d = *this;
        d.runs_code = true;
        return d;
    }
    constexpr PluginDescriptor with_version(const char* v) const {
        auto d = *this;
        d.version = v;
        return d;
    }
    constexpr PluginDescriptor with_example(const char* e) const {
        auto d = *this;
        d.example = e;
        return d;
    }
};

/// The plugins of a family library (FIXPOINT_PLUGIN_FAMILY): n descriptors from one table.
struct PluginFamily {
    const PluginDescriptor* descriptors = nullptr;
    std::uint32_t n = 0;
};

template <class C>
Object* create_plugin(const ParamBag& p) {
    return new C(p);
}

template <class C, std::size_t N>
constexpr PluginDescriptor describe(Kind kind, const char* name, const char* summary,
                                    const ParamSpec (&params)[N]) {
    PluginDescriptor d;
    d.name = name;
    d.kind = kind;
    d.summary = summary;
    d.params = params;
    d.n_params = std::uint32_t(N);
    d.create = &create_plugin<C>;
    return d;
}

/// For plugins without parameters.
template <class C>
constexpr PluginDescriptor describe(Kind kind, const char* name, const char* summary) {
    PluginDescriptor d;
    d.name = name;
    d.kind = kind;
    d.summary = summary;
    d.create = &create_plugin<C>;
    return d;
}

} // namespace fp

#define FIXPOINT_PLUGIN(...)                                                                                 \
    namespace {                                                                                              \
    constexpr ::fp::PluginDescriptor fixpoint_plugin_descriptor_ = __VA_ARGS__;                              \
    constexpr std::uint32_t fixpoint_plugin_abi_ = ::fp::abi_version;                                        \
    }                                                                                                        \
    BOOST_DLL_ALIAS(fixpoint_plugin_abi_, fixpoint_abi)                                                      \
    BOOST_DLL_ALIAS(fixpoint_plugin_descriptor_, fixpoint_descriptor)

/// A library of many plugins that share their code (flam3's variations: one table, one plugin
/// per variation). `array` is a constexpr array of fp::PluginDescriptor; the host loads each
/// as it loads a plugin of its own file, and refuses the library if any one is malformed.
#define FIXPOINT_PLUGIN_FAMILY(array)                                                                        \
    namespace {                                                                                              \
    constexpr ::fp::PluginFamily fixpoint_plugin_family_{(array).data(), std::uint32_t((array).size())};     \
    constexpr std::uint32_t fixpoint_plugin_abi_ = ::fp::abi_version;                                        \
    }                                                                                                        \
    BOOST_DLL_ALIAS(fixpoint_plugin_abi_, fixpoint_abi)                                                      \
    BOOST_DLL_ALIAS(fixpoint_plugin_family_, fixpoint_family)
