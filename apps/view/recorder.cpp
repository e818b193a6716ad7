#include "recorder.hpp"

#include <cstdio>
#include <filesystem>
#include <system_error>

#include "frnn/error.hpp"
#include "frnn/io/atomic_file.hpp"
#include "frnn/sim/video.hpp"

namespace frnn::view {

void recorder::start(const std::string& dir) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) throw error("cannot make the recording folder '" + dir + "': " + ec.message());
    dir_ = dir;
    frames_ = 0;
    recording_ = true;
}

namespace {
std::filesystem::path frame_path(const std::string& dir, std::size_t k) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05zu.png", k);
    return std::filesystem::path(dir) / name;
}
}  // namespace

void recorder::add(const sim::image& frame) {
    io::write_file_atomically(frame_path(dir_, frames_).string(), sim::encode_png(frame));
    ++frames_;
}

std::string recorder::stop() {
    recording_ = false;
    // ffmpeg reads frames until the first number missing: those an earlier, longer recording
    // left in the folder would follow this one's.
    std::error_code ec;
    for (std::size_t k = frames_; std::filesystem::remove(frame_path(dir_, k), ec) && !ec; ++k) {
    }
    std::string done = std::to_string(frames_) + " frames in " + dir_;
    if (frames_ == 0) return done;
    if (!sim::ffmpeg_available()) return done + " (no ffmpeg: no MP4)";
    const std::string mp4 = (std::filesystem::path(dir_) / "recording.mp4").string();
    sim::encode_video(dir_, video_fps, mp4);
    return done + " and " + mp4;
}

}  // namespace frnn::view
