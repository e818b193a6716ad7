// Recording: every drawn frame's pixels as a PNG (frnn::sim::encode_png, zlib-compressed) in a
// folder, frame_00000.png on; when recording stops and ffmpeg is installed, the frames also
// become DIR/recording.mp4 (frnn::sim::encode_video). Encoding runs on the drawing thread: a
// frame costs its PNG (tens of ms at 1280 x 720), and stopping waits for ffmpeg.
#pragma once
#include <string>

#include "frnn/sim/output.hpp"

namespace frnn::view {

class recorder {
public:
    /// Frames per second of the MP4: one video frame per drawn frame at a steady 30 fps.
    static constexpr double video_fps = 30;

    bool recording() const { return recording_; }
    /// Starts a recording into `dir` (made if missing; the frames of an earlier recording there
    /// are replaced). Throws frnn::error when the folder cannot be made.
    void start(const std::string& dir);
    /// Writes the frame (throws frnn::error when it cannot).
    void add(const sim::image& frame);
    /// Stops; removes the frames an earlier, longer recording left after this one's; with
    /// ffmpeg and at least one frame, encodes the MP4. Returns what was written.
    std::string stop();
    std::size_t frames() const { return frames_; }
    const std::string& dir() const { return dir_; }

private:
    bool recording_ = false;
    std::string dir_;
    std::size_t frames_ = 0;
};

}  // namespace frnn::view
