// The golden corpus: recipes across every renderer, colour path, scheme and precision, with the
// SHA-256 of each image's pixels (SHA256SUMS). An image's bytes are a function of its recipe and
// of the render version (host/core/render_version.hpp); this program holds the build to that.
//
//   fixpoint_golden DIR            render every DIR/*.yaml, compare with DIR/SHA256SUMS
//                                  (FIXPOINT_SIMD=T: on instruction set T, as the CLI's --simd)
//   fixpoint_golden DIR --record   write the hashes that changed, each at this build's render
//                                  version: refused for a recipe whose pixels changed while the
//                                  version stayed, or whose plugins no change since names
//
// The hash covers the float pixels the renderer made and the 8- or 16-bit values a PNG of the
// recipe stores (the host's quantisation), after the image's size. Renders run in this process,
// on two threads, whole (the tests of strips, threads, targets and ranks prove those give the
// same bytes). SHA256SUMS: one line per recipe, "HASH  VERSION  NAME.yaml", sorted by name.
#include <fixpoint/errors.hpp>
#include <fixpoint/host/core/config.hpp>
#include <fixpoint/host/core/host.hpp>
#include <fixpoint/host/core/pipeline.hpp>
#include <fixpoint/host/core/render_version.hpp>
#include <fixpoint/host/job/render_job.hpp>
#include <fixpoint/simd.hpp>

#include <openssl/evp.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace fp::host;

namespace {

struct Recorded {
    std::string hash;
    int version = 0;
};

std::string sha256(const std::vector<unsigned char>& bytes) {
    unsigned char md[EVP_MAX_MD_SIZE];
    unsigned len = 0;
    if (!EVP_Digest(bytes.data(), bytes.size(), md, &len, EVP_sha256(), nullptr))
        throw std::runtime_error("OpenSSL's SHA-256 failed");
    std::string hex;
    char b[3];
    for (unsigned i = 0; i < len; ++i) {
        std::snprintf(b, sizeof b, "%02x", md[i]);
        hex += b;
    }
    return hex;
}

template <class T>
void append(std::vector<unsigned char>& out, const T* p, std::size_t n) {
    // (Little-endian on every machine we build for; the values are hashed as stored.)
    const auto* c = reinterpret_cast<const unsigned char*>(p);
    out.insert(out.end(), c, c + n * sizeof(T));
}

/// The recipe's render, the names of its plugins and the recipe as recorded (what the
/// changelog's params read).
std::string pixel_hash(const Registry& reg, const fs::path& recipe, std::vector<std::string>& plugins,
                       CNode& rec) {
    // (The corpus is ours: a python-scheme in it may run.)
    const Pipeline p = load_pipeline(reg, recipe.string(), {}, "", true);
    rec = parse_config(p.recipe, "recipe");
    if (const CNode* used = rec.find("plugins"))
        for (const auto& kv : used->keys) plugins.push_back(kv.first);
    RenderRequest r;
    r.keep_image = true;
    r.threads = 2;
    RenderPlan plan = plan_render(p, r);
    const RenderResult res = run_render(plan);
    const fp::Image& img = res.image;
    std::vector<unsigned char> bytes;
    const std::int32_t size[3] = {img.width, img.height, img.channels};
    append(bytes, size, 3);
    append(bytes, img.pixels.data(), img.pixels.size());
    if (p.bit_depth == 8) {
        std::vector<std::uint8_t> q(img.pixels.size());
        quantise_pixels(img, 8, q.data());
        append(bytes, q.data(), q.size());
    } else {
        std::vector<std::uint16_t> q(img.pixels.size());
        quantise_pixels(img, 16, q.data());
        append(bytes, q.data(), q.size());
    }
    return sha256(bytes);
}

std::map<std::string, Recorded> read_sums(const fs::path& file) {
    std::map<std::string, Recorded> out;
    std::ifstream in(file);
    std::string hash, name;
    int version = 0;
    while (in >> hash >> version >> name) out[name] = {hash, version};
    return out;
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 2 || argc > 3 || (argc == 3 && std::string(argv[2]) != "--record")) {
        std::fprintf(stderr, "usage: fixpoint_golden DIR [--record]\n");
        return 2;
    }
    // FIXPOINT_SIMD pins the kernels to one instruction set, as for the CLI (every-target.sh).
    if (const char* t = std::getenv("FIXPOINT_SIMD"); t && *t && !fp::simd::force_target(t)) {
        std::fprintf(stderr, "fixpoint_golden: FIXPOINT_SIMD: %s is not an instruction set of this CPU\n", t);
        return 2;
    }
    const fs::path dir = argv[1];
    const bool record = argc == 3;
    const int now = render_version();
    try {
        const Host host;
        const auto sums = read_sums(dir / "SHA256SUMS");
        std::vector<fs::path> recipes;
        for (const auto& e : fs::directory_iterator(dir))
            if (e.path().extension() == ".yaml") recipes.push_back(e.path());
        std::sort(recipes.begin(), recipes.end());
        int failed = 0, changed = 0;
        std::map<std::string, Recorded> out;
        for (const auto& path : recipes) {
            const std::string name = path.filename().string();
            std::vector<std::string> plugins;
            CNode rec;
            std::string hash;
            try {
                hash = pixel_hash(host.registry(), path, plugins, rec);
            } catch (const fp::Error& e) {
                std::fprintf(stderr, "%s: does not render: %s\n", name.c_str(), e.what());
                ++failed;
                continue;
            }
            const auto it = sums.find(name);
            if (it != sums.end() && it->second.hash == hash) {
                out[name] = it->second;
                continue;
            }
            if (it == sums.end()) {
                if (!record) {
                    std::fprintf(stderr,
                                 "%s: no hash recorded in SHA256SUMS (run fixpoint_golden DIR --record)\n",
                                 name.c_str());
                    ++failed;
                }
                out[name] = {hash, now};
                ++changed;
                continue;
            }
            const Recorded& was = it->second;
            std::string why;
            if (was.version >= now)
                why = "its pixels changed, but the render version is still " + std::to_string(now) +
                      ": add a version to framework/render-versions.yaml naming what changed "
                      "(docs/render-versions.md), then record";
            else if (changes_since(was.version, plugins, params_of(rec)).empty())
                why = "its pixels changed, but no change after render version " +
                      std::to_string(was.version) +
                      " in framework/render-versions.yaml touches it (names its plugins, and the "
                      "parameters it has)";
            if (!record || !why.empty()) {
                std::fprintf(stderr, "%s: pixels %s, recorded %s at render version %d%s%s\n", name.c_str(),
                             hash.c_str(), was.hash.c_str(), was.version, why.empty() ? "" : ": ",
                             why.c_str());
                ++failed;
                out[name] = was;
                continue;
            }
            out[name] = {hash, now};
            ++changed;
        }
        for (const auto& [name, r] : sums)
            if (!fs::exists(dir / name)) {
                std::fprintf(stderr, "%s: in SHA256SUMS but not in %s\n", name.c_str(), dir.c_str());
                ++failed;
            }
        if (record && changed > 0 && failed == 0) { // (all or nothing)
            const fs::path tmp = dir / "SHA256SUMS.tmp";
            {
                std::ofstream f(tmp);
                for (const auto& [name, r] : out) f << r.hash << "  " << r.version << "  " << name << "\n";
                if (!f) throw std::runtime_error("cannot write " + tmp.string());
            }
            fs::rename(tmp, dir / "SHA256SUMS");
        }
        std::printf("golden recipes: %zu rendered, %d failed, %d %s (render version %d)\n", recipes.size(),
                    failed, changed, record ? "recorded" : "unrecorded", now);
        return failed ? 1 : 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "fixpoint_golden: %s\n", e.what());
        return 1;
    }
}
