#pragma once
// What Linux can give a process without swapping (MemAvailable, page cache
// included), or infinity where /proc/meminfo does not say.
#include <cmath>
#include <fstream>
#include <limits>
#include <string>

namespace poresph {

inline double memory_available_bytes() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  double kilobytes = 0;
  while (meminfo >> key >> kilobytes) {
    if (key == "MemAvailable:") return kilobytes * 1024;
    meminfo.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  }
  return INFINITY;
}

}  // namespace poresph
