// `fixpoint animate`: keyframes for any numeric parameter of a config, one render per frame,
// and a video assembled by ffmpeg.
//
// The format, at the top level of a config beside renderer: and output::
//
//   animation:
//     frames: 120                 # required: frames 0 .. 119 (1 to 100000)
//     fps: 30                     # frames per second of --video (default 30; (0, 1000])
//     interpolation: linear       # smooth or catmull-rom (default linear)
//     loop: false                 # true: periodic, the last keyframe runs on into the first
//     keys:                       # required, at least one
//       renderer.iteration.alpha: {0: 0.5, 60: 0.7, 119: 0.9}
//       renderer.view: {0: [-2, 2, -2, 2], 119: [-1, 1, -1, 1]}
//       renderer.maps[0].colour: {0: "#ff6b6b", 119: [0.2, 0.4, 1]}
//
// - A key is a parameter path exactly as `--set` takes it (under renderer:); its value is a
//   mapping from frame numbers (whole numbers in [0, frames - 1], in any order) to values.
//   Every frame of the animation is the config with each key's value at that frame set, just
//   as `--set path=value` would set it (`animate --list` prints those assignments).
// - Values: numbers, lists of numbers (nested lists too; elementwise), and colours "#rrggbb"
//   (taken as the list [r, g, b] = [rr/255, gg/255, bb/255]). Every keyframe of a key has the
//   same shape. Colours are interpolated componentwise in the values the config gives (the
//   image's sRGB-encoded values, as written), not in linear light; between keys a colour is
//   written as [r, g, b].
// - At a keyframe the value is the one written there, as written. Before the first keyframe
//   and after the last the value stays at that keyframe's. Between two keyframes at frames
//   f0 < f1 with values a and b, at frame f: t = (f - f0) / (f1 - f0), and the value is
//   a + (b - a) * s with s = t (linear) or s = t * t * (3 - 2 t) (smooth: smoothstep, which
//   eases in and out of every keyframe and never leaves the range between two neighbouring
//   keyframes, so a value valid at both keys stays valid between them).
// - catmull-rom: the cubic Hermite curve through the keyframes whose slope at keyframe i (per
//   frame) is (v[i+1] - v[i-1]) / (f[i+1] - f[i-1]), its neighbours' secant (Catmull and Rom
//   1974, in the form for unevenly spaced keys); at the first and last keyframe of an animation
//   that does not loop the missing neighbour is the key itself, so the slope is the one-sided
//   secant. Between f0 and f1, with d = f1 - f0 and slopes m0, m1:
//   v = h00 a + h10 d m0 + h01 b + h11 d m1, h00 = 2t^3 - 3t^2 + 1, h10 = t^3 - 2t^2 + t,
//   h01 = -2t^3 + 3t^2, h11 = t^3 - t^2. Motion through the keys is smooth (the slope is
//   continuous at every key), but the curve may overshoot between keys: a value valid at the
//   keys may be refused between them, at the frame's check, before anything renders.
// - loop: true makes the keys periodic with period `frames`: keyframe f stands for every frame
//   f + k * frames, so after the last keyframe the value runs on to the first one's at
//   frames + f_first (and before the first it comes from the last's at f_last - frames), with
//   catmull-rom's neighbours taken round the loop. Frame `frames`, the one after the last, would
//   be frame 0 exactly: a GIF or a video of the frames loops without a seam.
// - Integers: a key whose parameter is an integer in its plugin's schema (points, seed, chains,
//   a polygon's number of points, ...) is rounded to the nearest integer between keyframes,
//   halves away from zero (std::llround). Every other number is a real, written in the
//   shortest text that reads back as the double (std::to_chars): [-2, 2] to [-1, 1] passes
//   through [-1.5, 1.5].
// - Temporal coherence: nothing is reseeded per frame. Every frame renders with the config's
//   seed and chains (unless a key animates them), so what does not change does not flicker.
// - `render` and `validate` of a config with an animation section render (check) the config as
//   it stands, without the animation; `validate` also checks every frame of the animation.
//   Recipes do not carry the animation section: frame k's recipe is the config of frame k, and
//   `fixpoint render frame.png` renders it again, byte for byte.
//
// Everything (the section, every frame's config, every frame's file, the video's path and
// ffmpeg) is checked before the first frame is rendered. A frame whose file exists with the
// same recipe is skipped (said in the log); a file there with another recipe is refused unless
// --force. Frames are written one by one, each atomically, so an interrupted run is continued
// by running it again.
#include "motion_blur.hpp"
#include "video.hpp"

#include <fixpoint/errors.hpp>
#include <fixpoint/host/core/image_io.hpp>
#include <fixpoint/host/job/render_job.hpp>
#include <fixpoint/host/tools/animate.hpp>
#include <fixpoint/text.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>

namespace fp::host {

namespace fs = std::filesystem;

namespace {

constexpr long max_frames = 100000;

[[noreturn]] void fail(const Mark& m, const std::string& what, const std::string& why) {
    throw InputError(m.str() + ": " + what + ": " + why);
}

bool whole_number(const std::string& t, long& v) {
    const char* b = t.data();
    const char* e = b + t.size();
    if (b != e && *b == '+') ++b;
    const auto [p, ec] = std::from_chars(b, e, v);
    return b != e && ec == std::errc() && p == e;
}

// A number as the schemas read one (an unquoted scalar).
bool number(const CNode& n, double& v) {
    if (!n.is_scalar() || n.quoted) return false;
    const char* b = n.scalar.data();
    const char* e = b + n.scalar.size();
    if (b != e && *b == '+') ++b;
    const auto [p, ec] = std::from_chars(b, e, v);
    return b != e && ec == std::errc() && p == e && std::isfinite(v);
}

bool hex_colour(const CNode& n, double rgb[3]) {
    if (!n.is_scalar() || n.scalar.size() != 7 || n.scalar[0] != '#') return false;
    unsigned v = 0;
    const auto [p, ec] = std::from_chars(n.scalar.data() + 1, n.scalar.data() + 7, v, 16);
    if (ec != std::errc() || p != n.scalar.data() + 7) return false;
    rgb[0] = double((v >> 16) & 255) / 255, rgb[1] = double((v >> 8) & 255) / 255,
    rgb[2] = double(v & 255) / 255;
    return true;
}

// A keyframe's value flattened: its numbers in order, and its shape ("n", "[n, n]",
// "[[n, n], [n, n]]"; a colour is "[n, n, n]").
struct Flat {
    std::vector<double> v;
    std::string shape;
};

bool flatten(const CNode& n, Flat& f) {
    double rgb[3];
    if (hex_colour(n, rgb)) {
        for (double c : rgb) f.v.push_back(c);
        f.shape += "[n, n, n]";
        return true;
    }
    if (n.is_seq()) {
        if (n.items.empty()) return false;
        f.shape += "[";
        for (std::size_t i = 0; i < n.items.size(); ++i) {
            if (i) f.shape += ", ";
            if (!flatten(n.items[i], f)) return false;
        }
        f.shape += "]";
        return true;
    }
    double v;
    if (!number(n, v)) return false;
    f.v.push_back(v), f.shape += "n";
    return true;
}

// A node of shape `like` (a keyframe's value) holding the numbers of `f` from `at` on, rounded
// to whole numbers for an integer parameter.
CNode rebuild(const CNode& like, const Flat& f, std::size_t& at, const Mark& mark, bool integer) {
    if (like.is_seq() || (like.is_scalar() && like.scalar.size() == 7 && like.scalar[0] == '#')) {
        CNode s = seq_node();
        s.mark = mark;
        const std::size_t n = like.is_seq() ? like.items.size() : 3;
        for (std::size_t i = 0; i < n; ++i)
            s.items.push_back(rebuild(like.is_seq() ? like.items[i] : CNode{}, f, at, mark, integer));
        return s;
    }
    const double v = f.v[at];
    CNode s = scalar_node(integer ? std::to_string(std::llround(v)) : number_text(v));
    if (s.scalar == "-0") s.scalar = "0";
    s.mark = mark;
    ++at;
    return s;
}

std::string keys_path(const AnimationKey& k) { return "animation.keys." + excerpt(k.path, 80); }

} // namespace

bool has_animation(const CNode& root) { return root.is_map() && root.find("animation") != nullptr; }

Animation parse_animation(const CNode& root) {
    const CNode& s = *root.find("animation");
    const Mark& at = *root.key_mark("animation");
    if (!s.is_map())
        fail(s.type == CNode::Type::Null ? at : s.mark, "animation",
             "expected a mapping (frames, fps, interpolation, loop, keys), got " + s.describe());
    Animation a;
    const std::vector<std::string> known = {
        "frames", "fps", "interpolation", "loop", "temporal_samples", "temporal_filter_width", "keys"};
    for (std::size_t i = 0; i < s.keys.size(); ++i)
        if (std::find(known.begin(), known.end(), s.keys[i].first) == known.end()) {
            const auto near = suggest(s.keys[i].first, known);
            fail(s.key_marks[i], "animation",
                 "unknown key " + quote(s.keys[i].first) +
                     (near.empty() ? " (expected frames, fps, interpolation, loop, temporal_samples, "
                                     "temporal_filter_width, keys)"
                                   : " (did you mean '" + near[0] + "'?)"));
        }
    const CNode* frames = s.find("frames");
    if (!frames) fail(at, "animation", "missing 'frames:' (the number of frames)");
    const Mark& fmark = frames->type == CNode::Type::Null ? *s.key_mark("frames") : frames->mark;
    if (!frames->is_scalar() || frames->quoted || !whole_number(frames->scalar, a.frames) || a.frames < 1 ||
        a.frames > max_frames)
        fail(fmark, "animation.frames",
             "expected a whole number from 1 to " + std::to_string(max_frames) + ", got " +
                 frames->describe());
    if (const CNode* fps = s.find("fps")) {
        if (!number(*fps, a.fps) || !(a.fps > 0) || a.fps > 1000)
            fail(fps->type == CNode::Type::Null ? *s.key_mark("fps") : fps->mark, "animation.fps",
                 "expected a number in (0, 1000], got " + fps->describe());
    }
    if (const CNode* in = s.find("interpolation")) {
        if (!in->is_scalar() ||
            (in->scalar != "linear" && in->scalar != "smooth" && in->scalar != "catmull-rom"))
            fail(in->type == CNode::Type::Null ? *s.key_mark("interpolation") : in->mark,
                 "animation.interpolation", "expected linear, smooth or catmull-rom, got " + in->describe());
        a.interpolation = in->scalar == "smooth"        ? Interpolation::smooth
                          : in->scalar == "catmull-rom" ? Interpolation::catmull_rom
                                                        : Interpolation::linear;
    }
    if (const CNode* lp = s.find("loop")) {
        if (!lp->is_scalar() || lp->quoted || (lp->scalar != "true" && lp->scalar != "false"))
            fail(lp->type == CNode::Type::Null ? *s.key_mark("loop") : lp->mark, "animation.loop",
                 "expected true or false, got " + lp->describe());
        a.loop = lp->scalar == "true";
    }
    if (const CNode* ts = s.find("temporal_samples")) {
        if (!ts->is_scalar() || ts->quoted || !whole_number(ts->scalar, a.temporal_samples) ||
            a.temporal_samples < 1 || a.temporal_samples > 1024)
            fail(ts->type == CNode::Type::Null ? *s.key_mark("temporal_samples") : ts->mark,
                 "animation.temporal_samples",
                 "expected a whole number from 1 to 1024, got " + ts->describe());
    }
    if (const CNode* tw = s.find("temporal_filter_width")) {
        if (!number(*tw, a.temporal_filter_width) || !(a.temporal_filter_width > 0) ||
            a.temporal_filter_width > 16)
            fail(tw->type == CNode::Type::Null ? *s.key_mark("temporal_filter_width") : tw->mark,
                 "animation.temporal_filter_width",
                 "expected a number in (0, 16] (the frames a frame's samples span), got " + tw->describe());
    }
    const CNode* keys = s.find("keys");
    if (!keys) fail(at, "animation", "missing 'keys:' (parameter paths and their keyframes)");
    if (!keys->is_map() || keys->keys.empty())
        fail(keys->type == CNode::Type::Null ? *s.key_mark("keys") : keys->mark, "animation.keys",
             "expected a mapping of parameter paths to keyframes {frame: value, ...}, got " +
                 (keys->is_map() ? std::string("an empty mapping") : keys->describe()));
    for (std::size_t i = 0; i < keys->keys.size(); ++i) {
        AnimationKey k;
        k.path = keys->keys[i].first;
        k.mark = keys->key_marks[i];
        const CNode& kf = keys->keys[i].second;
        const std::string what = keys_path(k);
        if (k.path.rfind("renderer.", 0) != 0)
            fail(k.mark, what,
                 "expected a parameter path under renderer: (as --set takes it, e.g. renderer.seed)");
        // The path must fit the config's tree as --set would apply it (an index in range, no
        // scalar on the way); an unknown name is caught when the frame's config is checked.
        {
            CNode probe = root;
            override_target(probe, k.path, k.mark.str() + ": " + what, k.mark);
        }
        if (!kf.is_map() || kf.keys.empty())
            fail(kf.type == CNode::Type::Null ? k.mark : kf.mark, what,
                 "expected keyframes {frame: value, ...}, got " +
                     (kf.is_map() ? std::string("an empty mapping") : kf.describe()));
        std::string shape;
        for (std::size_t j = 0; j < kf.keys.size(); ++j) {
            const auto& [fr, v] = kf.keys[j];
            long frame = 0;
            if (!whole_number(fr, frame) || frame < 0 || frame >= a.frames)
                fail(kf.key_marks[j], what,
                     "keyframe " + quote(fr) + ": expected a frame number from 0 to " +
                         std::to_string(a.frames - 1) + " (frames: " + std::to_string(a.frames) + ")");
            for (const auto& [f2, v2] : k.frames)
                if (f2 == frame)
                    fail(kf.key_marks[j], what, "frame " + std::to_string(frame) + " is keyed twice");
            const Mark& vmark = v.type == CNode::Type::Null ? kf.key_marks[j] : v.mark;
            Flat f;
            if (!flatten(v, f))
                fail(vmark, what,
                     "frame " + std::to_string(frame) +
                         ": expected a number, a list of numbers or a colour \"#rrggbb\", got " +
                         v.describe());
            if (shape.empty())
                shape = f.shape;
            else if (f.shape != shape)
                fail(vmark, what,
                     "frame " + std::to_string(frame) + ": a value of shape " + f.shape +
                         " where the first keyframe has " + shape + " (n: a number; a colour is [n, n, n])");
            k.frames.emplace_back(frame, v);
        }
        std::stable_sort(k.frames.begin(), k.frames.end(),
                         [](const auto& x, const auto& y) { return x.first < y.first; });
        for (const auto& other : a.keys)
            if (other.path == k.path) fail(k.mark, what, "this path is animated twice");
        a.keys.push_back(std::move(k));
    }
    return a;
}

namespace {

/// Keyframe i of k, round the loop: index i mod m, its frame moved by whole periods.
struct Near {
    const CNode* value;
    double frame;
};
Near key_at(const Animation& a, const AnimationKey& k, long i) {
    const long m = long(k.frames.size());
    const long wraps = (i >= 0 ? i : i - m + 1) / m; // floor(i / m)
    const auto& [f, v] = k.frames[std::size_t(i - wraps * m)];
    return {&v, double(f) + double(wraps) * double(a.frames)};
}

/// The slope (per frame, per component) at keyframe i: the secant of its neighbours, the key
/// itself standing for a missing one where the animation does not loop.
std::vector<double> slope(const Animation& a, const AnimationKey& k, long i) {
    const long m = long(k.frames.size());
    const Near lo = a.loop || i > 0 ? key_at(a, k, i - 1) : key_at(a, k, i);
    const Near hi = a.loop || i < m - 1 ? key_at(a, k, i + 1) : key_at(a, k, i);
    Flat l, h;
    flatten(*lo.value, l);
    flatten(*hi.value, h);
    std::vector<double> out(l.v.size(), 0.0);
    if (hi.frame > lo.frame)
        for (std::size_t c = 0; c < out.size(); ++c) out[c] = (h.v[c] - l.v[c]) / (hi.frame - lo.frame);
    return out;
}

} // namespace

CNode animated_value(const Animation& a, const AnimationKey& k, double frame) {
    const auto& fs_ = k.frames;
    const long m = long(fs_.size());
    // A loop's frames repeat with period `frames`: the would-be frame `frames` is frame 0.
    if (a.loop) {
        const double period = double(a.frames);
        frame = std::fmod(std::fmod(frame, period) + period, period);
    }
    for (const auto& [f, v] : fs_)
        if (double(f) == frame) return v;
    if (m == 1) return fs_.front().second;
    // The segment [key i, key i + 1] holding the frame (round the loop where it loops).
    long i = 0;
    if (frame < double(fs_.front().first)) {
        if (!a.loop) return fs_.front().second;
        i = -1;
    } else if (frame > double(fs_.back().first)) {
        if (!a.loop) return fs_.back().second;
        i = m - 1;
    } else {
        while (double(fs_[std::size_t(i + 1)].first) < frame) ++i;
    }
    const Near k0 = key_at(a, k, i), k1 = key_at(a, k, i + 1);
    Flat a0, a1;
    flatten(*k0.value, a0);
    flatten(*k1.value, a1);
    const double d = k1.frame - k0.frame;
    const double t = (frame - k0.frame) / d;
    Flat out;
    if (a.interpolation == Interpolation::catmull_rom) {
        const std::vector<double> m0 = slope(a, k, i), m1 = slope(a, k, i + 1);
        const double t2 = t * t, t3 = t2 * t;
        const double h00 = 2 * t3 - 3 * t2 + 1, h10 = t3 - 2 * t2 + t, h01 = -2 * t3 + 3 * t2, h11 = t3 - t2;
        for (std::size_t c = 0; c < a0.v.size(); ++c)
            out.v.push_back(h00 * a0.v[c] + h10 * d * m0[c] + h01 * a1.v[c] + h11 * d * m1[c]);
    } else {
        const double s = a.interpolation == Interpolation::smooth ? t * t * (3 - 2 * t) : t;
        for (std::size_t c = 0; c < a0.v.size(); ++c) out.v.push_back(a0.v[c] + (a1.v[c] - a0.v[c]) * s);
    }
    std::size_t at = 0;
    return rebuild(*k0.value, out, at, k.mark, k.integer);
}

CNode frame_config(const CNode& root, const Animation& a, double frame) {
    CNode c = root;
    for (const auto& k : a.keys)
        override_target(c, k.path, k.mark.str() + ": " + keys_path(k), k.mark) = animated_value(a, k, frame);
    return c;
}

std::string flow_text(const CNode& n) {
    if (n.is_seq()) {
        std::string t = "[";
        for (std::size_t i = 0; i < n.items.size(); ++i) t += (i ? ", " : "") + flow_text(n.items[i]);
        return t + "]";
    }
    if (n.is_scalar()) return n.quoted ? "\"" + n.scalar + "\"" : n.scalar;
    return "null";
}

namespace {

// -o frames/%04d.png: one frame number, %d or %0Nd; %% is a '%'.
struct Pattern {
    std::string text, before, after;
    int width = 0;
    std::string path(long k) const {
        std::string num = std::to_string(k);
        if (int(num.size()) < width) num.insert(0, std::size_t(width) - num.size(), '0');
        return before + num + after;
    }
};

Pattern parse_pattern(const std::string& text) {
    Pattern p;
    p.text = text;
    int conversions = 0;
    const std::string bad = "-o " + quote(text, 200) +
                            ": expected a file name with one frame number, %d or %0Nd, as frames/%04d.png";
    for (std::size_t i = 0; i < text.size(); ++i) {
        std::string& side = conversions ? p.after : p.before;
        if (text[i] != '%') {
            side += text[i];
            continue;
        }
        if (i + 1 < text.size() && text[i + 1] == '%') {
            side += '%', ++i;
            continue;
        }
        std::size_t j = i + 1;
        int width = 0;
        if (j < text.size() && text[j] == '0') {
            ++j;
            if (j >= text.size() || text[j] < '1' || text[j] > '9') throw InputError(bad);
            width = text[j++] - '0';
        }
        if (j >= text.size() || text[j] != 'd' || ++conversions > 1) throw InputError(bad);
        p.width = width;
        i = j;
    }
    if (conversions != 1) throw InputError(bad);
    return p;
}

// --frames A..B (or K), within the animation.
std::pair<long, long> parse_range(const std::string& t, long frames) {
    long a = 0, b = 0;
    const auto dots = t.find("..");
    const bool ok = dots == std::string::npos
                        ? whole_number(t, a) && (b = a, true)
                        : whole_number(t.substr(0, dots), a) && whole_number(t.substr(dots + 2), b);
    if (!ok || a < 0 || b < a || b >= frames)
        throw InputError(
            "--frames " + quote(t, 80) + ": expected A..B (or one frame K) with 0 <= A <= B <= " +
            std::to_string(frames - 1) + " (the animation has " + std::to_string(frames) + " frames)");
    return {a, b};
}

// The config with --set applied, and its animation section.
CNode load_animated(const std::string& config, const std::vector<std::string>& sets) {
    if (is_recipe_image(config))
        throw InputError(config +
                         ": an image's recipe has no animation: section; animate the config it came from");
    CNode root = load_yaml_file(config);
    for (const auto& s : sets) apply_override(root, s);
    if (!has_animation(root))
        throw InputError(root.mark.str() +
                         ": no 'animation:' section (frames, keys: see fixpoint animate --help)");
    return root;
}

Pipeline frame_pipeline(const Registry& reg, const CNode& root, const Animation& a, double k) {
    try {
        return load_pipeline(reg, frame_config(root, a, k));
    } catch (const InputError& e) {
        throw InputError(std::string(e.what()) + " (animation frame " + number_text(k) + ")");
    }
}

// The schema's spec of the parameter at `path` in a validated tree (nullptr: none, as for an
// element of a list, renderer.view[0]).
const ParamSpec* spec_at(const TObject& t, const std::string& path) {
    for (const auto& p : t.params) {
        if (p.path == path) return p.spec;
        if (p.object)
            if (const ParamSpec* s = spec_at(*p.object, path)) return s;
        for (const auto& it : p.items) {
            for (const auto& e : it.extras)
                if (e.path == path) return e.spec;
            if (const ParamSpec* s = spec_at(*it.object, path)) return s;
        }
    }
    return nullptr;
}

// The animation of a config, with frame 0 checked and each key's integer flag from the schema
// (frame 0 holds keyframe values as written: it never depends on that flag).
Animation prepare(const Registry& reg, const CNode& root) {
    Animation a = parse_animation(root);
    frame_pipeline(reg, root, a, 0);
    const CNode c = frame_config(root, a, 0);
    const auto typed = validate(reg, Kind::Renderer, *c.find("renderer"), "renderer");
    for (auto& k : a.keys) {
        const ParamSpec* s = spec_at(*typed, k.path);
        k.integer = s && s->type == ParamType::Int;
    }
    return a;
}

} // namespace

const char* animate_help() {
    return R"(
The animation: section, at the top level of the config beside renderer: and output::

  animation:
    frames: 120                  # frames 0 .. 119
    fps: 30                      # of --video (default 30)
    interpolation: smooth        # linear (default), smooth or catmull-rom
    loop: true                   # periodic: the last key runs on into the first (default false)
    temporal_samples: 4          # motion blur: samples a frame (default 1: none)
    temporal_filter_width: 1     # the frames a frame's samples span (default 1)
    keys:                        # a path as --set takes it: {frame: value, ...}
      renderer.iteration.alpha: {0: 0.5, 60: 0.7, 119: 0.9}
      renderer.view: {0: [-2, 2, -2, 2], 119: [-1, 1, -1, 1]}
      renderer.maps[0].colour: {0: "#ff6b6b", 119: [0.2, 0.4, 1]}

Frame k is the config with each key's value at frame k set exactly as --set path=value sets it
(--list prints them). At a keyframe the value is the one written; before the first and after
the last keyframe it stays; between keyframes f0 < f1, with t = (f - f0) / (f1 - f0), it is
a + (b - a) * s, s = t (linear) or s = t*t*(3 - 2t) (smooth: smoothstep, easing in and out of
each key without overshoot). catmull-rom: the cubic through the keys whose slope at each key
is its neighbours' secant, smooth through the keys but free to overshoot between them. loop:
true repeats the keys every `frames` frames, the last keyframe running on into the first
(catmull-rom's neighbours taken round the loop), so frame `frames` would be frame 0 and the
video loops without a seam. Numbers, lists of numbers (elementwise) and colours ("#rrggbb"
as [r, g, b] in [0, 1], interpolated componentwise as given, i.e. sRGB-encoded, not in linear
light). A parameter that is an integer in its plugin's schema (points, seed, ...) is rounded
to the nearest integer between keys, halves away from zero; every other number is real.

The same seed and chains render every frame (nothing is reseeded), so the pattern does not
flicker. Each frame carries its recipe: fixpoint render FRAME.png renders it again, byte for
byte. A frame whose file exists with the same recipe is skipped (said in the log), so an
interrupted run continues when run again; a file with another recipe is refused without
--force. Everything is checked before the first render. render and validate of such a config
render (check) the config as it stands, ignoring the animation; validate also checks every
frame.

Motion blur (flam3's temporal_samples S and temporal_filter_width w, its box filter): frame f
sums the histograms of S renders, sample j at time f + w ((j + 1/2) / S - 1/2) (the keys
interpolated there as at a frame), each of its own share j of S of the chains, and finishes
the sum with frame f's tone. Each chain runs once, at one time, so a frame that does not
move is its plain render, pixel for pixel, at the same cost; a moving one holds the whole
shutter. It needs a renderer that keeps a histogram (chaos-game). A blurred frame's recipe is
its frame's with a line naming the samples: fixpoint render FRAME.png renders it unblurred
(the samples' configs are the animation's).

  fixpoint animate configs/animation/fig4-centres.yaml -o frames/%04d.png --video fig4.mp4
  fixpoint animate configs/animation/fig4-centres.yaml --list --frames 40..47
)";
}

// Every frame's config checked; Ctrl-C polled between frames (an animation may have 100 000).
void check_frames(const Registry& reg, const CNode& root, const Animation& a,
                  const std::atomic<bool>* interrupted) {
    for (long k = 0; k < a.frames; ++k) {
        if (interrupted && interrupted->load()) throw Cancelled();
        frame_pipeline(reg, root, a, k);
    }
}

std::string validate_animation(const Registry& reg, const std::string& config,
                               const std::vector<std::string>& sets, const std::atomic<bool>* interrupted) {
    if (is_recipe_image(config)) return "";
    CNode root = load_yaml_file(config);
    for (const auto& s : sets) apply_override(root, s);
    if (!has_animation(root)) return "";
    const Animation a = prepare(reg, root);
    check_frames(reg, root, a, interrupted);
    return "an animation of " + std::to_string(a.frames) + " frame" + (a.frames == 1 ? "" : "s") + " (" +
           std::to_string(a.keys.size()) + " key" + (a.keys.size() == 1 ? "" : "s") + ")";
}

int animate(const Registry& reg, const AnimateOptions& o, const RenderHooks& hooks) {
    const std::atomic<bool>* interrupted = hooks.cancel;
    const auto info = [&](const std::string& s) {
        if (!o.quiet && o.info) o.info(s);
    };
    const CNode root = load_animated(o.config, o.sets);
    const Animation a = prepare(reg, root);
    const auto [first, last] =
        o.frames.empty() ? std::pair<long, long>{0, a.frames - 1} : parse_range(o.frames, a.frames);
    if (o.list) {
        // Every frame is checked first: a listing is of frames that render.
        check_frames(reg, root, a, interrupted);
        for (long k = first; k <= last; ++k) {
            std::string line = std::to_string(k);
            for (const auto& key : a.keys)
                line += " " + key.path + "=" + flow_text(animated_value(a, key, k));
            std::printf("%s\n", line.c_str());
        }
        return 0;
    }
    if (o.pattern.empty())
        throw InputError("animate: -o is required (the frames' file names, as frames/%04d.png)");
    const Pattern pat = parse_pattern(o.pattern);
    const Format fmt = format_for(pat.path(0));
    if (is_vector(fmt))
        throw InputError("-o " + quote(o.pattern, 200) + ": frames are written as .png, .exr or .tif images");
    if (!o.video.empty()) check_video(o.video, o.config, o.force);

    // Every frame: its config checked, its render planned (memory, tiles, its file), or its file
    // skipped (there with this recipe) or refused (another recipe, unless --force). A frame's
    // folder is made by the job just before the frame is written.
    std::vector<bool> skip(std::size_t(last - first + 1), false);
    const auto request = [&](const std::string& out) {
        RenderRequest r;
        r.output = out;
        r.force = true; // (an existing frame file is decided here: skipped, refused or replaced)
        r.make_folder = true;
        r.source = o.config;
        r.threads = o.threads;
        return r;
    };
    bool warned = false;
    for (long k = 0; k < a.frames; ++k) {
        Pipeline p = frame_pipeline(reg, root, a, k);
        if (!warned && o.warn)
            for (const auto& w : p.warnings) o.warn("warning: " + w);
        if (!warned) check_motion_blur(a, p);
        warned = true;
        p.recipe = blurred_recipe(a, p);
        if (k < first || k > last) continue;
        const std::string out = pat.path(k);
        std::error_code ec;
        if (fs::equivalent(out, o.config, ec))
            throw InputError("cannot write " + quote(out, 200) + ": it is the config being animated");
        if (fs::exists(fs::symlink_status(out, ec))) {
            std::string have;
            try {
                have = read_recipe(out);
            } catch (const InputError&) {
            }
            if (have == p.recipe)
                skip[std::size_t(k - first)] = true;
            else if (!o.force)
                throw InputError(quote(out, 200) + " exists and is not frame " + std::to_string(k) +
                                 " of this animation (another recipe): add --force to replace it");
        }
        if (!skip[std::size_t(k - first)]) (void)plan_render(p, request(out));
        if (interrupted && interrupted->load()) throw Cancelled();
    }

    long rendered = 0, skipped = 0;
    double total = 0;
    for (long k = first; k <= last; ++k) {
        const std::string out = pat.path(k);
        if (skip[std::size_t(k - first)]) {
            ++skipped;
            info(out + ": frame " + std::to_string(k) + " is there with this recipe: skipped");
            continue;
        }
        Pipeline p = frame_pipeline(reg, root, a, k);
        p.recipe = blurred_recipe(a, p);
        RenderResult r;
        if (a.temporal_samples > 1) {
            r = render_blurred_frame(
                a, k, [&](double t) { return frame_pipeline(reg, root, a, t); }, p, request(out), hooks);
        } else {
            RenderPlan plan = plan_render(p, request(out));
            r = run_render(plan, hooks);
        }
        if (o.warn)
            for (const auto& w : r.warnings) o.warn("warning: " + w);
        ++rendered;
        total += r.seconds;
        info(out + ": frame " + std::to_string(k) + " of " + std::to_string(first) + ".." +
             std::to_string(last) + ", " + std::to_string(r.stats.samples) + " " + r.stats.unit + " in " +
             number_text(std::round(r.seconds * 100) / 100) + " s");
    }
    info(std::to_string(rendered) + " frame" + (rendered == 1 ? "" : "s") + " rendered in " +
         number_text(std::round(total * 100) / 100) + " s, " + std::to_string(skipped) + " skipped (" +
         pat.path(first) + " ... " + pat.path(last) + ")");
    if (!o.video.empty()) {
        make_video(pat.text, first, last - first + 1, a.fps, o.video, interrupted);
        info(o.video + ": " + std::to_string(last - first + 1) + " frames at " + number_text(a.fps) + " fps");
    }
    return 0;
}

} // namespace fp::host
