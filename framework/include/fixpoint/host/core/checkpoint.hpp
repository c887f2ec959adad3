// Checkpoint files (`fixpoint render --checkpoint FILE`, `--resume FILE`): the host's envelope
// around a renderer's payload (RenderContext::write_checkpoint, resume_from).
//
//   "fixpoint checkpoint\n"   magic, 20 bytes
//   u32 format                1
//   string version            the fixpoint that wrote it (FIXPOINT_VERSION)
//   string renderer           the renderer plugin's name
//   i64 points                renderer.points (-1: none)
//   string identity           the recipe without renderer.points (Pipeline::identity)
//   payload                   the renderer's
//   u64 payload bytes
//   u32 CRC-32                of everything before it (zlib's)
//
// Integers little-endian, strings as u64 length and bytes. A checkpoint is written to a
// temporary file of its own beside FILE (open_temp_beside) and renamed over FILE once whole and
// synced, so FILE is always the last whole checkpoint, even
// after a kill or a full disk mid-write.
#pragma once

#include <fixpoint/render.hpp>

#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>

namespace fp::host {

struct CheckpointHeader {
    std::string version, renderer, identity;
    std::int64_t points = -1;
};

/// Writes `header` and the payload `body` writes as the checkpoint `path`, atomically (above).
/// fp::host::WriteError when the file cannot be written whole; the previous one stays.
void write_checkpoint_file(const std::string& path, const CheckpointHeader& header,
                           const std::function<void(CheckpointSink&)>& body);

/// A checkpoint opened to resume from: checked whole (magic, format, checksum) when opened,
/// then compared with the recipe (check_against); read() then gives the payload.
class CheckpointFile final : public CheckpointSource {
public:
    /// fp::InputError "'FILE': ..." for a file that is missing, not a checkpoint, of another
    /// format, or corrupt.
    explicit CheckpointFile(const std::string& path);
    ~CheckpointFile() override;
    const CheckpointHeader& header() const { return header_; }
    /// fp::InputError "'FILE': ..." when the checkpoint was made by another fixpoint, by
    /// another renderer or recipe, or with more points than `want` (a checkpoint continues to
    /// as many points or more).
    void check_against(const CheckpointHeader& want) const;

    void read(void* data, std::size_t bytes) override;
    std::uint64_t left() const override { return left_; }

private:
    std::string path_;
    std::FILE* f_ = nullptr;
    CheckpointHeader header_;
    std::uint64_t left_ = 0;
};

/// A checkpoint's payload kept in memory (render --quality's rounds, which continue one another
/// in one process): written by Runtime::write_checkpoint, read back as the next round's resume.
class MemoryCheckpoint final : public CheckpointSource {
public:
    explicit MemoryCheckpoint(std::shared_ptr<const std::string> payload) : payload_(std::move(payload)) {}
    void read(void* data, std::size_t bytes) override;
    std::uint64_t left() const override { return payload_->size() - at_; }

private:
    std::shared_ptr<const std::string> payload_;
    std::size_t at_ = 0;
};

/// Where two recipes (identities) first differ, for a refusal: "its line 12 is 'gamma: 2.2', this
/// recipe's 'gamma: 3'".
std::string recipe_difference(const std::string& had, const std::string& want);

/// "30s", "5m", "1.5h", "90" (seconds): a time as --checkpoint-every takes it, in seconds;
/// fp::InputError naming `option` otherwise.
double parse_duration(const std::string& text, const std::string& option);

} // namespace fp::host
