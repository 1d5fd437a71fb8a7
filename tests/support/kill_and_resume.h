#pragma once
// Kills a trainer for real (SIGKILL, no chance to clean up) at pseudo-random moments —
// during a step, a metrics append, a blob or checkpoint write — then resumes it, until
// a run completes. The caller compares the final outputs bitwise with an uninterrupted
// run: whatever the kill interrupted, the resumed run must end in the same bytes.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>

#include "core/rng.h"

namespace nns::testing {

struct KillStats {
  int kills = 0, runs = 0;
};

// `command` is run by /bin/sh with `exec` so the signal reaches the trainer itself;
// " --resume" is appended once OUT/checkpoint.blob exists. Delays are drawn uniformly
// from [0, max_delay_ms) by a seeded Rng: the same seed kills at the same moments.
inline KillStats kill_and_resume(const std::string& command, const std::string& out, const std::string& log, int kills,
                                 double max_delay_ms, uint64_t seed) {
  Rng rng(seed);
  KillStats st;
  for (;;) {
    const bool resume = std::filesystem::exists(out + "/checkpoint.blob");
    const std::string cmd = "exec " + command + (resume ? " --resume" : "") + " >> " + log + " 2>&1";
    pid_t pid = ::fork();
    if (pid == 0) {
      ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
    ++st.runs;
    int status = 0;
    if (st.kills < kills) {
      const auto delay = std::chrono::microseconds(int64_t(rng.uniform() * max_delay_ms * 1000));
      const auto until = std::chrono::steady_clock::now() + delay;
      while (std::chrono::steady_clock::now() < until && ::waitpid(pid, &status, WNOHANG) == 0)
        std::this_thread::sleep_for(std::chrono::microseconds(200));
      if (::waitpid(pid, &status, WNOHANG) == 0) {
        ::kill(pid, SIGKILL);
        ::waitpid(pid, &status, 0);
        ++st.kills;
        continue;
      }
    } else {
      ::waitpid(pid, &status, 0);
    }
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return st;
    if (st.runs > 4 * kills + 10) return st;  // the caller's comparison fails
  }
}

}  // namespace nns::testing
