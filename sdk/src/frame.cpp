#include <fixpoint/errors.hpp>
#include <fixpoint/frame.hpp>

#include <cstdint>

namespace fp {

Frame Frame::read(const ParamBag& p, const std::string& region_param) {
    Frame f;
    f.width = int(p.integer("width"));
    f.height = int(p.integer("height"));
    if (std::uint64_t(f.width) * std::uint64_t(f.height) >= 0xffffffffull)
        throw ParamError("height", "the image is too large: width * height must be below 4294967295 pixels");
    if (p.has(region_param)) {
        const auto& v = p.reals(region_param);
        const std::string must = "the " + region_param + " must be [xmin, xmax, ymin, ymax]";
        if (v.size() != 4) throw ParamError(region_param, must);
        if (!(v[0] < v[1])) throw ParamError(region_param, must + " with xmin < xmax");
        if (!(v[2] < v[3])) throw ParamError(region_param, must + " with ymin < ymax");
        f.region = {v[0], v[1], v[2], v[3]};
        f.has_region = true;
    }
    if (p.has("background")) {
        f.background = p.colour("background");
        f.has_background = true;
    }
    return f;
}

} // namespace fp
