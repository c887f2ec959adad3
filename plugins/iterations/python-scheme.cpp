// python-scheme: an iteration scheme written in Python, for prototyping a scheme before
// writing it in C++ (docs/python.md). The file (or the inline `code`) defines
//
//     def step(T, x, y, n):      # x, y: numpy arrays of the batch, n: the step index
//         tx, ty = T(x, y)       # T: the map, applied to whole arrays
//         return 0.5 * x + 0.5 * tx, 0.5 * y + 0.5 * ty
//
// and optionally `applications = 2` (applications of T per step) and `picard = True` (the
// promise that step is exactly T, checked by the conformance suite). `args` in the code's
// namespace holds the item's `args` as a tuple of floats.
//
// As SchemeBase (fixpoint/scheme.hpp) has it, a scheme may compute in any number system
// (`numbers`) with named coefficients, sequences over n in the papers' names (alpha, beta,
// gamma, a, b). A step that takes a fifth argument gets them as k: each coefficient's value at
// step n as its 2x2 multiplier matrix, and `lin(A, u, B, v[, C, w])` forms A u + B v (+ C w) in
// SchemeBase's order and the points' precision, so that the C++ scheme's bits come out:
//
//     def step(T, x, y, n, k):   # the Mann iteration, in any number system
//         return lin(I - k["alpha"], (x, y), k["alpha"], T(x, y))
//
// `file` is relative to the config that names it (the host resolves files, ParamRole::file).
// Python runs one batch at a time (its global lock), so a render takes one thread unless
// asked for more (ability::one_batch_at_a_time).
//
// This plugin does not link Python: a plugin folder is loaded by every command, and one that
// needs libpython would make every command load it (or fail where it is missing). The
// Python side lives in a library beside the plugins (python-scheme-bridge.so), loaded when
// a python-scheme is first built; in the fixpoint CLI that first loads libpython itself,
// while inside a Python process the bridge uses the running interpreter.
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/scheme.hpp> // numbers_param (its loops are compiled in, unused)

#include <dlfcn.h>

#include <filesystem>
#include <memory>
#include <mutex>
#include <string>

#ifndef FIXPOINT_LIBPYTHON
#define FIXPOINT_LIBPYTHON "libpython3.so"
#endif

namespace {

/// The bridge's entry point: builds the scheme or throws fp::ParamError.
using MakeScheme = void (*)(const fp::ParamBag&, std::shared_ptr<const fp::IterationScheme>&);

void where_am_i() {}

/// The bridge's entry point, loading the bridge (and libpython) the first time.
MakeScheme bridge() {
    static std::once_flag once;
    static MakeScheme make = nullptr;
    static std::string error;
    std::call_once(once, [] {
        // Python is in the process already when fixpoint runs inside it (the Python module):
        // its symbols are then global. Otherwise libpython is loaded with its symbols global,
        // as an interpreter executable would provide them, for the bridge and for the
        // extension modules (numpy) that Python imports.
        if (!dlsym(RTLD_DEFAULT, "Py_IsInitialized") && !dlopen(FIXPOINT_LIBPYTHON, RTLD_NOW | RTLD_GLOBAL)) {
            const char* e = dlerror();
            error = std::string("Python is not available: ") + (e ? e : FIXPOINT_LIBPYTHON);
            return;
        }
        Dl_info info{};
        if (!dladdr(reinterpret_cast<void*>(&where_am_i), &info) || !info.dli_fname) {
            error = "cannot find the python-scheme plugin's own file";
            return;
        }
        const auto file =
            std::filesystem::path(info.dli_fname).parent_path().parent_path() / "python-scheme-bridge.so";
        void* lib = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!lib) {
            const char* e = dlerror();
            error = "cannot load " + file.string() + ": " + (e ? e : "unknown error");
            return;
        }
        make = reinterpret_cast<MakeScheme>(dlsym(lib, "fixpoint_make_python_scheme"));
        if (!make) error = file.string() + " has no fixpoint_make_python_scheme";
    });
    if (!make) throw fp::ParamError("python-scheme: " + error);
    return make;
}

/// The scheme the bridge built, behind the plugin's own class (whose vtable this plugin
/// holds): one virtual call per batch.
class PythonScheme final : public fp::IterationScheme {
public:
    explicit PythonScheme(const fp::ParamBag& p) { bridge()(p, impl_); }

    void step(const fp::Transform& t, fp::Points<float> p, fp::Mask m, std::uint64_t n) const override {
        impl_->step(t, p, m, n);
    }
    void step(const fp::Transform& t, fp::Points<double> p, fp::Mask m, std::uint64_t n) const override {
        impl_->step(t, p, m, n);
    }
    unsigned applications() const override { return impl_->applications(); }
    bool is_picard() const override { return impl_->is_picard(); }

private:
    std::shared_ptr<const fp::IterationScheme> impl_;
};

constexpr fp::ParamSpec params[] = {
    fp::scheme::numbers_param,
    fp::param::string("file", "the Python file that defines step(T, x, y, n) (relative to the config)")
        .opt()
        .reads_file(),
    fp::param::string("code",
                      "the Python code itself, instead of a file (recipes then hold the whole scheme)")
        .opt(),
    fp::param::reals("args", "numbers the code reads as the tuple `args`").def("[]"),
    // The coefficients' names: those of paper 02's schemes (SchemeBase's plugins use no others).
    fp::param::sequence("alpha", "alpha_n, a coefficient: step(T, x, y, n, k) reads its matrix k['alpha']")
        .opt(),
    fp::param::sequence("beta", "beta_n, a coefficient: k['beta']").opt(),
    fp::param::sequence("gamma", "gamma_n, a coefficient: k['gamma']").opt(),
    fp::param::sequence("a", "a_n, a coefficient: k['a']").opt(),
    fp::param::sequence("b", "b_n, a coefficient: k['b']").opt(),
};

} // namespace

FIXPOINT_PLUGIN(fp::describe<PythonScheme>(
                    fp::Kind::IterationScheme, "python-scheme",
                    "an iteration scheme written in Python: step(T, x, y, n) on numpy arrays", params)
                    .with_example("{code: \"a = args[0]\\ndef step(T, x, y, n):\\n    tx, ty = T(x, y)\\n"
                                  "    return (1 - a) * x + a * tx, (1 - a) * y + a * ty\\n\", args: [0.5]}")
                    .with_runs_code()
                    .with_abilities(fp::ability::one_batch_at_a_time))
