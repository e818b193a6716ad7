// encode_video (frnn/sim/video.hpp): ffmpeg started with posix_spawnp, its arguments passed as
// they are (no shell quoting), its output to a temporary beside the target.
#include "frnn/sim/video.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>
#include <vector>

#include "frnn/error.hpp"
#include "frnn/io/atomic_file.hpp"

extern char** environ;

namespace frnn::sim {

namespace {

// Runs `args` (args[0] looked up on PATH), its standard output discarded, and returns its exit
// status, or -1 when it could not start or did not exit normally.
int run_program(const std::vector<std::string>& args) {
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    pid_t pid = 0;
    const int started = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (started != 0) return -1;
    int status = 0;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

bool ffmpeg_available() { return run_program({"ffmpeg", "-loglevel", "quiet", "-version"}) == 0; }

void encode_video(const std::string& png_dir, double fps, const std::string& mp4_path) {
    if (!(fps > 0) || !(fps <= 1000)) throw error("video: frame rate " + std::to_string(fps) + " is not in (0, 1000]");
    if (!ffmpeg_available()) throw error("video: ffmpeg is not installed (apt-get install ffmpeg)");
    const std::filesystem::path temporary = io::temporary_path_beside(mp4_path);
    char rate[32];
    std::snprintf(rate, sizeof rate, "%.6g", fps);
    const int status = run_program({"ffmpeg", "-y", "-nostdin", "-loglevel", "error", "-framerate", rate, "-i",
                                    png_dir + "/frame_%05d.png", "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-pix_fmt",
                                    "yuv420p", "-f", "mp4", temporary.string()});
    if (status != 0) {
        std::error_code ec;
        std::filesystem::remove(temporary, ec);
        throw error("video: ffmpeg could not make " + mp4_path + " from " + png_dir + "/frame_%05d.png (exit status " +
                    std::to_string(status) + ")");
    }
    io::commit_temporary(temporary, mp4_path);
}

}  // namespace frnn::sim
