// fixpoint's Python module, the C++ half (`fixpoint._fixpoint`); fixpoint/__init__.py is the
// interface users call, and turns its arguments into the plain ones taken here.
//
// Renders run with the GIL released, on a thread of their own, while the calling thread
// reports progress and watches for Ctrl-C: a Python callback and Python's signal handling
// both need the calling thread and the GIL.
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/host/core/build.hpp>
#include <fixpoint/host/core/config.hpp>
#include <fixpoint/host/core/image_io.hpp>
#include <fixpoint/host/core/param_list.hpp>
#include <fixpoint/host/core/pipeline.hpp>
#include <fixpoint/host/core/registry.hpp>
#include <fixpoint/host/core/runtime.hpp>
#include <fixpoint/host/job/render_job.hpp>
#include <fixpoint/simd.hpp>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <dlfcn.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace py = pybind11;
namespace fs = std::filesystem;
using namespace fp;
using namespace fp::host;

namespace {

void where_am_i() {}

/// The plugin folders: the build's or install's (found from this module's own file, which
/// sits in the same tree as the CLI: lib/python3/dist-packages/fixpoint/), then
/// FIXPOINT_PLUGIN_PATH, then those added with add_plugin_dir().
struct Plugins {
    std::vector<fs::path> extra;
    std::optional<Registry> reg;
    std::vector<std::string> refused; ///< warnings not yet given to Python
};

Plugins& plugins() {
    // Never destroyed: plugin libraries stay loaded until the process ends, past the
    // interpreter's own teardown.
    static auto* p = new Plugins;
    return *p;
}

Registry& registry() {
    Plugins& p = plugins();
    if (!p.reg) {
        Registry reg;
        Dl_info info{};
        if (dladdr(reinterpret_cast<void*>(&where_am_i), &info) && info.dli_fname)
            reg.load_dir(fs::path(info.dli_fname).parent_path() / FIXPOINT_PY_PLUGIN_REL_DIR);
        // (default_dirs() starts with the folder beside the running executable: python's.)
        const auto dirs = Registry::default_dirs();
        for (std::size_t i = 1; i < dirs.size(); ++i) reg.load_dir(dirs[i]);
        for (const auto& d : p.extra) reg.load_dir(d);
        for (const auto& r : reg.refused()) p.refused.push_back("plugin file skipped: " + r.reason);
        p.reg = std::move(reg);
    }
    return *p.reg;
}

/// Warnings for Python's warnings module: the Python half issues them.
std::vector<std::string> take_warnings() {
    auto w = std::move(plugins().refused);
    plugins().refused.clear();
    return w;
}

void add_plugin_dir(const std::string& dir) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) throw InputError("plugin folder '" + dir + "' is not a folder");
    Plugins& p = plugins();
    p.extra.emplace_back(dir);
    if (p.reg) {
        const std::size_t before = p.reg->refused().size();
        p.reg->load_dir(dir);
        for (std::size_t i = before; i < p.reg->refused().size(); ++i)
            p.refused.push_back("plugin file skipped: " + p.reg->refused()[i].reason);
    }
}

Pipeline pipeline_of(const std::string& config, bool is_text, const std::vector<std::string>& sets,
                     bool allow_python) {
    Registry& reg = registry();
    if (!is_text) return load_pipeline(reg, config, sets, "", allow_python);
    CNode root = parse_yaml(config, "<config>");
    for (const auto& s : sets) apply_override(root, s);
    return load_pipeline(reg, std::move(root));
}

/// Run `work` on a thread of its own with the GIL released; the calling thread reports
/// `done()` / `total` to `progress` about ten times a second and turns Ctrl-C (or an
/// exception from the callback) into a cancelled render.
template <class Work>
void run_released(Work&& work, std::atomic<bool>& cancel, const std::function<std::uint64_t()>& done,
                  std::uint64_t total, const py::object& progress) {
    std::exception_ptr failure;
    std::mutex mu;
    std::condition_variable cv;
    bool finished = false;
    std::optional<py::error_already_set> raised;
    {
        py::gil_scoped_release nogil;
        std::thread worker([&] {
            try {
                work();
            } catch (...) {
                failure = std::current_exception();
            }
            std::lock_guard<std::mutex> lock(mu);
            finished = true;
            cv.notify_all();
        });
        std::unique_lock<std::mutex> lock(mu);
        while (!finished) {
            cv.wait_for(lock, std::chrono::milliseconds(100));
            if (finished || raised) continue;
            lock.unlock();
            {
                py::gil_scoped_acquire gil;
                try {
                    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
                    if (!progress.is_none() && total) progress(std::min(1.0, double(done()) / double(total)));
                } catch (py::error_already_set& e) {
                    raised.emplace(std::move(e));
                    cancel.store(true);
                }
            }
            lock.lock();
        }
        lock.unlock();
        worker.join();
    }
    if (raised) throw std::move(*raised);
    if (failure) std::rethrow_exception(failure);
    if (!progress.is_none()) progress(1.0);
}

/// What render() and validate() ask of the render job alike.
RenderRequest python_request(const std::string& config, bool is_text, unsigned threads,
                             const std::string& output, bool pixels) {
    RenderRequest request;
    request.output = output;
    request.source = is_text ? "" : config;
    request.raster_only = "{}: the Python module writes images (.png, .exr, .tif)";
    request.keep_image = pixels;
    request.threads = threads;
    return request;
}

/// render(config, is_text, sets, threads, progress, output, allow_python, pixels, job)
///   -> (float pixels or None, recipe, stats, warnings, bit_depth)
/// `job`: the render job's further requests as strings, as the CLI's options take them:
/// memory, checkpoint, checkpoint_every, resume ("" where not given), strict ("true").
/// With an output path, planned and written by the render job as `fixpoint render -o` does
/// (output.tiled honoured); without `pixels` the image is only written, and may stream in strips
/// when it does not fit in memory. allow_python: a recipe read from an image may run its
/// python-scheme's code.
py::tuple render(const std::string& config, bool is_text, const std::vector<std::string>& sets,
                 unsigned threads, const py::object& progress, const std::string& output, bool allow_python,
                 bool pixels, const std::map<std::string, std::string>& job) {
    const Pipeline p = pipeline_of(config, is_text, sets, allow_python);
    if (!pixels && output.empty()) throw InputError("render: pixels=False needs an output file to write");
    RenderRequest request = python_request(config, is_text, threads, output, pixels);
    const auto opt = [&job](const char* key) {
        const auto it = job.find(key);
        return it == job.end() ? std::string() : it->second;
    };
    if (const std::string m = opt("memory"); !m.empty()) request.memory = parse_size(m, "memory");
    request.checkpoint = opt("checkpoint"), request.checkpoint_every = opt("checkpoint_every");
    request.resume = opt("resume");
    request.strict = opt("strict") == "true";
    RenderPlan plan = plan_render(p, request);
    std::atomic<bool> cancel{false};
    std::atomic<std::uint64_t> done{0};
    RenderHooks hooks;
    hooks.cancel = &cancel;
    hooks.done = &done;
    RenderResult r;
    run_released([&] { r = run_render(plan, hooks); }, cancel, [&done] { return done.load(); },
                 plan_work_units(plan), progress);
    std::vector<std::string> warnings = p.warnings;
    for (auto& w : r.warnings) warnings.push_back(std::move(w));
    py::object image = py::none();
    if (pixels) {
        const Image& img = r.image;
        py::array_t<float> a(std::vector<py::ssize_t>{img.height, img.width, img.channels});
        std::copy(img.pixels.begin(), img.pixels.end(), a.mutable_data());
        image = std::move(a);
    }
    py::dict st;
    st["samples"] = r.stats.samples;
    st["restarts"] = r.stats.restarts;
    st["bad_values"] = r.stats.bad_values;
    st["unit"] = r.stats.unit;
    if (r.stats.drawn != RenderStats::unknown_count) st["drawn"] = r.stats.drawn;
    st["threads"] = plan.threads;
    if (!plan.checkpoints.path.empty()) st["checkpoints"] = r.checkpoints_written;
    st["simd"] = std::string(simd::active_target());
    if (!r.stats.how.empty()) st["how"] = r.stats.how;
    return py::make_tuple(image, p.recipe, st, warnings, p.bit_depth);
}

/// validate(config, is_text, sets, threads, output, allow_python, memory, pixels) -> dict: every check
/// render() would make (the schemas, the plugins' own, the output path, the memory plan), with
/// nothing rendered, as `fixpoint validate`. An output that exists is not refused (render()
/// replaces a named output): the dict names it under "exists".
py::dict validate_config(const std::string& config, bool is_text, const std::vector<std::string>& sets,
                         unsigned threads, const std::string& output, bool allow_python,
                         const std::string& memory, bool pixels) {
    const Pipeline p = pipeline_of(config, is_text, sets, allow_python);
    RenderRequest request = python_request(config, is_text, threads, output, pixels);
    if (!memory.empty()) request.memory = parse_size(memory, "memory");
    const RenderPlan plan = plan_render(p, request);
    py::dict d;
    d["width"] = p.renderer->width();
    d["height"] = p.renderer->height();
    d["output"] = plan.output.empty() ? py::object(py::none()) : py::object(py::str(plan.output));
    std::error_code ec;
    d["exists"] = !plan.output.empty() && fs::exists(fs::symlink_status(plan.output, ec));
    d["threads"] = plan.threads;
    d["streams"] = plan.memory.stream; // (in strips: the image does not fit the memory whole)
    d["warnings"] = p.warnings;
    return d;
}

/// Float pixels (height, width, channels) as an 8- or 16-bit image file stores them.
py::array quantise(const py::array_t<float, py::array::c_style | py::array::forcecast>& a, int bit_depth) {
    if (a.ndim() != 3) throw InputError("quantise: expected an array of shape (height, width, channels)");
    if (bit_depth != 8 && bit_depth != 16)
        throw InputError("quantise: bit_depth must be 8 or 16, got " + std::to_string(bit_depth));
    Image img;
    img.height = int(a.shape(0));
    img.width = int(a.shape(1));
    img.channels = int(a.shape(2));
    img.pixels.assign(a.data(), a.data() + a.size());
    const std::vector<py::ssize_t> shape = {a.shape(0), a.shape(1), a.shape(2)};
    if (bit_depth == 16) {
        py::array_t<std::uint16_t> out(shape);
        quantise_pixels(img, 16, out.mutable_data());
        return out;
    }
    py::array_t<std::uint8_t> out(shape);
    quantise_pixels(img, 8, out.mutable_data());
    return out;
}

/// params(config, is_text, sets) -> list of dicts: every parameter of the config with its
/// place and declaration (host/core/param_list.hpp), the data interact() builds its widgets
/// from, as serve's page builds its panel.
py::list config_params(const std::string& config, bool is_text, const std::vector<std::string>& sets) {
    CNode root = is_text ? parse_yaml(config, "<config>") : parse_yaml(read_yaml_text(config), config);
    for (const auto& s : sets) apply_override(root, s);
    py::list out;
    for (const ParamEntry& e : list_params(registry(), root)) {
        py::dict d;
        d["path"] = e.path, d["name"] = e.name, d["owner"] = e.owner, d["kind"] = e.kind;
        d["value"] = e.value, d["written"] = e.written, d["required"] = e.required;
        d["default"] = e.default_value, d["description"] = e.description, d["depth"] = e.depth;
        d["min"] = e.min ? py::object(py::float_(*e.min)) : py::object(py::none());
        d["max"] = e.max ? py::object(py::float_(*e.max)) : py::object(py::none());
        d["min_open"] = e.min_open, d["max_open"] = e.max_open;
        d["choices"] = e.choices, d["plugin_kind"] = e.plugin_kind, d["count"] = e.count;
        out.append(d);
    }
    return out;
}

/// The PNG bytes of float pixels (height, width, 3), 8 or 16 bits, as render -o writes them
/// (no recipe): what a notebook shows of an image (fixpoint.Picture._repr_png_).
py::bytes encode_png(const py::array_t<float, py::array::c_style | py::array::forcecast>& a, int bit_depth) {
    if (a.ndim() != 3 || a.shape(2) != 3)
        throw InputError("encode_png: expected an array of shape (height, width, 3)");
    if (bit_depth != 8 && bit_depth != 16)
        throw InputError("encode_png: bit_depth must be 8 or 16, got " + std::to_string(bit_depth));
    Image img;
    img.height = int(a.shape(0));
    img.width = int(a.shape(1));
    img.channels = 3;
    img.pixels.assign(a.data(), a.data() + a.size());
    return py::bytes(encode_image(img, Format::Png, bit_depth, ""));
}

py::array_t<double> eval(const std::string& transform, const std::string& scheme,
                         const py::array_t<double, py::array::c_style | py::array::forcecast>& points,
                         long long steps) {
    Registry& reg = registry();
    auto t = std::dynamic_pointer_cast<const Transform>(
        build_from_text(reg, Kind::Transform, transform, "<transform>", "transform"));
    auto s = std::dynamic_pointer_cast<const IterationScheme>(
        build_from_text(reg, Kind::IterationScheme, scheme, "<scheme>", "scheme"));
    if (points.ndim() != 2 || points.shape(1) != 2)
        throw InputError("eval: points must be an array of shape (n, 2), got " +
                         std::to_string(points.ndim()) + " dimension(s)");
    if (steps < 0) throw InputError("eval: steps must be 0 or more, got " + std::to_string(steps));
    const auto n = std::size_t(points.shape(0));
    std::vector<double> xs(n), ys(n);
    for (std::size_t i = 0; i < n; ++i) xs[i] = points.at(i, 0), ys[i] = points.at(i, 1);
    {
        py::gil_scoped_release nogil;
        Points<double> pts{xs.data(), ys.data(), n};
        if (n)
            for (long long k = 0; k < steps; ++k) s->step(*t, pts, nullptr, std::uint64_t(k));
    }
    py::array_t<double> out({py::ssize_t(n), py::ssize_t(2)});
    auto o = out.mutable_unchecked<2>();
    for (std::size_t i = 0; i < n; ++i) o(i, 0) = xs[i], o(i, 1) = ys[i];
    return out;
}

py::dict param_dict(const ParamSpec& s) {
    py::dict d;
    d["name"] = s.name;
    std::string type(param_type_name(s.type));
    d["type"] = type;
    if (s.type == ParamType::Object || s.type == ParamType::Objects)
        d["kind"] = std::string(kind_name(s.kind));
    d["default"] = s.default_yaml ? py::object(py::str(s.default_yaml)) : py::none();
    d["required"] = !s.default_yaml && !s.optional;
    d["doc"] = s.doc ? s.doc : "";
    if (std::isfinite(s.lo) || std::isfinite(s.hi)) {
        d["range"] = py::make_tuple(s.lo, s.hi);
        d["range_open"] = py::make_tuple(s.lo_open, s.hi_open);
    }
    if (s.choices) d["choices"] = std::string(s.choices);
    if (s.count) d["count"] = s.count;
    if (s.type == ParamType::Objects && s.n_item_params) {
        py::list items;
        for (std::uint32_t i = 0; i < s.n_item_params; ++i) items.append(param_dict(s.item_params[i]));
        d["item_params"] = items;
    }
    return d;
}

py::dict plugin_dict(const PluginEntry& e) {
    py::dict d;
    d["name"] = e.desc->name;
    d["kind"] = std::string(kind_name(e.desc->kind));
    d["version"] = e.desc->version;
    d["summary"] = e.desc->summary;
    d["file"] = e.file.string();
    return d;
}

py::list list_plugins(const std::optional<std::string>& kind) {
    std::optional<Kind> k;
    if (kind) {
        for (int i = 0; i < kind_count; ++i)
            if (*kind == kind_name(Kind(i))) k = Kind(i);
        if (!k) throw InputError("unknown kind '" + *kind + "'");
    }
    py::list out;
    for (const auto* e : registry().all(k)) out.append(plugin_dict(*e));
    return out;
}

py::dict describe_plugin(const std::string& name) {
    const PluginEntry* e = &registry().get(name);
    py::dict d = plugin_dict(*e);
    py::list ps;
    for (std::uint32_t i = 0; i < e->desc->n_params; ++i) ps.append(param_dict(e->desc->params[i]));
    d["params"] = ps;
    d["example"] = e->desc->example ? e->desc->example : "{}";
    d["runs_code"] = e->desc->runs_code; // (refused in an image's recipe unless allow_python)
    return d;
}

} // namespace

PYBIND11_MODULE(_fixpoint, m) {
    m.doc() = "fixpoint's C++ core; use the functions of the fixpoint package";
    // The image module sits in the same tree as this module (not beside python's executable).
    {
        Dl_info info{};
        if (dladdr(reinterpret_cast<void*>(&where_am_i), &info) && info.dli_fname)
            set_image_module_path((fs::path(info.dli_fname).parent_path() / FIXPOINT_PY_IMAGE_MODULE_REL_PATH)
                                      .lexically_normal());
    }
    // fp::InputError (bad input, with its file:line:col) becomes fixpoint.Error, defined in
    // Python; fp::Cancelled a KeyboardInterrupt; other errors RuntimeError.
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const Cancelled&) {
            PyErr_SetNone(PyExc_KeyboardInterrupt);
        } catch (const InputError& e) {
            py::object cls = py::module_::import("fixpoint._errors").attr("Error");
            PyErr_SetObject(cls.ptr(), py::str(e.what()).ptr());
        }
    });
    m.def("render", &render);
    m.def("validate", &validate_config);
    m.def("params", &config_params);
    m.def("quantise", &quantise);
    m.def("encode_png", &encode_png);
    m.def("eval", &eval);
    m.def("plugins", &list_plugins);
    m.def("describe", &describe_plugin);
    m.def("add_plugin_dir", &add_plugin_dir);
    m.def("take_warnings", &take_warnings);
    m.def("read_recipe", &read_recipe);
    m.attr("__version__") = FIXPOINT_VERSION;
}
