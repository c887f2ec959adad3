// The Python side of the python-scheme plugin (plugins/iterations/python-scheme.cpp): runs a
// scheme's step(T, x, y, n) on whole batches as numpy arrays.
//
// Built like an extension module: it names Python's symbols without linking libpython, and
// takes them from the process (the python executable, or the libpython the plugin loaded
// with global symbols). Every call into Python holds the GIL; render threads take it once
// per batch, so Python schemes are serialised, and deterministic like every scheme: a
// step's result depends on its batch alone.
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/scheme.hpp> // read_coefficient, numbers_param

#include <pybind11/eval.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

namespace py = pybind11;

namespace {

#ifndef FIXPOINT_PYTHON_EXECUTABLE
#define FIXPOINT_PYTHON_EXECUTABLE "/usr/bin/python3"
#endif

// Ctrl-C and SIGTERM reach both the CLI and the Python code: the CLI's handler sets its flag
// (the render stops), and Python's makes the running code raise KeyboardInterrupt at its next
// bytecode, so that a scheme looping at load (or in a step) stops too. Each handler is called
// from this one, which is set over both.
struct sigaction g_host_handler[2], g_python_handler[2];

extern "C" void on_signal(int sig) {
    const int i = sig == SIGINT ? 0 : 1;
    for (const struct sigaction* a : {&g_host_handler[i], &g_python_handler[i]})
        if (!(a->sa_flags & SA_SIGINFO) && a->sa_handler != SIG_DFL && a->sa_handler != SIG_IGN)
            a->sa_handler(sig);
}

/// Python's KeyboardInterrupt for SIGINT and SIGTERM, beside the handlers the host set
/// (only where the host set its own: a process that leaves them to the default ends at once).
void chain_signals() {
    int i = 0;
    for (const int sig : {SIGINT, SIGTERM}) {
        struct sigaction current {};
        sigaction(sig, nullptr, &current);
        if ((current.sa_flags & SA_SIGINFO) || current.sa_handler == SIG_DFL ||
            current.sa_handler == SIG_IGN) {
            ++i;
            continue;
        }
        g_host_handler[i] = current;
        // Python's own C handler, installed by signal.signal, then taken back under ours.
        py::module_::import("signal").attr("signal")(
            sig, py::module_::import("signal").attr("default_int_handler"));
        struct sigaction ours {};
        ours.sa_handler = on_signal;
        sigemptyset(&ours.sa_mask);
        sigaction(sig, &ours, &g_python_handler[i]);
        ++i;
    }
}

/// Start the interpreter when the process has none (the fixpoint CLI), and let other threads
/// take the GIL: the render's workers call the scheme.
void ensure_interpreter() {
    static std::once_flag once;
    std::call_once(once, [] {
        if (Py_IsInitialized()) return;
        PyConfig config;
        PyConfig_InitPythonConfig(&config);
        // No signal handlers: the CLI's own SIGINT handler stops renders.
        config.install_signal_handlers = 0;
        // The interpreter the build found (Debian's, with its numpy), as the Python module is
        // built for: by default an embedded Python takes its prefix from the `python3` first on
        // PATH (pyenv's, say), whose site-packages lack numpy.
        PyConfig_SetBytesString(&config, &config.program_name, FIXPOINT_PYTHON_EXECUTABLE);
        const PyStatus status = Py_InitializeFromConfig(&config);
        PyConfig_Clear(&config);
        if (PyStatus_Exception(status))
            throw fp::ParamError(std::string("cannot start the Python of ") + FIXPOINT_PYTHON_EXECUTABLE +
                                 ": " + (status.err_msg ? status.err_msg : "unknown error"));
        try {
            chain_signals();
        } catch (const py::error_already_set&) {
            // (No signal module: Ctrl-C still stops the render, between batches.)
        }
        // os._exit in a scheme would end the CLI at once, with exit code 0 and no image: an
        // exception instead, reported as the scheme's error. (The Python module's process is
        // the user's own: left alone.)
        try {
            py::exec(R"(
import os as _os
def _no_exit(code=0):
    raise SystemExit(f"os._exit({code}): a python-scheme may not end the process")
_os._exit = _no_exit
del _os, _no_exit
)");
        } catch (const py::error_already_set&) {
        }
        PyEval_SaveThread();
    });
}

/// Which Python ran the code, for an error that depends on it (a module it lacks).
std::string interpreter_note(py::error_already_set& e) {
    if (!e.matches(PyExc_ImportError)) return "";
    try {
        const py::module_ sys = py::module_::import("sys");
        const std::string version = py::str(sys.attr("version"));
        return " (python-scheme runs Python " + version.substr(0, version.find(' ')) + " of " +
               std::string(py::str(sys.attr("prefix"))) + ")";
    } catch (const py::error_already_set&) {
        return "";
    }
}

/// "file:line: Type: message" of the Python exception being handled, from its traceback's
/// last frame in the scheme's own code where there is one.
std::string describe(py::error_already_set& e, const std::string& source) {
    std::string where;
    try {
        py::object tb = py::reinterpret_borrow<py::object>(e.trace());
        std::string line;
        while (tb && !tb.is_none()) {
            py::object frame = tb.attr("tb_frame");
            const std::string file = py::str(frame.attr("f_code").attr("co_filename"));
            if (file == source) line = py::str(tb.attr("tb_lineno"));
            tb = tb.attr("tb_next");
        }
        if (!line.empty()) where = source + ":" + line + ": ";
    } catch (const py::error_already_set&) {
    }
    std::string type = "Exception";
    try {
        if (e.type()) type = py::str(e.type().attr("__name__"));
    } catch (const py::error_already_set&) {
    }
    std::string msg;
    try {
        if (e.value()) msg = py::str(e.value());
    } catch (const py::error_already_set&) {
    }
    // A SyntaxError knows its own line.
    if (where.empty() && type == "SyntaxError") {
        try {
            where = source + ":" + std::string(py::str(e.value().attr("lineno"))) + ": ";
            msg = py::str(e.value().attr("msg"));
        } catch (const py::error_already_set&) {
        }
    }
    return where + type + (msg.empty() ? "" : ": " + msg);
}

// The coefficients python-scheme declares (plugins/iterations/python-scheme.cpp), with no range.
constexpr fp::ParamSpec coefficient_specs[] = {
    fp::param::sequence("alpha", ""), fp::param::sequence("beta", ""), fp::param::sequence("gamma", ""),
    fp::param::sequence("a", ""), fp::param::sequence("b", "")};

// What every scheme's namespace holds beside numpy: I, the matrix of the number 1, and lin,
// SchemeBase's c.lin on (x, y) pairs of arrays. Its sums are grouped as scheme-inl.hpp's
// lin2_t/lin3_t group them, each matrix entry rounded to the points' precision first, and numpy
// rounds every operation (no fused multiply-add, as the C++ build has -ffp-contract=off), so a
// scheme written with it gives the C++ scheme's bits.
constexpr const char* scheme_prelude = R"(
I = np.eye(2)

def lin(A, u, B, v, C=None, w=None):
    """A u + B v (+ C w): 2x2 matrices (k['alpha'], I - k['alpha'], ...) acting on points
    u = (x, y) of arrays, in the points' precision and in the order of the C++ SchemeBase."""
    t = np.asarray(u[0]).dtype.type
    def entries(M):
        M = np.asarray(M, dtype=np.float64)
        if M.shape != (2, 2):
            raise ValueError(f"lin: a matrix is 2x2, got the shape {M.shape}")
        return t(M[0, 0]), t(M[0, 1]), t(M[1, 0]), t(M[1, 1])
    a, b, c, d = entries(A)
    e, f, g, h = entries(B)
    x = (a * u[0] + b * u[1]) + (e * v[0] + f * v[1])
    y = (c * u[0] + d * u[1]) + (g * v[0] + h * v[1])
    if C is not None:
        p, q, r, s = entries(C)
        x = x + (p * w[0] + q * w[1])
        y = y + (r * w[0] + s * w[1])
    return x, y
)";

class PyScheme final : public fp::IterationScheme {
public:
    explicit PyScheme(const fp::ParamBag& p) {
        const bool has_file = p.has("file"), has_code = p.has("code");
        if (has_file == has_code)
            throw fp::ParamError(has_file ? "code" : "file", "give either 'file' or 'code', not both");
        std::string code;
        if (has_file) {
            // (The host gives the file from the working folder, resolved from the config's.)
            const std::string& file = p.string("file");
            source_ = file;
            // A folder opens as a stream that reads nothing, and a FIFO or device would block
            // or never end: a scheme is a regular file.
            std::error_code ec;
            const auto st = std::filesystem::status(file, ec);
            if (!ec && std::filesystem::exists(st) && !std::filesystem::is_regular_file(st))
                throw fp::ParamError("file",
                                     "'" + source_ + "' is not a regular file (a Python file is needed)");
            std::ifstream in(file, std::ios::binary);
            if (!in)
                throw fp::ParamError(
                    "file", "cannot read '" + source_ + "': " + std::strerror(errno) +
                                " (a path in a config is from its folder, in --set from the working folder)");
            std::ostringstream ss;
            ss << in.rdbuf();
            code = ss.str();
        } else {
            source_ = "<code>";
            code = p.string("code");
        }
        numbers_ = p.object<fp::NumberSystem>("numbers");
        for (const fp::ParamSpec& spec : coefficient_specs)
            if (p.has(spec.name))
                coefs_.push_back({spec.name, fp::scheme::read_coefficient(spec, p, numbers_->is_real())});
        ensure_interpreter();
        const char* const key = has_file ? "file" : "code";
        py::gil_scoped_acquire gil;
        // Every Python object lives in this block and reaches the members only once the scheme
        // is whole: an exception then unwinds them here, with the GIL held. (Members assigned
        // early were released by the unwinding after the GIL was: a scheme without `step`
        // aborted the process.)
        try {
            // Each scheme its own namespace: two python-schemes never share globals.
            py::dict ns;
            const py::module_ builtins = py::module_::import("builtins");
            ns["__builtins__"] = builtins;
            ns["__name__"] = "fixpoint_scheme";
            ns["__file__"] = source_;
            py::tuple args(p.reals("args").size());
            for (std::size_t i = 0; i < p.reals("args").size(); ++i) args[i] = p.reals("args")[i];
            ns["args"] = args;
            ns["np"] = py::module_::import("numpy");
            builtins.attr("exec")(py::str(scheme_prelude), ns);
            py::object compiled = builtins.attr("compile")(py::str(code), py::str(source_), "exec");
            builtins.attr("exec")(compiled, ns);
            if (!ns.contains("step") || !PyCallable_Check(ns["step"].ptr()))
                throw fp::ParamError(key, source_ + " defines no function step(T, x, y, n)");
            py::object step = ns["step"];
            unsigned applications = 1;
            if (ns.contains("applications")) {
                const long a = ns["applications"].cast<long>();
                if (a < 1 || a > 64)
                    throw fp::ParamError(key, source_ + ": applications must be from 1 to 64, got " +
                                                  std::to_string(a));
                applications = unsigned(a);
            }
            const bool picard = ns.contains("picard") && ns["picard"].cast<bool>();
            // step(T, x, y, n, k) gets the coefficients; step(T, x, y, n) may not be given any.
            const std::size_t arity =
                py::len(py::module_::import("inspect").attr("signature")(step).attr("parameters"));
            if (arity != 4 && arity != 5)
                throw fp::ParamError(key, source_ + ": step takes (T, x, y, n) or (T, x, y, n, k), not " +
                                              std::to_string(arity) + " arguments");
            if (arity == 4 && !coefs_.empty())
                throw fp::ParamError(coefs_[0].name,
                                     "the coefficient is given, but " + source_ +
                                         "'s step(T, x, y, n) takes none: write step(T, x, y, "
                                         "n, k) and read its matrix k['" +
                                         coefs_[0].name + "']");
            step_ = std::move(step);
            takes_k_ = arity == 5;
            ns_ = std::move(ns);
            applications_ = applications;
            picard_ = picard;
        } catch (py::error_already_set& e) {
            if (e.matches(PyExc_KeyboardInterrupt)) throw fp::Cancelled();
            throw fp::ParamError(key, describe(e, source_) + interpreter_note(e));
        } catch (const py::cast_error&) {
            throw fp::ParamError(key,
                                 source_ + ": 'applications' must be a whole number and 'picard' a bool");
        }
    }

    ~PyScheme() override {
        // Python objects are released with the GIL held; after the interpreter is gone (a
        // Python process exiting) they are left alone.
        if (Py_IsInitialized()) {
            py::gil_scoped_acquire gil;
            step_ = py::object();
            ns_ = py::object();
        } else {
            step_.release();
            ns_.release();
        }
    }

    void step(const fp::Transform& t, fp::Points<float> p, fp::Mask m, std::uint64_t n) const override {
        run(t, p, m, n);
    }
    void step(const fp::Transform& t, fp::Points<double> p, fp::Mask m, std::uint64_t n) const override {
        run(t, p, m, n);
    }
    unsigned applications() const override { return applications_; }
    bool is_picard() const override { return picard_; }

private:
    template <class T>
    void run(const fp::Transform& t, fp::Points<T> p, fp::Mask mask, std::uint64_t n) const {
        if (p.n == 0) return;
        py::gil_scoped_acquire gil;
        // Each render thread keeps its Python thread state rather than making and deleting one
        // per batch.
        static thread_local bool kept = false;
        if (!kept) gil.inc_ref(), kept = true;
        try {
            using Array = py::array_t<T, py::array::c_style | py::array::forcecast>;
            // The map on whole arrays, in the batch's precision; each call gets new arrays.
            // Each application of T in the step draws its own randoms from the points' keys, as
            // SchemeBase's c.t does (salt 0, 1, ... within the step), for arrays of the batch.
            std::uint32_t salt = 0;
            py::cpp_function map([&t, &p, &salt](Array x, Array y) {
                if (x.ndim() != 1 || y.ndim() != 1 || x.shape(0) != y.shape(0))
                    throw py::value_error("T(x, y): x and y must be 1-dimensional arrays of one length");
                const auto len = std::size_t(x.shape(0));
                Array ox(len), oy(len);
                std::copy_n(x.data(), len, ox.mutable_data());
                std::copy_n(y.data(), len, oy.mutable_data());
                const bool keyed = p.key && len == p.n;
                t.apply(fp::Points<T>{ox.mutable_data(), oy.mutable_data(), len, keyed ? p.key : nullptr,
                                      keyed ? salt++ : 0},
                        nullptr);
                return py::make_tuple(ox, oy);
            });
            Array x(p.n), y(p.n);
            std::copy_n(p.x, p.n, x.mutable_data());
            std::copy_n(p.y, p.n, y.mutable_data());
            py::object r = takes_k_ ? step_(map, x, y, n, coefficients(n)) : step_(map, x, y, n);
            if (!py::isinstance<py::tuple>(r) || py::len(r) != 2)
                throw fp::InputError("python-scheme: " + source_ + ": step must return a tuple (x, y)");
            const Array rx = Array::ensure(r.cast<py::tuple>()[0]),
                        ry = Array::ensure(r.cast<py::tuple>()[1]);
            if (!rx || !ry || rx.ndim() != 1 || ry.ndim() != 1 || std::size_t(rx.shape(0)) != p.n ||
                std::size_t(ry.shape(0)) != p.n)
                throw fp::InputError("python-scheme: " + source_ + ": step must return two arrays of " +
                                     std::to_string(p.n) + " numbers, as many as it was given");
            const T* ax = rx.data();
            const T* ay = ry.data();
            for (std::size_t i = 0; i < p.n; ++i)
                if (!mask || mask[i]) p.x[i] = ax[i], p.y[i] = ay[i];
        } catch (py::error_already_set& e) {
            if (e.matches(PyExc_KeyboardInterrupt)) throw fp::Cancelled();
            throw fp::InputError("python-scheme: " + describe(e, source_));
        } catch (const py::cast_error& e) {
            throw fp::InputError("python-scheme: " + source_ +
                                 ": step returned something that is not arrays");
        }
    }

    /// The coefficients at step n, each as its multiplier's matrix (NumberSystem::multiplier):
    /// {"alpha": [[a, b], [c, d]], ...}, float64 as SchemeBase's Mat2.
    py::dict coefficients(std::uint64_t n) const {
        py::dict k;
        for (const Coefficient& c : coefs_) {
            const fp::Mat2 m = numbers_->multiplier(c.values.at(n));
            py::array_t<double> a(std::vector<py::ssize_t>{2, 2});
            double* d = a.mutable_data();
            d[0] = m.a, d[1] = m.b, d[2] = m.c, d[3] = m.d;
            k[py::str(c.name)] = a;
        }
        return k;
    }

    struct Coefficient {
        std::string name;
        fp::Sequence values;
    };
    std::shared_ptr<const fp::NumberSystem> numbers_;
    std::vector<Coefficient> coefs_;
    bool takes_k_ = false;
    std::string source_;
    // (py::object, not py::dict: a dict's default constructor calls Python, which may not be
    // running yet when the members are made.)
    py::object ns_;
    py::object step_;
    unsigned applications_ = 1;
    bool picard_ = false;
};

} // namespace

extern "C" __attribute__((visibility("default"))) void
fixpoint_make_python_scheme(const fp::ParamBag& p, std::shared_ptr<const fp::IterationScheme>& out) {
    out = std::make_shared<const PyScheme>(p);
}
