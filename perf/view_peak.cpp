// A Kokkos tools library: at the peak of the Views' total, and at the
// largest resident set size seen at a Kokkos event (an allocation, a free,
// a kernel, a region), how many bytes each View label holds.
// docs/performance.md, "Memory per particle".
//
//   g++ -O2 -shared -fPIC -o /tmp/libviewpeak.so perf/view_peak.cpp
//   export KOKKOS_PROFILE_LIBRARY=/tmp/libviewpeak.so VIEW_PEAK_OUT=/tmp/peak.txt
//   build/poresph SCENE.xml ...
//
// VIEW_PEAK_OUT: where the tables go (stderr without it). VIEW_PEAK_TRACE (a file):
// a line each time the resident set has moved by a MB since the last line,
// with the Views' total and glibc's heap in use, free (resident holes among
// them) and mapped.
#include <malloc.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

namespace {

struct Allocation {
  std::string label;
  uint64_t bytes;
};
std::map<void*, Allocation> live;
uint64_t total = 0, peak = 0, rss_peak = 0, last_traced = 0;
std::map<std::string, uint64_t> at_peak, at_rss_peak;
std::vector<std::string> regions;
std::string region_at_peak, region_at_rss_peak, last_event;
FILE* trace = nullptr;

uint64_t resident_bytes() {
  long pages = 0, resident = 0;
  if (FILE* f = std::fopen("/proc/self/statm", "r")) {
    if (std::fscanf(f, "%ld %ld", &pages, &resident) != 2) resident = 0;
    std::fclose(f);
  }
  return static_cast<uint64_t>(resident) * static_cast<uint64_t>(sysconf(_SC_PAGESIZE));
}

std::map<std::string, uint64_t> by_label() {
  std::map<std::string, uint64_t> bytes;
  for (const auto& entry : live) bytes[entry.second.label] += entry.second.bytes;
  return bytes;
}

std::string region() {
  std::string path;
  for (const auto& r : regions) path += r + "/";
  return path;
}

void look_at_resident_set() {
  const uint64_t rss = resident_bytes();
  if (rss > rss_peak) rss_peak = rss, at_rss_peak = by_label(), region_at_rss_peak = region();
  if (!trace) return;
  if (rss > last_traced + 1000000 || rss + 1000000 < last_traced) {
    last_traced = rss;
    const struct mallinfo2 heap = mallinfo2();
    std::fprintf(trace, "rss %8.1f MB  views %8.1f MB  heap in use %7.1f free %7.1f mapped %7.1f  region %s  after %s\n",
                 rss / 1e6, total / 1e6, heap.uordblks / 1e6, heap.fordblks / 1e6, heap.hblkhd / 1e6,
                 region().c_str(), last_event.c_str());
    std::fflush(trace);
  }
}

void print(FILE* f, const char* title, const std::map<std::string, uint64_t>& bytes, const std::string& where) {
  std::vector<std::pair<uint64_t, std::string>> rows;
  uint64_t sum = 0;
  for (const auto& [label, b] : bytes) rows.push_back({b, label}), sum += b;
  std::sort(rows.rbegin(), rows.rend());
  std::fprintf(f, "%s: %.1f MB of Views (region %s)\n", title, sum / 1e6, where.c_str());
  for (const auto& [b, label] : rows)
    if (b > 100000) std::fprintf(f, "  %10.2f MB  %s\n", b / 1e6, label.c_str());
}

}  // namespace

extern "C" {
struct SpaceHandle {
  char name[64];
};

void kokkosp_init_library(int, uint64_t, uint32_t, void*) {
  if (const char* path = std::getenv("VIEW_PEAK_TRACE")) trace = std::fopen(path, "w");
}
void kokkosp_push_profile_region(const char* name) {
  look_at_resident_set();
  regions.push_back(name);
}
void kokkosp_pop_profile_region() {
  look_at_resident_set();
  if (!regions.empty()) regions.pop_back();
}
void kokkosp_begin_parallel_for(const char* name, uint32_t, uint64_t* id) {
  *id = 0;
  look_at_resident_set();
  last_event = std::string("kernel ") + name;
}
void kokkosp_end_parallel_for(uint64_t) { look_at_resident_set(); }
void kokkosp_allocate_data(SpaceHandle, const char* label, void* ptr, uint64_t bytes) {
  look_at_resident_set();
  live[ptr] = {label, bytes};
  last_event = std::string("allocation ") + label;
  total += bytes;
  if (total > peak) peak = total, at_peak = by_label(), region_at_peak = region();
}
void kokkosp_deallocate_data(SpaceHandle, const char*, void* ptr, uint64_t bytes) {
  look_at_resident_set();
  const auto it = live.find(ptr);
  if (it != live.end()) last_event = "free " + it->second.label, live.erase(it);
  total -= bytes;
}
void kokkosp_finalize_library() {
  const char* path = std::getenv("VIEW_PEAK_OUT");
  FILE* f = path ? std::fopen(path, "w") : stderr;
  if (!f) return;
  print(f, "At the peak of the Views", at_peak, region_at_peak);
  std::fprintf(f, "Largest resident set seen at an event: %.1f MB\n", rss_peak / 1e6);
  print(f, "Views then", at_rss_peak, region_at_rss_peak);
  if (path) std::fclose(f);
  if (trace) std::fclose(trace);
}
}
