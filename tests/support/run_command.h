#pragma once
// Runs a command line the way a user would and captures what it printed, for tests
// of the apps' messages and exit codes.
#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace nns::testing {

struct CommandResult {
  int code = -1;       // exit code; -1 if it could not run or was killed by a signal
  std::string output;  // stdout and stderr together
};

inline CommandResult run_command(const std::string& cmd) {
  CommandResult r;
  std::FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return r;
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
  int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// One of the built commands, build/bin/<app>.
inline CommandResult run_app(const std::string& app, const std::string& args) {
  return run_command(std::string(NNSHADE_BINARY_DIR) + "/bin/" + app + " " + args);
}

}  // namespace nns::testing
