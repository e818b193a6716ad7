// Running another program (ffmpeg, gnuplot) as a child process: no shell, so arguments and
// paths pass as they are, whatever characters they hold.
#pragma once
#include <string>
#include <vector>

namespace frnn::io {

/// Runs args[0], looked up on PATH, with `args`, and waits for it. Its standard output goes to
/// /dev/null when `discard_output`. Returns its exit status; 128 + the signal when a signal
/// ended it; -1 when it could not be started (errno then says why: ENOENT when not installed).
int run_program(const std::vector<std::string>& args, bool discard_output = false);

}  // namespace frnn::io
