// Runs a program without a shell (fork + execv), so no argument is ever interpreted.
#pragma once

#include <string>
#include <vector>

namespace occlusion_env {
namespace eval {

/// Runs argv[0] (an absolute or relative path; no PATH search) with `argv` in `work_dir` (empty:
/// the current directory), stdin from /dev/null, stdout and stderr to `log_path` (empty:
/// inherited). Returns the exit status; 127 when the program could not be executed, 128 + signal
/// when it was killed. Throws std::runtime_error when fork fails.
int runProgram(const std::vector<std::string>& argv, const std::string& work_dir,
               const std::string& log_path);

}  // namespace eval
}  // namespace occlusion_env
