// `fixpoint merge`: the shards of a render (render --shard K/N --histogram PART.fph) summed into
// its whole histogram. Every shard holds exact integer sums of its own chains, and each chain
// runs in exactly one shard, so the sum is the single render's histogram, bin for bin; a bin's
// last colour is the one with the largest (step, chain), as when MPI ranks combine.
#include <fixpoint/host/core/checkpoint.hpp>
#include <fixpoint/host/core/histogram_file.hpp>

#include <fixpoint/errors.hpp>
#include <fixpoint/text.hpp>

#include <algorithm>
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace fp::host {

namespace {

/// A whole render's file counts as the one share of one.
std::string shares_of(const HistogramFileHeader& h) { return h.shards.empty() ? "1" : h.shards; }

/// Checks file `h` (at `path`) against the first one, and adds its shares to `have`.
void check_against(const HistogramFileHeader& first, const std::string& first_path,
                   const HistogramFileHeader& h, const std::string& path, std::string& have,
                   std::vector<std::string>& holder) {
    const std::string who = quote(path, 200), ref = quote(first_path, 200);
    if (h.version != first.version)
        throw InputError(who + " was made by render version " + h.version + ", " + ref + " by " +
                         first.version + ": only shards of one render merge");
    if (h.renderer != first.renderer)
        throw InputError(who + " is a histogram of a " + h.renderer + " render, " + ref + " of a " +
                         first.renderer + " one");
    if (h.identity != first.identity)
        throw InputError(who + " is a shard of another recipe than " + ref + " (" +
                         recipe_difference(first.identity, h.identity) + ")");
    const HistogramShape &a = first.shape, &b = h.shape;
    if (a.width != b.width || a.height != b.height || a.hits_only != b.hits_only || a.last != b.last)
        throw InputError(who + ": its histogram is not the one " + ref + " holds (damaged?)");
    const std::string mine = shares_of(h);
    if (mine.size() != have.size())
        throw InputError(who + " holds " + shards_named(mine) + ", " + ref + " " +
                         shards_named(shares_of(first)) + ": only shards of one plan of N merge");
    for (std::size_t i = 0; i < mine.size(); ++i) {
        if (mine[i] != '1') continue;
        if (have[i] == '1')
            throw InputError(who + " and " + quote(holder[i], 200) + " both hold " +
                             shards_named(shard_string(unsigned(i), unsigned(mine.size()))) +
                             ": give each shard once");
        have[i] = '1';
        holder[i] = path;
    }
}

/// Adds `in`'s sums (and last colours, by their order) into `into`.
void add(Histogram& into, const Histogram& in) {
    for (std::size_t i = 0; i < into.hits.size(); ++i) into.hits[i] += in.hits[i];
    for (std::size_t i = 0; i < into.bins.size(); ++i) {
        HistBin& a = into.bins[i];
        const HistBin& b = in.bins[i];
        a.hits += b.hits, a.r += b.r, a.g += b.g, a.b += b.b;
    }
    for (std::size_t i = 0; i < into.last_order.size(); ++i)
        if (later(in.last_order[i], into.last_order[i])) {
            into.last_order[i] = in.last_order[i];
            into.last[i] = in.last[i];
        }
}

} // namespace

void add_histogram(HistogramFile& into, const HistogramFile& in) {
    Histogram& h = into.histogram;
    if (h.width != in.histogram.width || h.height != in.histogram.height ||
        h.hits.size() != in.histogram.hits.size() || h.bins.size() != in.histogram.bins.size() ||
        h.last_order.size() != in.histogram.last_order.size())
        throw InternalError("histograms of other shapes summed");
    add(h, in.histogram);
    RenderStats& a = into.stats;
    const RenderStats& b = in.stats;
    a.samples += b.samples, a.drawn += b.drawn, a.restarts += b.restarts, a.bad_values += b.bad_values;
}

HistogramFile merge_histograms(const std::vector<std::string>& paths, std::uint64_t memory, bool whole) {
    if (paths.empty()) throw InputError("merge: name the shards' histogram files (.fph)");
    // Every header first (each file checked whole against its checksum): a bad shard is found
    // before any bins are read.
    std::vector<HistogramFileHeader> heads;
    for (std::size_t i = 0; i < paths.size(); ++i) {
        if (!is_histogram_file(paths[i]))
            throw InputError("merge: " + quote(paths[i], 200) +
                             " is not a histogram file: name the .fph files that render --shard wrote");
        for (std::size_t j = 0; j < i; ++j) {
            std::error_code ec;
            if (paths[j] == paths[i] || fs::equivalent(paths[j], paths[i], ec))
                throw InputError("merge: " + quote(paths[i], 200) + " is given twice: give each shard once");
        }
        heads.push_back(read_histogram_header(paths[i]));
    }
    const HistogramFileHeader& first = heads.front();
    std::string have(shares_of(first).size(), '0');
    std::vector<std::string> holder(have.size());
    for (std::size_t i = 0; i < paths.size(); ++i)
        check_against(first, paths.front(), heads[i], paths[i], have, holder);
    if (whole && have.find('0') != std::string::npos)
        throw InputError("merge: " + shards_named(have, true) + " of the render " +
                         (std::count(have.begin(), have.end(), '0') == 1 ? "is" : "are") +
                         " missing: no file given holds " +
                         (std::count(have.begin(), have.end(), '0') == 1 ? "it" : "them") +
                         " (render it with --shard K/N, then merge every shard)");
    // The sums, one file at a time into the first (two histograms in memory at once).
    const std::uint64_t each = paths.size() > 1 ? memory / 2 : memory;
    HistogramFile out = read_histogram_file(paths.front(), each);
    for (std::size_t i = 1; i < paths.size(); ++i) {
        add_histogram(out, read_histogram_file(paths[i], each));
    }
    // Whole: the file a single render keeps (no shards, no order).
    if (have.find('0') == std::string::npos) {
        out.header.shards.clear();
        out.histogram.last_order.clear();
        out.histogram.last_order.shrink_to_fit();
    } else {
        out.header.shards = have;
    }
    out.path = paths.front();
    return out;
}

} // namespace fp::host
