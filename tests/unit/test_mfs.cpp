// The mfs renderer (paper 05): multiple function systems of subdivision maps, paths,
// placements (Proposition 1, Algorithm 2) and addresses (Algorithm 1).
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/host/core/runtime.hpp>

#include "host.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

namespace {

// Example 1's quad maps f_1 .. f_9 (F^1_0 = all, F^1_1 = all but f_5) and triangle maps
// f_1 .. f_4 (F^2_0 = all, F^2_1 = f_1, f_3, f_4), with the paper's S and points.
const char* quad_S[] = {
    "[9, 0, 0, 0, 6, 3, 0, 0, 6, 0, 3, 0, 4, 2, 2, 1]", "[6, 3, 0, 0, 3, 6, 0, 0, 4, 2, 2, 1, 2, 4, 1, 2]",
    "[3, 6, 0, 0, 0, 9, 0, 0, 2, 4, 1, 2, 0, 6, 0, 3]", "[6, 0, 3, 0, 4, 2, 2, 1, 3, 0, 6, 0, 2, 1, 4, 2]",
    "[4, 2, 2, 1, 2, 4, 1, 2, 2, 1, 4, 2, 1, 2, 2, 4]", "[2, 4, 1, 2, 0, 6, 0, 3, 1, 2, 2, 4, 0, 3, 0, 6]",
    "[3, 0, 6, 0, 2, 1, 4, 2, 0, 0, 9, 0, 0, 0, 6, 3]", "[2, 1, 4, 2, 1, 2, 2, 4, 0, 0, 6, 3, 0, 0, 3, 6]",
    "[1, 2, 2, 4, 0, 3, 0, 6, 0, 0, 3, 6, 0, 0, 0, 9]"};
const char* tri_S[] = {"[2, 0, 0, 1, 1, 0, 1, 0, 1]", "[1, 1, 0, 0, 1, 1, 1, 0, 1]",
                       "[1, 1, 0, 0, 2, 0, 0, 1, 1]", "[1, 0, 1, 0, 1, 1, 0, 0, 2]"};

// The `maps:` of one subdivision per matrix of `S`, all with `divisor` and `points`; map `only0`
// (from 1) belongs to system 0 alone, the others to systems 0 and 1.
template <std::size_t N>
std::string subdivision_maps(const char* (&S)[N], int only0, const std::string& divisor,
                             const std::string& points) {
    std::string s = "maps: [";
    for (int i = 1; i <= int(N); ++i)
        s += std::string(i > 1 ? ", " : "") +
             "{type: subdivision, systems: " + (i == only0 ? "[0]" : "[0, 1]") + ", divisor: " + divisor +
             ", points: " + points + ", S: " + S[i - 1] + "}";
    return s + "]";
}
std::string quad_maps() { return subdivision_maps(quad_S, 5, "9", "[[0, 0], [1, 0], [0, 1], [1, 1]]"); }
std::string tri_maps() {
    return subdivision_maps(tri_S, 2, "2", "[[0, 0], [1, 0], [0.5, 0.6666666666666666]]");
}

std::shared_ptr<const fp::Renderer> make(const std::string& body) {
    return fp::test::host().make<fp::Renderer>("{type: mfs, " + body + "}");
}

struct Poly {
    std::string address;
    std::vector<fp::Vec2> v;
};

std::vector<Poly> polygons(const std::string& body, std::int64_t level = -1) {
    std::vector<Poly> out;
    for (const auto& line : make(body)->polygon_addresses(level)) {
        Poly p;
        std::istringstream in(line);
        in >> p.address;
        char c;
        double x, y;
        while (in >> c >> x >> c >> y >> c) p.v.push_back({x, y});
        out.push_back(p);
    }
    return out;
}

fp::Image render(const std::string& body, fp::RenderStats* st = nullptr, unsigned threads = 2) {
    auto r = make(body);
    fp::host::Runtime rt(threads, nullptr);
    fp::RenderStats stats;
    auto img = r->render(rt, stats);
    if (st) *st = stats;
    return img;
}

std::vector<char> lit(const fp::Image& img, float threshold = 0.5f) {
    std::vector<char> out(std::size_t(img.width) * std::size_t(img.height));
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = img.pixels[3 * i] > threshold;
    return out;
}

// Pixels lit in a with no lit pixel of b within `r` pixels.
std::size_t unmatched(const std::vector<char>& a, const std::vector<char>& b, int w, int h, int r) {
    std::size_t n = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            if (!a[std::size_t(y * w + x)]) continue;
            bool near = false;
            for (int dy = -r; dy <= r && !near; ++dy)
                for (int dx = -r; dx <= r && !near; ++dx) {
                    const int X = x + dx, Y = y + dy;
                    near = X >= 0 && Y >= 0 && X < w && Y < h && b[std::size_t(Y * w + X)];
                }
            n += !near;
        }
    return n;
}

TEST(Mfs, PolygonCountsAlongPaths) {
    EXPECT_EQ(polygons(quad_maps() + ", path: [0, 0, 0]").size(), 729u);  // 9^3, F^1_0
    EXPECT_EQ(polygons(quad_maps() + ", path: [1, 1, 1]").size(), 512u);  // 8^3, F^1_1
    EXPECT_EQ(polygons(quad_maps() + ", path: [0, 1, 0]").size(), 648u);  // 9 * 8 * 9
    EXPECT_EQ(polygons(tri_maps() + ", path: [0, 0, 0]").size(), 64u);    // 4^3, F^2_0
    EXPECT_EQ(polygons(tri_maps() + ", path: [1, 1, 1, 1]").size(), 81u); // 3^4, F^2_1
    EXPECT_EQ(polygons(quad_maps() + ", path: [1, 1, 1]", 2).size(), 64u);
    fp::RenderStats st;
    render("width: 64, height: 64, " + quad_maps() + ", path: [1, 1, 1, 1]", &st);
    EXPECT_EQ(st.samples, 4096u); // 8^4
    EXPECT_EQ(st.drawn, 4096u);
}

// Addresses are the paper's labels: level 1 of F^1_0 lists the ninths 1..9 (1 2 3 the bottom
// row); 2.5 is the centre of ninth 2.
TEST(Mfs, Addresses) {
    const auto l1 = polygons(quad_maps() + ", path: [0]");
    ASSERT_EQ(l1.size(), 9u);
    for (int i = 0; i < 9; ++i) {
        EXPECT_EQ(l1[std::size_t(i)].address, std::to_string(i + 1));
        EXPECT_NEAR(l1[std::size_t(i)].v[0].x, double(i % 3) / 3, 1e-6);
        EXPECT_NEAR(l1[std::size_t(i)].v[0].y, double(i / 3) / 3, 1e-6);
    }
    const auto l2 = polygons(quad_maps() + ", path: [0, 0], only: \"2.5\"");
    ASSERT_EQ(l2.size(), 1u);
    EXPECT_EQ(l2[0].address, "2.5");
    EXPECT_NEAR(l2[0].v[0].x, 1.0 / 3 + 1.0 / 9, 1e-6);
    EXPECT_NEAR(l2[0].v[0].y, 1.0 / 9, 1e-6);
    EXPECT_NEAR(l2[0].v[3].x, 1.0 / 3 + 2.0 / 9, 1e-6);
    EXPECT_NEAR(l2[0].v[3].y, 2.0 / 9, 1e-6);
}

// Proposition 1: with P replaced by P' (an affine image T of P) and S kept, every polygon is
// the image under T of the polygon with the same address.
TEST(Mfs, Proposition1PlacedFractalIsAffineImage) {
    // T(x, y) = (2x - 0.5y + 3, 0.25x + 1.5y - 1).
    auto T = [](fp::Vec2 p) { return fp::Vec2{2 * p.x - 0.5 * p.y + 3, 0.25 * p.x + 1.5 * p.y - 1}; };
    struct Case {
        std::string maps, path;
        std::vector<fp::Vec2> P;
    };
    const std::vector<Case> cases = {
        {tri_maps(), "[1, 1, 1, 1]", {{0, 0}, {1, 0}, {0.5, 2.0 / 3}}},
        {quad_maps(), "[1, 0, 1]", {{0, 0}, {1, 0}, {0, 1}, {1, 1}}},
    };
    for (const auto& c : cases) {
        std::string pts = "points: [";
        for (std::size_t k = 0; k < c.P.size(); ++k) {
            const fp::Vec2 q = T(c.P[k]);
            char buf[96];
            std::snprintf(buf, sizeof buf, "%s[%.17g, %.17g]", k ? ", " : "", q.x, q.y);
            pts += buf;
        }
        pts += "]";
        const auto a = polygons(c.maps + ", path: " + c.path);
        const auto b = polygons(c.maps + ", path: " + c.path + ", " + pts);
        ASSERT_EQ(a.size(), b.size());
        for (std::size_t i = 0; i < a.size(); ++i) {
            ASSERT_EQ(a[i].address, b[i].address);
            for (std::size_t k = 0; k < a[i].v.size(); ++k) {
                const fp::Vec2 t = T(a[i].v[k]);
                EXPECT_NEAR(b[i].v[k].x, t.x, 2e-5 * (1 + std::fabs(t.x))) << a[i].address;
                EXPECT_NEAR(b[i].v[k].y, t.y, 2e-5 * (1 + std::fabs(t.y))) << a[i].address;
            }
        }
    }
}

// Every point of a placed fractal lies inside its polygon: the triangle carpet placed at
// address 5 (then at 2.5) and nothing else drawn lights only pixels of that quad.
TEST(Mfs, PlacedFractalStaysInItsPolygon) {
    const std::string tri =
        "{type: mfs, at: \"ADDR\", path: [1, 1, 1, 1], colour: [1, 1, 1], " + tri_maps() + "}";
    struct Case {
        std::string at;
        double x0, y0, size; // the quad in world coordinates
    };
    for (const Case& c : {Case{"5", 1.0 / 3, 1.0 / 3, 1.0 / 3}, Case{"2.5", 4.0 / 9, 1.0 / 9, 1.0 / 9}}) {
        std::string placed = tri;
        placed.replace(placed.find("ADDR"), 4, c.at);
        const int W = 162;
        const auto img =
            render("width: 162, height: 162, view: [0, 1, 0, 1], background: [0, 0, 0], draw_target: "
                   "false, path: [1], " +
                   quad_maps() + ", placements: [" + placed + "]");
        const auto on = lit(img, 0.0f);
        std::size_t inside = 0, outside = 0;
        for (int y = 0; y < W; ++y)
            for (int x = 0; x < W; ++x) {
                if (!on[std::size_t(y * W + x)]) continue;
                // Pixel (x, y) covers world [x / W, (x + 1) / W] x [1 - (y + 1) / W, 1 - y / W].
                const double wx0 = double(x) / W, wx1 = double(x + 1) / W;
                const double wy1 = 1 - double(y) / W, wy0 = 1 - double(y + 1) / W;
                const bool in = wx1 > c.x0 && wx0 < c.x0 + c.size && wy1 > c.y0 && wy0 < c.y0 + c.size;
                (in ? inside : outside) += 1;
            }
        EXPECT_EQ(outside, 0u) << c.at;
        EXPECT_GT(inside, std::size_t(0.2 * c.size * c.size * W * W)) << c.at;
    }
}

// The chaos game over the IFS F^1_1 (the subdivision maps as plane maps, in the chaos-game
// renderer) lands on the attractor the deterministic path (1, 1, 1, 1) approximates: on an
// 81 x 81 image of the unit square a level-4 quad is one pixel, and the chaos game lights
// exactly those pixels (within a pixel at cell edges, where a point's pixel is a rounding
// matter), and nearly all of them. (At level 3 the 512 one-pixel holes of level 4 show up as
// exactly 512 pixels the chaos game never reaches.)
TEST(Mfs, ChaosGameLandsOnTheSameAttractor) {
    // The eight maps of F^1_1 for the chaos game.
    std::string cg = "maps: [";
    for (int i = 1, k = 0; i <= 9; ++i)
        if (i != 5)
            cg += std::string(k++ ? ", " : "") +
                  "{type: subdivision, divisor: 9, points: [[0, 0], [1, 0], [0, 1], [1, 1]], S: " +
                  quad_S[i - 1] + "}";
    cg += "]";
    const int W = 81;
    auto chaos = fp::test::host().make<fp::Renderer>(
        "{type: chaos-game, width: 81, height: 81, view: [0, 1, 0, 1], points: 400000, chains: 256, "
        "precision: double, " +
        cg + "}");
    fp::host::Runtime rt(2, nullptr);
    fp::RenderStats st;
    const auto a = lit(chaos->render(rt, st), 0.0f);
    const auto b =
        lit(render("width: 81, height: 81, view: [0, 1, 0, 1], background: [0, 0, 0], colour: [1, 1, 1], "
                   "path: [1, 1, 1, 1], " +
                   quad_maps()),
            0.5f);
    std::size_t na = 0, nb = 0;
    for (char c : a) na += c;
    for (char c : b) nb += c;
    ASSERT_GT(na, 1000u);
    EXPECT_EQ(nb, 4096u);                          // 8^4 one-pixel quads
    EXPECT_EQ(unmatched(a, b, W, W, 1), 0u);       // chaos game inside the level-4 union
    EXPECT_LT(unmatched(b, a, W, W, 0), nb / 100); // and covering it
}

// The same recipe gives the same pixels on any number of threads.
TEST(Mfs, Deterministic) {
    const std::string body = "width: 96, height: 96, colour_by: address, " + quad_maps() +
                             ", path: [1, 1], placements: [{type: mfs, at: \"5\", path: [1, 1], " +
                             tri_maps() + "}]";
    EXPECT_EQ(render(body, nullptr, 1).pixels, render(body, nullptr, 3).pixels);
}

TEST(Mfs, PlacementsReplaceTargetPolygons) {
    fp::RenderStats st;
    // Level 1 of F^1_0 (9 quads), quads 1 and 9 replaced by 2 x 27 triangles each; 5 hidden.
    render("width: 32, height: 32, path: [0], hide: \"5\", " + quad_maps() +
               ", placements: [{type: mfs, at: \"1; 9\", path: [1, 1, 1], " + tri_maps() + "}]",
           &st);
    EXPECT_EQ(st.samples, 6u + 2u * 2u * 27u);
}

} // namespace
