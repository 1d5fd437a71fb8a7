#pragma once
// What the kernel says a process can still allocate without swapping (/proc/meminfo's
// MemAvailable: free memory plus the page cache it can drop), for trainers that choose
// between holding their data in memory and streaming it from disk.
#include <fstream>
#include <sstream>
#include <string>

namespace nns::runs {

// GiB available now; 0 where /proc/meminfo cannot say (then nothing is held in memory
// that a budget of "half the available" would allow).
inline double available_memory_gib() {
  std::ifstream in("/proc/meminfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("MemAvailable:", 0) == 0) {
      std::istringstream ss(line.substr(13));
      double kib = 0;
      ss >> kib;
      return kib / double(1 << 20);
    }
  return 0;
}

// What a trainer holds in memory by default before it streams or reads again: half of
// what is available when the run starts, leaving the rest to the model, the page cache
// and whatever else runs beside it.
inline double default_memory_budget_gib() { return available_memory_gib() / 2; }

}  // namespace nns::runs
