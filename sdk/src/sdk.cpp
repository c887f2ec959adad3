// Key functions of the SDK's classes: their vtables and type information live in this one
// shared library, so dynamic_cast and exceptions work across plugins loaded with RTLD_LOCAL.
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/vertex_map.hpp>

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
Box Transform::sample_domain() const { return {-2, 2, -2, 2}; }
std::optional<PeriodLattice> Transform::periods() const { return std::nullopt; }
KnownKernel Transform::kernel() const { return {}; }
std::string Transform::plane_map_problem() const { return {}; }

unsigned IterationScheme::applications() const { return 1; }
void IterationScheme::check_steps(const Transform&, std::uint64_t) const {}
bool IterationScheme::is_picard() const { return false; }
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
ColourRule Colourer::colour_rule() const { return ColourRule::none; }
PixelRule Colourer::pixel_rule() const { return PixelRule::mean; }
bool Colourer::colours_trap_hits() const { return false; }
void Colourer::colour_hits(const std::int32_t*, const float*, const std::uint32_t*, std::size_t, const Rgb*,
                           float*) const {
    throw Error("this colourer cannot colour orbit-trap hits");
}

} // namespace fp
