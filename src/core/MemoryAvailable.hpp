#pragma once
// What a process can still allocate: what Linux can give without swapping
// (MemAvailable, page cache included), or, where the process's address
// space is limited (ulimit -v, a batch system's memory limit), what is left
// of that limit, whichever is smaller; infinity where neither is known.
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <string>

namespace poresph {

struct AvailableMemory {
  double bytes = INFINITY;
  std::string source;  // where the figure comes from, for messages
};

inline double meminfo_available_bytes() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  double kilobytes = 0;
  while (meminfo >> key >> kilobytes) {
    if (key == "MemAvailable:") return kilobytes * 1024;
    meminfo.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  }
  return INFINITY;
}

// The address-space limit less what the process has mapped already; infinity without a limit.
inline double address_space_left_bytes() {
  rlimit limit{};
  if (getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return INFINITY;
  std::ifstream statm("/proc/self/statm");
  double pages = 0;
  statm >> pages;
  return std::max(0.0, static_cast<double>(limit.rlim_cur) - pages * static_cast<double>(sysconf(_SC_PAGESIZE)));
}

inline AvailableMemory memory_available() {
  AvailableMemory m;
  const double machine = meminfo_available_bytes(), address_space = address_space_left_bytes();
  if (address_space < machine) {
    m.bytes = address_space;
    m.source = "what is left of the process's address-space limit (ulimit -v)";
  } else if (std::isfinite(machine)) {
    m.bytes = machine;
    m.source = "MemAvailable in /proc/meminfo";
  } else {
    m.source = "unknown (no /proc/meminfo)";
  }
  return m;
}

inline double memory_available_bytes() { return memory_available().bytes; }

// Where a run's processes live: how much memory the machine has for the
// processes_on_machine of them together, against which their need (each
// one's times their count) is weighed. Run/Memory Limit (memory_limit_bytes
// > 0) or MemAvailable is the machine's, shared by its processes; an
// address-space limit is each process's own.
struct MemoryBudget {
  double available_bytes = 0;  // Run/Memory Limit, or what the machine has available (MemAvailable)
  int processes_on_machine = 1;
  std::string source;          // where available_bytes comes from, for the message
  bool each_process_limited = false;  // available_bytes is processes_on_machine times each one's own limit
};
inline MemoryBudget machine_memory_budget(double memory_limit_bytes, int processes_on_machine) {
  MemoryBudget budget;
  budget.processes_on_machine = std::max(1, processes_on_machine);
  if (memory_limit_bytes > 0) {
    budget.available_bytes = memory_limit_bytes;
    budget.source = "Run/Memory Limit";
    return budget;
  }
  const double machine = meminfo_available_bytes();
  const double processes = address_space_left_bytes() * budget.processes_on_machine;
  budget.available_bytes = std::min(machine, processes);
  budget.each_process_limited = processes < machine;
  budget.source = processes < machine              ? "what is left of the address-space limit (ulimit -v) of each process"
                  : std::isfinite(machine) ? "MemAvailable in /proc/meminfo"
                                           : "unknown (no /proc/meminfo)";  // infinite: no memory check
  return budget;
}

}  // namespace poresph
