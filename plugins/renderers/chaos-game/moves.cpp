// A block step's moves, as the renderer makes them through the plugins (the generic path; the
// fused step makes the same ones in its pass): the choice of a map per chain, the grouping of the
// chains by map around the iteration scheme's step calls, the chains' start points, and the
// scheme's step as the fused step's program. chaos-game/block.cpp calls them.
#include "chaos-game/chains.hpp"
#include "chaos-game/kernels.hpp"
#include "chaos-game/renderer.hpp"

#include <fixpoint/check.hpp>
#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <type_traits>

namespace fp_chaos {

// ---------------------------------------------------------------- map choice
// Rules on: chosen[i] = the map drawn among those allowed for chain i (not its previous map,
// not a map whose set holds its point) with probability q_j / (sum of allowed q); k when none
// is allowed or the chain is inactive; restart[i] = 1 for active chains with none allowed.
// One Transform::contains call per map with a set on the whole block, then the draw
// (choose-inl.hpp's draw_rules_t and draw_paper: paper 01's loop, reading the drawn map's test
// from those rows; after rejection_draws rejections the direct draw: one more pcg32 output r,
// u = floor(r * total / 2^32) in [0, total), chosen = #{j : cum_j <= u}, the first map whose
// cumulative weight passes u).
template <class T>
void ChaosGame::choose_rules(Scratch<T>& s, size_t nb) const {
    const fp::Points<const T> pts{s.c.x.get(), s.c.y.get(), nb};
    unsigned char* inside = s.inside.get();
    for (uint32_t j : region_maps_) maps_[j]->contains(pts, inside + size_t(j) * block_size);
    DrawArgs a = s.draw_args(nb, uint32_t(maps_.size()));
    a.inside = inside, a.row = block_size;
    a.q = q_.data(), a.thr = alias_thr_.data(), a.alias = alias_.data(), a.uniform = uniform_;
    draw_by_rules(a);
}

// Rules off: Walker's alias table, one pcg32 output per chain.
template <class T>
void ChaosGame::choose_alias(Scratch<T>& s, size_t nb) const {
    DrawArgs a = s.draw_args(nb, uint32_t(maps_.size()));
    a.thr = alias_thr_.data(), a.alias = alias_.data();
    draw_by_alias(a);
}

// With xaos (flam3's chaos): a scalar draw per chain by its previous map's row (flam3's
// xform_distrib rows: the first for a chain without a previous map).
void ChaosGame::xaos_tables(const std::vector<double>& w, const std::vector<double>& chaos) {
    const size_t k = w.size();
    xaos_thr_.assign((k + 1) * k, 0), xaos_alias_.assign((k + 1) * k, 0), xaos_q_.assign((k + 1) * k, 0);
    // (Maps without a set leave their rows of `inside` as they are: the draw reads those with one.)
    xaos_set_.assign(k, 0);
    for (uint32_t j : region_maps_) xaos_set_[j] = 1;
    for (size_t r = 0; r <= k; ++r) {
        std::vector<double> row(k);
        double sum = 0;
        for (size_t j = 0; j < k; ++j) sum += row[j] = r == 0 ? w[j] : w[j] * chaos[(r - 1) * k + j];
        if (!(sum > 0))
            throw fp::ParamError("maps",
                                 "maps[" + std::to_string(r - 1) +
                                     "].chaos: 0 for every map of positive weight: no map may follow it");
        std::vector<uint32_t> thr, alias;
        walker_table(row, thr, alias);
        // (walker_table pads its tables for the vector draws: the first k entries are the row's.)
        std::copy_n(thr.begin(), k, xaos_thr_.begin() + std::ptrdiff_t(r * k));
        std::copy_n(alias.begin(), k, xaos_alias_.begin() + std::ptrdiff_t(r * k));
        for (size_t j = 0; j < k; ++j)
            if (row[j] > 0)
                xaos_q_[r * k + j] =
                    uint32_t(std::max(1.0, std::floor(row[j] / sum * double(1u << 31) + 0.5)));
    }
}

template <class T>
void ChaosGame::choose_xaos(Scratch<T>& s, size_t nb) const {
    const uint32_t k = uint32_t(maps_.size());
    const unsigned char* inside = s.inside.get();
    if (rules_) {
        const fp::Points<const T> pts{s.c.x.get(), s.c.y.get(), nb};
        for (uint32_t j : region_maps_) maps_[j]->contains(pts, s.inside.get() + size_t(j) * block_size);
    }
    const unsigned char* has_set = xaos_set_.data();
    uint64_t* rs = s.c.rs.get();
    const uint64_t* ri = s.c.ri.get();
    const uint32_t* prev = s.c.prev.get();
    const uint32_t* active = s.c.active.get();
    uint32_t* chosen = s.chosen.get();
    uint32_t* restart = s.restart.get();
    for (size_t i = 0; i < nb; ++i) {
        const uint32_t r = pcg_next(rs[i], ri[i]);
        const size_t row = size_t(prev[i] < k ? prev[i] + 1 : 0) * k;
        restart[i] = 0;
        chosen[i] = k;
        if (!active[i]) continue;
        if (!rules_) {
            // Walker: column m >> 32 of m = r k, kept below its threshold, else its alias.
            const uint64_t m = uint64_t(r) * k;
            const uint32_t col = uint32_t(m >> 32);
            chosen[i] = uint32_t(m) < xaos_thr_[row + col] ? col : xaos_alias_[row + col];
            continue;
        }
        auto allowed = [&](uint32_t j) { return !(has_set[j] && inside[size_t(j) * block_size + i]); };
        uint64_t t = 0;
        for (uint32_t j = 0; j < k; ++j)
            if (allowed(j)) t += xaos_q_[row + j];
        if (t == 0) {
            restart[i] = 1;
            continue;
        }
        // u in [0, t): the first allowed map whose cumulative weight passes u.
        const uint64_t u = (uint64_t(r) * t) >> 32;
        uint64_t cum = 0;
        for (uint32_t j = 0; j < k; ++j) {
            if (!allowed(j)) continue;
            cum += xaos_q_[row + j];
            if (cum > u) {
                chosen[i] = j;
                break;
            }
        }
    }
}

// ---------------------------------------------------------------- random keys
// Maps that draw random numbers (Transform::uses_random: flam3's julia, blur, ...) take them
// from a key per point: fp::map_key(seed, chain, n), the chain's own counter-based stream,
// so the chain's pcg32 draws (its map choices) stay those of a recipe without such maps.
template <class T>
const uint64_t* ChaosGame::keys(Scratch<T>& s, const uint32_t* lanes, size_t at, size_t len,
                                uint64_t n) const {
    if (!random_maps_) return nullptr;
    uint64_t* k = s.gk.get() + at;
    const uint32_t* chain = s.c.chain.get();
    for (size_t t = 0; t < len; ++t) k[t] = fp::map_key(seed_, chain[lanes[t]], n);
    return k;
}

template <class T>
void ChaosGame::hide(Scratch<T>& s, size_t nb, uint64_t n, uint32_t dummy) const {
    const uint32_t* chosen = s.chosen.get();
    const uint32_t* chain = s.c.chain.get();
    uint32_t* idx = s.idx.get();
    for (size_t i = 0; i < nb; ++i) {
        const double v = visible_[chosen[i]];
        // (A salt of its own: the maps' randoms at this step take 0 and up, the final maps' 2^31.)
        if (v < 1 && !(fp::map_uniform(fp::map_key(seed_, chain[i], n), 0xC0000000u, 0) < v)) idx[i] = dummy;
    }
}

// ---------------------------------------------------------------- colour stealing
// (picture.hpp) The colour point in double from its float store, so that every target gives
// the same bits: a scalar loop of plain products and sums (no contraction: the build's
// -ffp-contract=off), rounded to float as it is kept.
template <class T>
void ChaosGame::steal(Scratch<T>& s, size_t nb, const unsigned char* moved) const {
    const uint32_t* chosen = s.chosen.get();
    float* u = s.c.ci.get();
    float* v = s.c.cv.get();
    for (size_t i = 0; i < nb; ++i) {
        if (!moved[i]) continue;
        const std::array<double, 6>& m = colour_maps_[chosen[i]];
        const double a = u[i], b = v[i];
        u[i] = float(m[0] * a + m[1] * b + m[4]);
        v[i] = float(m[2] * a + m[3] * b + m[5]);
        const fp::Rgb c = picture_.at(u[i], v[i]);
        s.c.cr.get()[i] = c.r, s.c.cg.get()[i] = c.g, s.c.cb.get()[i] = c.b;
    }
}

// ---------------------------------------------------------------- final maps, camera
template <class T>
void ChaosGame::finals(Scratch<T>& s, size_t nb, uint64_t n, bool colour) const {
    T* fx = s.fx.get();
    T* fy = s.fy.get();
    std::copy(s.c.x.get(), s.c.x.get() + nb, fx);
    std::copy(s.c.y.get(), s.c.y.get() + nb, fy);
    if (colour) {
        std::copy(s.c.cr.get(), s.c.cr.get() + nb, s.fr.get());
        std::copy(s.c.cg.get(), s.c.cg.get() + nb, s.fg.get());
        std::copy(s.c.cb.get(), s.c.cb.get() + nb, s.fb.get());
        std::copy(s.c.ci.get(), s.c.ci.get() + nb, s.fi.get());
    }
    const uint64_t* keys = nullptr;
    if (random_final_) {
        // The final maps' randoms: the chain's key at this step (the maps' own salt 0 and up is
        // the step's applications of its map; the final maps take salts from 2^31).
        uint64_t* k = s.fk.get();
        for (size_t i = 0; i < nb; ++i) k[i] = fp::map_key(seed_, s.c.chain.get()[i], n);
        keys = k;
    }
    unsigned char* moved = s.moved.get();
    for (size_t j = 0; j < final_.size(); ++j) {
        // flam3's final opacity: the points it skips keep their input (a copy, put back after).
        const double opacity = final_opacity_[j];
        if (opacity < 1) {
            std::copy(fx, fx + nb, s.ox.get());
            std::copy(fy, fy + nb, s.oy.get());
            if (colour)
                for (auto [from, to] : {std::pair{s.fr.get(), s.orr.get()}, std::pair{s.fg.get(), s.og.get()},
                                        std::pair{s.fb.get(), s.ob.get()}, std::pair{s.fi.get(), s.oi.get()}})
                    std::copy(from, from + nb, to);
        }
        final_[j]->apply(fp::Points<T>{fx, fy, nb, keys, 0x80000000u + uint32_t(j)}, nullptr);
        // (With colour stealing the plotted point keeps its chain's colour: final maps have
        // no colour maps.)
        if (colour && !steal_) {
            std::fill(s.fchosen.get(), s.fchosen.get() + nb, uint32_t(j));
            std::fill(moved, moved + nb, static_cast<unsigned char>(1));
            fp::ColourState cs{s.fr.get(), s.fg.get(), s.fb.get(), nb};
            if (palette_) {
                cs.index = s.fi.get();
                cs.map_index = final_index_.data();
                cs.map_speed = final_speed_.data();
            }
            colourer_->update(s.fchosen.get(), cs, final_colours_.data(), moved);
        }
        if (opacity < 1) {
            // (A salt of its own, from 0xE0000000: the maps' randoms take 0 and up, the final
            // maps' 2^31 + j, the maps' opacity 0xC0000000.)
            const uint32_t* chain = s.c.chain.get();
            for (size_t i = 0; i < nb; ++i) {
                if (fp::map_uniform(fp::map_key(seed_, chain[i], n), 0xE0000000u + uint32_t(j), 0) < opacity)
                    continue;
                fx[i] = s.ox.get()[i], fy[i] = s.oy.get()[i];
                if (colour) {
                    s.fr.get()[i] = s.orr.get()[i], s.fg.get()[i] = s.og.get()[i];
                    s.fb.get()[i] = s.ob.get()[i], s.fi.get()[i] = s.oi.get()[i];
                }
            }
        }
    }
    // A chain whose own point is not finite restarts, whatever its final maps made of it (blur
    // ignores its input).
    for (size_t i = 0; i < nb; ++i)
        if (!std::isfinite(s.c.x.get()[i]) || !std::isfinite(s.c.y.get()[i]))
            fx[i] = std::numeric_limits<T>::quiet_NaN();
    if (rotate_ || y_down_) {
        // flam3's camera: the point turned about the view's centre (c, -s; s, c), then, with the
        // y axis down, mirrored in the view's middle row (its ymin at the top).
        const double cx = 0.5 * (frame_.region.xmin + frame_.region.xmax);
        const double cy = 0.5 * (frame_.region.ymin + frame_.region.ymax);
        const T co = T(cam_[0]), si = T(cam_[1]), X = T(cx), Y = T(cy);
        const T sum = T(frame_.region.ymin + frame_.region.ymax);
        for (size_t i = 0; i < nb; ++i) {
            T x = fx[i], y = fy[i];
            if (rotate_) {
                const T dx = x - X, dy = y - Y;
                x = (dx * co - dy * si) + X;
                y = (dx * si + dy * co) + Y;
            }
            fx[i] = x;
            fy[i] = y_down_ ? sum - y : y;
        }
    }
}

// ---------------------------------------------------------------- grouping by map
// Group the chains by chosen map (chains with chosen = k stay), call the iteration scheme
// once per map on its points, and put the new points back.
template <class T>
void ChaosGame::move_chains(Scratch<T>& s, size_t nb, uint64_t n) const {
    const size_t k = maps_.size();
    T* __restrict x = s.c.x.get();
    T* __restrict y = s.c.y.get();
    T* __restrict gx = s.gx.get();
    T* __restrict gy = s.gy.get();
    const uint32_t* __restrict chosen = s.chosen.get();
    uint32_t* __restrict cnt = s.cnt.get();
    if (k <= max_compress_maps) {
        // Each map's points compressed into its own segment with their chains' indices
        // (choose-inl.hpp's group_t), one step call per map, then scattered back.
        const uint32_t* __restrict gi = s.gi.get();
        group(GroupArgs<T>{x, y, chosen, gx, gy, s.gi.get(), cnt, seg_stride, nb, uint32_t(k)});
        for (size_t j = 0; j < k; ++j) {
            const size_t at = j * seg_stride, len = cnt[j];
            if (!len) continue;
            iteration_->step(*maps_[j], fp::Points<T>{gx + at, gy + at, len, keys(s, gi + at, at, len, n)},
                             nullptr, n);
            scatter(gx + at, gy + at, gi + at, len, x, y);
        }
        return;
    }
    // Counting sort into contiguous segments; perm remembers where each point came from.
    uint32_t* __restrict perm = s.perm.get();
    for (size_t j = 0; j <= k; ++j) cnt[j] = 0;
    for (size_t i = 0; i < nb; ++i) {
        FP_DCHECK(chosen[i] <= k);
        ++cnt[chosen[i]];
    }
    uint32_t start = 0;
    for (size_t j = 0; j <= k; ++j) {
        const uint32_t c = cnt[j];
        cnt[j] = start;
        start += c;
    }
    for (size_t i = 0; i < nb; ++i) {
        const uint32_t t = cnt[chosen[i]]++;
        perm[t] = uint32_t(i);
        gx[t] = x[i];
        gy[t] = y[i];
    }
    // cnt[j] is now the end of map j's segment.
    for (size_t j = 0; j < k; ++j) {
        const size_t beg = j == 0 ? 0 : cnt[j - 1], len = cnt[j] - beg;
        if (len)
            iteration_->step(*maps_[j],
                             fp::Points<T>{gx + beg, gy + beg, len, keys(s, perm + beg, beg, len, n)},
                             nullptr, n);
    }
    const size_t movers = cnt[k - 1];
    for (size_t t = 0; t < movers; ++t) {
        x[perm[t]] = gx[t];
        y[perm[t]] = gy[t];
    }
}

// ---------------------------------------------------------------- start points
// For the m chains list[0..m): a start point. With `start` given, that point; else a uniform
// point of the start box (the view unless `start_box`) outside every map's set, drawn from
// the chain's own stream (at most start_tries candidates, the last one taken whatever it is).
// Batched: one contains call per map with a set per round, over all pending chains.
template <class T>
void ChaosGame::new_starts(Scratch<T>& s, const uint32_t* list, size_t m) const {
    T* x = s.c.x.get();
    T* y = s.c.y.get();
    if (has_start_) {
        for (size_t t = 0; t < m; ++t) x[list[t]] = T(start_.x), y[list[t]] = T(start_.y);
        return;
    }
    uint32_t* pend = s.pend.get();
    std::copy(list, list + m, pend);
    size_t np = m;
    T* sx = s.sx.get();
    T* sy = s.sy.get();
    unsigned char* hit = s.hit.get();
    unsigned char* any = s.any.get();
    for (unsigned tr = 0; tr < start_tries && np > 0; ++tr) {
        for (size_t t = 0; t < np; ++t) {
            const uint32_t i = pend[t];
            FP_DCHECK(i < block_size);
            const double ux = pcg_uniform(s.c.rs.get()[i], s.c.ri.get()[i]);
            const double uy = pcg_uniform(s.c.rs.get()[i], s.c.ri.get()[i]);
            sx[t] = T(start_box_.xmin + (start_box_.xmax - start_box_.xmin) * ux);
            sy[t] = T(start_box_.ymin + (start_box_.ymax - start_box_.ymin) * uy);
            any[t] = 0;
        }
        if (tr + 1 < start_tries) {
            const fp::Points<const T> cand{sx, sy, np};
            for (uint32_t j : region_maps_) {
                maps_[j]->contains(cand, hit);
                for (size_t t = 0; t < np; ++t) any[t] |= hit[t];
            }
        }
        size_t keep = 0;
        for (size_t t = 0; t < np; ++t) {
            const uint32_t i = pend[t];
            if (any[t]) {
                pend[keep++] = i;
            } else {
                x[i] = sx[t];
                y[i] = sy[t];
            }
        }
        np = keep;
    }
}

// ---------------------------------------------------------------- the scheme's program
static_assert(uint32_t(ProgOp::map) == uint32_t(fp::SchemeProgram::Op::map) &&
              uint32_t(ProgOp::copy) == uint32_t(fp::SchemeProgram::Op::copy) &&
              uint32_t(ProgOp::lin2) == uint32_t(fp::SchemeProgram::Op::lin2) &&
              uint32_t(ProgOp::lin3) == uint32_t(fp::SchemeProgram::Op::lin3));

template <class T>
bool ChaosGame::lane_program(uint64_t n, LaneProgram<T>& out) const {
    // (Asked at every block step: a program is a few dozen bytes to record and compare, and a
    // kernel is recorded, not run.)
    fp::SchemeProgram first, other;
    const bool dbl = std::is_same_v<T, double>;
    if (!iteration_->program(*maps_[0], n, dbl, first)) return false;
    for (size_t j = 1; j < maps_.size(); ++j)
        if (!iteration_->program(*maps_[j], n, dbl, other) || !other.same_as(first)) return false;
    out.size = first.size;
    out.regs = first.regs;
    for (uint32_t i = 0; i < first.size; ++i) {
        const fp::SchemeProgram::Instr& a = first.code[i];
        auto& b = out.code[i];
        b.op = ProgOp(uint32_t(a.op));
        b.dst = a.dst, b.u = a.u, b.v = a.v, b.w = a.w;
        for (size_t j = 0; j < fp::SchemeProgram::coefficients(a.op); ++j) b.k[j] = T(a.k[j]);
    }
    return true;
}

template void ChaosGame::choose_xaos<float>(Scratch<float>&, size_t) const;
template void ChaosGame::choose_xaos<double>(Scratch<double>&, size_t) const;
template void ChaosGame::steal<float>(Scratch<float>&, size_t, const unsigned char*) const;
template void ChaosGame::steal<double>(Scratch<double>&, size_t, const unsigned char*) const;
template void ChaosGame::hide<float>(Scratch<float>&, size_t, uint64_t, uint32_t) const;
template void ChaosGame::hide<double>(Scratch<double>&, size_t, uint64_t, uint32_t) const;
template void ChaosGame::choose_rules<float>(Scratch<float>&, size_t) const;
template void ChaosGame::choose_rules<double>(Scratch<double>&, size_t) const;
template void ChaosGame::choose_alias<float>(Scratch<float>&, size_t) const;
template void ChaosGame::choose_alias<double>(Scratch<double>&, size_t) const;
template void ChaosGame::move_chains<float>(Scratch<float>&, size_t, uint64_t) const;
template void ChaosGame::move_chains<double>(Scratch<double>&, size_t, uint64_t) const;
template void ChaosGame::finals<float>(Scratch<float>&, size_t, uint64_t, bool) const;
template void ChaosGame::finals<double>(Scratch<double>&, size_t, uint64_t, bool) const;
template void ChaosGame::new_starts<float>(Scratch<float>&, const uint32_t*, size_t) const;
template void ChaosGame::new_starts<double>(Scratch<double>&, const uint32_t*, size_t) const;
template bool ChaosGame::lane_program<float>(uint64_t, LaneProgram<float>&) const;
template bool ChaosGame::lane_program<double>(uint64_t, LaneProgram<double>&) const;

} // namespace fp_chaos
