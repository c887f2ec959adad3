// Histogram files (`fixpoint render --histogram FILE.fph`, `fixpoint tone FILE.fph`): a render's
// accumulated histogram with its recipe, so that it can be finished again (other tone, filter,
// density estimation) with no iterating. docs/histograms.md documents the layout for other
// tools; in short:
//
//   "fixpoint histogram\n"   magic, 19 bytes
//   u32 format               1
//   string version           the render version that made it (render_version_tag)
//   string renderer          the renderer plugin's name
//   string identity          the recipe without its finishing parameters (Pipeline::histogram_identity)
//   string recipe            the whole recipe of the render
//   string shards            (format 2 only) a shard's: one character per share of the render's N,
//                            '1' for the shares the file holds (render --shard K/N, merge)
//   u32 width, u32 height    of the histogram (the image times renderer.supersample)
//   u32 form                 bit 0: hits alone; bit 1: last colours
//   zlib stream              the rows, top first: per row its bins (u64 hits, or u64 {hits, r,
//                            g, b}: colour sums in units of 1/65535), then with last colours
//                            u16 {r, g, b} per bin, and in a shard's file then u64 step, u32
//                            chain, u32 0 per bin: the order of that colour, by which a merge
//                            picks each bin's last colour
//   u64 samples, drawn, restarts, bad values   the render's counts
//   u64 stream bytes         the zlib stream's size
//   u32 CRC-32               of everything before it (zlib's)
//
// A whole render's file is format 1 (format 2 without the shards string); a shard's, format 2.
// Integers little-endian, strings as u64 length and bytes. Exact integers, not floats: the
// sums of a large render pass 2^24, and `tone` promises the bytes of the full render. The file is
// written to a temporary name of its own beside FILE and renamed once whole and synced.
#pragma once

#include <fixpoint/histogram.hpp>
#include <fixpoint/render.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace fp::host {

struct HistogramFileHeader {
    std::string version, renderer, identity, recipe;
    HistogramShape shape;
    /// "" for a whole render; a shard's (render --shard K/N) or a merge of some: one character
    /// per share of N, '1' for those the file holds.
    std::string shards = {};
};

/// The shards string of share `k` (from 0) of `n`.
std::string shard_string(unsigned k, unsigned n);
/// "shard 2/4", "shards 1/4 and 3/4", "shards 1/4, 2/4 and 4/4": the shares the string holds,
/// or (with `missing`) those it lacks.
std::string shards_named(const std::string& shards, bool missing = false);

/// Whether `path` names a histogram file (by its extension, .fph).
bool is_histogram_file(const std::string& path);

/// A histogram file being written: opened at a temporary name beside `path`, the rows handed
/// over in order (RenderContext::keep_histogram), then commit() renames it; destroyed before
/// that, it removes the temporary file.
class HistogramWriter {
public:
    /// fp::host::WriteError when the file cannot be made.
    HistogramWriter(std::string path, HistogramFileHeader header);
    ~HistogramWriter();
    HistogramWriter(const HistogramWriter&) = delete;
    HistogramWriter& operator=(const HistogramWriter&) = delete;
    /// Rows [row0, row0 + rows) from `part`, which holds the histogram's rows from part_row0.
    void rows(const Histogram& part, int part_row0, int row0, int rows);
    /// The counts, the checksum; synced and renamed to the path. WriteError on failure.
    void commit(const RenderStats& stats);
    const std::string& temporary_path() const { return tmp_; }
    const std::string& path() const { return path_; }

private:
    struct Stream;
    void put(const void* data, std::size_t bytes, bool finish); // deflated into the file
    std::string path_, tmp_;
    HistogramFileHeader header_;
    int fd_ = -1;
    int next_row_ = 0;
    std::unique_ptr<Stream> z_;
};

/// A histogram file read whole and checked (magic, format, checksum, sizes).
struct HistogramFile {
    std::string path;
    HistogramFileHeader header;
    Histogram histogram; ///< hits alone in `hits` (form bit 0), else `bins`; `last` with bit 1
    RenderStats stats;
};

/// Only the header (for the recipe in it): checked against the checksum too. fp::InputError
/// "'FILE': ..." for a file that is missing, not a histogram file, of another format, or corrupt.
HistogramFileHeader read_histogram_header(const std::string& path);
/// The whole file. `memory`: the most its histogram may take (fp::InputError beyond it).
HistogramFile read_histogram_file(const std::string& path, std::uint64_t memory);

/// The bytes a histogram of this shape takes in memory (and, uncompressed, in the file); with
/// `order`, the last colours' order too (a shard's).
std::uint64_t histogram_bytes(const HistogramShape& shape, bool order = false);

/// Adds `in`'s sums, last colours (by their order, where kept) and stats into `into`, a
/// histogram of the same shape (fp::InternalError otherwise).
void add_histogram(HistogramFile& into, const HistogramFile& in);
/// `fixpoint merge`: the shards' histograms summed into one, checked first (every file whole,
/// of one render version, renderer, recipe, shape and plan of N shares, no share twice; with
/// `whole`, every share present), each refusal one fp::InputError line naming the file. The
/// recipe is the first file's; the header's shards is "" once every share is in.
HistogramFile merge_histograms(const std::vector<std::string>& paths, std::uint64_t memory, bool whole);

} // namespace fp::host
