// Drafts (see fixpoint/host/job/draft.hpp).
#include <fixpoint/host/core/build.hpp>
#include <fixpoint/host/job/draft.hpp>

#include <algorithm>
#include <charconv>
#include <cstdint>

namespace fp::host {

namespace {

// The integer a recipe writes for `key` in the renderer's mapping, if it writes one there (mfs
// has a `points` too: a list of points, left alone).
bool integer_at(const CNode& renderer, const char* key, long double& out) {
    const CNode* n = renderer.find(key);
    if (!n || !n->is_scalar() || n->quoted) return false;
    // Recipes write large counts in exponent form (1e+08): read as a number, kept integral.
    const std::string& s = n->scalar;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    (void)end;
    return ec == std::errc();
}

std::string integer_text(long double v) { return std::to_string(static_cast<long long>(v)); }

} // namespace

std::vector<std::string> draft_overrides(const Pipeline& full, int factor) {
    if (factor <= 1) return {};
    std::vector<std::string> sets;
    const int w = full.renderer->width(), h = full.renderer->height();
    sets.push_back("renderer.width=" + std::to_string(std::max(1, w / factor)));
    sets.push_back("renderer.height=" + std::to_string(std::max(1, h / factor)));
    // The recipe has every default filled in: the counts are there whether the config wrote
    // them or not.
    const CNode recipe = parse_yaml(full.recipe, "recipe");
    const CNode* r = recipe.find("renderer");
    if (!r || !r->is_map()) return sets;
    const long double area = static_cast<long double>(factor) * factor;
    long double v = 0;
    // What the renderer declares of its parameters (fp::ParamRole): the work in proportion to
    // the pixels, so that a pixel of the draft gets about the points a pixel of the full render
    // gets and the tone mapping sees the same densities; one sample per pixel (its pixels are
    // already factor^2 fewer).
    const PluginDescriptor& d = *full.renderer_plugin->desc;
    for (std::uint32_t i = 0; i < d.n_params; ++i) {
        const ParamSpec& s = d.params[i];
        if (s.type != ParamType::Int || !integer_at(*r, s.name, v)) continue;
        if (s.role == ParamRole::work)
            sets.push_back("renderer." + std::string(s.name) + "=" +
                           integer_text(std::max<long double>(1, v / area)));
        else if (s.role == ParamRole::samples && v > 1)
            sets.push_back("renderer." + std::string(s.name) + "=1");
    }
    return sets;
}

std::vector<int> preview_factors(int width, int height) {
    std::vector<int> f;
    const int side = std::max(width, height);
    for (int k : {8, 4, 2})
        if (side / k >= 32) f.push_back(k);
    f.push_back(1);
    return f;
}

double samples_per_pixel(const RenderStats& stats, int width, int height) {
    const double pixels = double(width) * double(height);
    return pixels > 0 ? double(stats.samples) / pixels : 0.0;
}

} // namespace fp::host
