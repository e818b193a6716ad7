// encode_video (frnn/sim/video.hpp): ffmpeg run as a child process (frnn/io/child_process.hpp),
// its arguments passed as they are (no shell quoting), its output to a temporary beside the target.
#include "frnn/sim/video.hpp"

#include <cstdio>
#include <string>
#include <filesystem>
#include <system_error>
#include <vector>

#include "frnn/error.hpp"
#include "frnn/io/atomic_file.hpp"
#include "frnn/io/child_process.hpp"

namespace frnn::sim {

bool ffmpeg_available() { return io::run_program({"ffmpeg", "-loglevel", "quiet", "-version"}, true) == 0; }

void encode_video(const std::string& png_dir, double fps, const std::string& mp4_path) {
    if (!(fps > 0) || !(fps <= 1000)) throw error("video: frame rate " + std::to_string(fps) + " is not in (0, 1000]");
    if (!ffmpeg_available()) throw error("video: ffmpeg is not installed (apt-get install ffmpeg)");
    const std::filesystem::path temporary = io::temporary_path_beside(mp4_path);
    char rate[32];
    std::snprintf(rate, sizeof rate, "%.6g", fps);
    const std::vector<std::string> args{"ffmpeg", "-y", "-nostdin", "-loglevel", "error", "-framerate", rate,
                                        "-i", png_dir + "/frame_%05d.png", "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2",
                                        "-pix_fmt", "yuv420p", "-f", "mp4", temporary.string()};
    const int status = io::run_program(args, /*discard_output=*/true);
    if (status != 0) {
        std::error_code ec;
        std::filesystem::remove(temporary, ec);
        throw error("video: ffmpeg could not make " + mp4_path + " from " + png_dir + "/frame_%05d.png (exit status " +
                    std::to_string(status) + ")");
    }
    io::commit_temporary(temporary, mp4_path);
}

}  // namespace frnn::sim
