// MP4 video from PNG frames with ffmpeg (Debian's `ffmpeg`, run as a separate program), for
// `frnn sim --video` and the viewer's recording.
#pragma once
#include <string>

namespace frnn::sim {

/// Whether an `ffmpeg` program is on PATH.
bool ffmpeg_available();

/// Encodes `png_dir`/frame_00000.png, frame_00001.png, ... at `fps` frames per second into
/// `mp4_path` (H.264, yuv420p, sizes padded to even), written under a temporary name and
/// renamed, so the file is whole or absent. ffmpeg runs without a shell (any path works).
/// Throws frnn::error when ffmpeg is missing or fails (with its exit status).
void encode_video(const std::string& png_dir, double fps, const std::string& mp4_path);

}  // namespace frnn::sim
