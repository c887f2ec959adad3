// Key functions of the SDK's classes: their vtables and type information live in this one
// shared library, so dynamic_cast and exceptions work across plugins loaded with RTLD_LOCAL.
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/vertex_map.hpp>

#include <algorithm>
#include <cstdint>

namespace fp {

Error::~Error() = default;
InputError::~InputError() = default;
ParamError::~ParamError() = default;
InternalError::~InternalError() = default;
Cancelled::~Cancelled() = default;

Object::~Object() = default;
Shape::~Shape() = default;
Transform::~Transform() = default;
VertexMap::~VertexMap() = default;
IterationScheme::~IterationScheme() = default;
NumberSystem::~NumberSystem() = default;
Metric::~Metric() = default;
Trap::~Trap() = default;
Filter::~Filter() = default;
Colourer::~Colourer() = default;
Renderer::~Renderer() = default;
RenderContext::~RenderContext() = default;
unsigned RenderContext::rank() const { return 0; }
unsigned RenderContext::ranks() const { return 1; }
void RenderContext::combine(void*, std::size_t, std::size_t,
                            const std::function<void(const void*, void*, std::size_t)>&, bool) {}

namespace {
template <class T>
void squared_exit(const Shape& shape, Vec2 o, Points<const T> d, T* s) {
    shape.ray_exit(o, d, s);
    for (std::size_t i = 0; i < d.n; ++i) s[i] *= s[i];
}
} // namespace

void Shape::inversion_factor(Vec2 o, Points<const float> d, float* s) const { squared_exit(*this, o, d, s); }
void Shape::inversion_factor(Vec2 o, Points<const double> d, double* s) const {
    squared_exit(*this, o, d, s);
}
bool Shape::as_circle(Vec2&, double&) const { return false; }

void Colourer::resolve_parallel(const Histogram& h, Rgb background, float* rgb, RenderContext&) const {
    resolve(h, background, rgb);
}
bool Colourer::resolves_rows() const { return false; }
void Colourer::resolve_rows(const Histogram&, int, const HistogramSummary&, Rgb, float*,
                            RenderContext&) const {
    throw Error("this colourer cannot shade a histogram by strips of rows");
}

std::uint64_t RenderContext::memory_budget() const { return UINT64_MAX; }
std::uint64_t Renderer::memory_within(unsigned workers, std::uint64_t) const { return memory_bytes(workers); }
bool Renderer::streams_rows() const { return false; }
void Renderer::render_rows(RenderContext&, RenderStats&, RowSink&) const {
    throw Error("this renderer cannot stream its image by rows");
}
RowSink::~RowSink() = default;

bool RenderContext::checkpointing() const { return false; }
bool RenderContext::checkpoint_due() const { return false; }
void RenderContext::write_checkpoint(const std::function<void(CheckpointSink&)>&) {}
CheckpointSource* RenderContext::resume_from() { return nullptr; }
bool Renderer::keeps_checkpoints() const { return false; }
bool RenderContext::keeps_histogram() const { return false; }
bool Colourer::palette_index() const { return false; }
void RenderContext::keep_histogram(const Histogram&, int, int, int) {}
bool RenderContext::shard() const { return false; }
HistogramShape Renderer::histogram_shape() const { return {}; }
Image Renderer::finish_histogram(const Histogram&, const RenderStats&, RenderContext&) const {
    throw Error("this renderer keeps no histogram to finish");
}
CheckpointSink::~CheckpointSink() = default;
CheckpointSource::~CheckpointSource() = default;

void HistogramSummary::begin(int w, int h) {
    *this = HistogramSummary{};
    width = w;
    height = h;
    first.assign(std::size_t(std::max(h, 0)), -1);
    last.assign(std::size_t(std::max(h, 0)), -1);
}

void HistogramSummary::add(const Histogram& rows, int row0, RenderContext* ctx) {
    if (rows.width != width || row0 < 0 || rows.height < 0 || row0 + rows.height > height ||
        rows.size() != std::size_t(rows.width) * std::size_t(rows.height))
        throw InternalError("HistogramSummary::add: rows outside the histogram");
    // Pieces of 16 rows, each with its own partial sums, folded in piece order: integer sums
    // and maxima, so any split gives the same summary.
    struct Part {
        std::uint64_t max_hits = 0;
        uint128 hits = 0, hits_column = 0, hits_row = 0;
    };
    const std::size_t W = std::size_t(width), piece_rows = 16;
    const std::size_t pieces = (std::size_t(rows.height) + piece_rows - 1) / piece_rows;
    std::vector<Part> part(pieces);
    auto piece = [&](std::size_t t) {
        if (ctx && ctx->cancelled()) throw Cancelled();
        Part p;
        const std::size_t r1 = std::min(std::size_t(rows.height), (t + 1) * piece_rows);
        // One loop for either form of the bins: `at` reads bin x of a row.
        auto row = [&](std::size_t r, auto at) {
            const std::size_t y = std::size_t(row0) + r;
            std::int32_t f = -1, l = -1;
            uint128 row_hits = 0, row_column = 0;
            for (std::size_t x = 0; x < W; ++x) {
                const std::uint64_t h = at(x);
                if (!h) continue;
                if (f < 0) f = std::int32_t(x);
                l = std::int32_t(x);
                row_hits += h;
                row_column += uint128(h) * x;
                p.max_hits = std::max(p.max_hits, h);
            }
            p.hits += row_hits;
            p.hits_column += row_column;
            p.hits_row += row_hits * y;
            first[y] = f;
            last[y] = l;
        };
        for (std::size_t r = t * piece_rows; r < r1; ++r) {
            if (!rows.hits.empty()) {
                const std::uint64_t* h = rows.hits.data() + r * W;
                row(r, [h](std::size_t x) { return h[x]; });
            } else {
                const HistBin* b = rows.bins.data() + r * W;
                row(r, [b](std::size_t x) { return b[x].hits; });
            }
        }
        part[t] = p;
    };
    if (!ctx || ctx->workers() <= 1)
        for (std::size_t t = 0; t < pieces; ++t) piece(t);
    else
        ctx->parallel_for(pieces, [&](std::size_t t, unsigned) { piece(t); });
    for (const Part& p : part) {
        max_hits = std::max(max_hits, p.max_hits);
        hits += p.hits;
        hits_column += p.hits_column;
        hits_row += p.hits_row;
    }
}

bool Transform::has_region() const { return false; }
void Transform::contains(Points<const float> p, unsigned char* out) const {
    for (std::size_t i = 0; i < p.n; ++i) out[i] = 0;
}
void Transform::contains(Points<const double> p, unsigned char* out) const {
    for (std::size_t i = 0; i < p.n; ++i) out[i] = 0;
}
std::vector<Vec2> Transform::region_outline(std::size_t) const { return {}; }
std::optional<Vec2> Transform::region_centre() const { return std::nullopt; }
bool Transform::is_involution() const { return false; }
bool Transform::uses_random() const { return false; }
Box Transform::sample_domain() const { return {-2, 2, -2, 2}; }
std::optional<PeriodLattice> Transform::periods() const { return std::nullopt; }
KnownKernel Transform::kernel() const { return {}; }
std::string Transform::plane_map_problem() const { return {}; }

unsigned IterationScheme::applications() const { return 1; }
void IterationScheme::check_steps(const Transform&, std::uint64_t) const {}
bool IterationScheme::is_picard() const { return false; }
bool IterationScheme::program(const Transform&, std::uint64_t, bool, SchemeProgram&) const { return false; }
bool NumberSystem::is_real() const { return false; }

bool Renderer::has_vector_output() const { return false; }
std::optional<Box> Renderer::region() const { return std::nullopt; }
std::string Renderer::render_vector(RenderContext&, RenderStats&, VectorFormat, const std::string&) const {
    throw Error("this renderer has no vector output");
}
std::vector<std::string> Renderer::polygon_addresses(std::int64_t) const {
    throw Error("this renderer has no polygon addresses");
}

bool Colourer::needs_colour() const { return true; }
bool Colourer::reads_hits_only() const { return false; }
ColourRule Colourer::colour_rule() const { return ColourRule::none; }
PixelRule Colourer::pixel_rule() const { return PixelRule::mean; }
bool Colourer::colours_trap_hits() const { return false; }
bool Colourer::finishes() const { return false; }
void Colourer::linear(const Histogram&, int, const HistogramSummary&, double, std::size_t, std::size_t,
                      float*) const {
    throw Error("this colourer does not finish a supersampled or filtered histogram");
}
void Colourer::display(const float*, std::size_t, Rgb, float*) const {
    throw Error("this colourer does not finish a supersampled or filtered histogram");
}
void Colourer::colour_hits(const std::int32_t*, const float*, const std::uint32_t*, std::size_t, const Rgb*,
                           float*) const {
    throw Error("this colourer cannot colour orbit-trap hits");
}

} // namespace fp
