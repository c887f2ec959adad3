// `fixpoint animate --video`: the frames assembled into a video by ffmpeg (Debian's package,
// found on PATH), apart from the animation's own rules.
#pragma once

#include <atomic>
#include <string>

namespace fp::host {

/// The video's path checked before any frame renders: .mp4, .mkv, .mov or .gif, not the config,
/// not a folder, in a folder that exists, not replacing a file unless `force`, and ffmpeg found.
/// Throws fp::InputError naming --video.
void check_video(const std::string& video, const std::string& config, bool force);

/// ffmpeg run on frames first .. first + count - 1 of `pattern` (printf-style, %04d) at `fps`,
/// into a temporary file beside the video that is renamed into place when ffmpeg succeeds.
/// fp::InputError with ffmpeg's last line when it fails; fp::Cancelled when `interrupted` is set.
void make_video(const std::string& pattern, long first, long count, double fps, const std::string& video,
                const std::atomic<bool>* interrupted);

} // namespace fp::host
