// Measures of a rendered pattern (see measures.hpp).
#include <fixpoint/host/tools/measures.hpp>

#include <algorithm>
#include <array>
#include <cmath>

namespace fp::host {

std::vector<unsigned char> lit_pixels(const Image& img, Rgb background) {
    const std::size_t n = std::size_t(img.width) * std::size_t(img.height);
    std::vector<unsigned char> lit(n, 0);
    const std::size_t ch = std::size_t(std::max(img.channels, 1));
    const float bg[3] = {background.r, background.g, background.b};
    const float tol = 0.5f / 255.0f;
    for (std::size_t i = 0; i < n && i * ch < img.pixels.size(); ++i)
        for (std::size_t c = 0; c < std::min<std::size_t>(ch, 3); ++c)
            if (std::fabs(img.pixels[i * ch + c] - bg[ch >= 3 ? c : 0]) > tol) {
                lit[i] = 1;
                break;
            }
    return lit;
}

double coverage(const Image& img, Rgb background) {
    const auto lit = lit_pixels(img, background);
    if (lit.empty()) return 0;
    std::size_t k = 0;
    for (unsigned char v : lit) k += v;
    return double(k) / double(lit.size());
}

double grey_entropy(const Image& img) {
    const std::size_t n = std::size_t(img.width) * std::size_t(img.height);
    const std::size_t ch = std::size_t(std::max(img.channels, 1));
    if (n == 0 || img.pixels.size() < n * ch) return 0;
    std::array<std::size_t, 256> hist{};
    for (std::size_t i = 0; i < n; ++i) {
        const float* p = &img.pixels[i * ch];
        const double g = ch >= 3 ? 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2] : p[0];
        const double c = std::isfinite(g) ? std::clamp(g, 0.0, 1.0) : 0.0;
        ++hist[std::size_t(std::lround(c * 255))];
    }
    double h = 0;
    for (std::size_t k : hist)
        if (k) {
            const double p = double(k) / double(n);
            h -= p * std::log2(p);
        }
    return h;
}

double box_dimension(const std::vector<unsigned char>& lit, int width, int height) {
    if (width <= 0 || height <= 0 || lit.size() < std::size_t(width) * std::size_t(height)) return 0;
    // The lit set's extent: boxes above a quarter of it count mostly its edge ((L/s + 1)^2
    // boxes for a filled square of side L), so they are left out (but 2, 4 and 8 always count).
    int x0 = width, x1 = -1, y0 = height, y1 = -1;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            if (lit[std::size_t(y) * std::size_t(width) + std::size_t(x)])
                x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    if (x1 < 0) return 0;
    const int top = std::max(8, std::max(x1 - x0 + 1, y1 - y0 + 1) / 4);
    std::vector<double> xs, ys;
    for (int s = 2; s <= 64 && s <= top && s <= std::max(width, height); s *= 2) {
        const int bw = (width + s - 1) / s, bh = (height + s - 1) / s;
        std::vector<unsigned char> box(std::size_t(bw) * std::size_t(bh), 0);
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x)
                if (lit[std::size_t(y) * std::size_t(width) + std::size_t(x)])
                    box[std::size_t(y / s) * std::size_t(bw) + std::size_t(x / s)] = 1;
        std::size_t count = 0;
        for (unsigned char b : box) count += b;
        if (count == 0) return 0;
        xs.push_back(std::log(double(s)));
        ys.push_back(std::log(double(count)));
    }
    if (xs.size() < 2) return 0;
    double mx = 0, my = 0;
    for (std::size_t i = 0; i < xs.size(); ++i) mx += xs[i], my += ys[i];
    mx /= double(xs.size());
    my /= double(xs.size());
    double sxy = 0, sxx = 0;
    for (std::size_t i = 0; i < xs.size(); ++i) {
        sxy += (xs[i] - mx) * (ys[i] - my);
        sxx += (xs[i] - mx) * (xs[i] - mx);
    }
    return -sxy / sxx;
}

double box_dimension(const Image& img, Rgb background) {
    return box_dimension(lit_pixels(img, background), img.width, img.height);
}

double coverage_score(double c) {
    if (!(c > 0.002)) return 0;
    if (c < 0.02) return std::log(c / 0.002) / std::log(10.0);
    if (c <= 0.6) return 1;
    return std::clamp((1 - c) / 0.4, 0.0, 1.0);
}

double entropy_score(double bits) { return std::isfinite(bits) ? std::clamp(bits / 6, 0.0, 1.0) : 0; }

double dimension_score(double d) {
    if (!std::isfinite(d)) return 0;
    if (d < 1.3) return std::clamp((d - 0.5) / 0.8, 0.0, 1.0);
    if (d <= 1.8) return 1;
    return std::clamp((2 - d) / 0.2, 0.0, 1.0);
}

double lyapunov_score(double l) {
    if (std::isnan(l)) return 0;
    return 1 / (1 + std::exp(-std::clamp(l / 0.05, -700.0, 700.0)));
}

} // namespace fp::host
