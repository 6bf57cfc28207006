#pragma once
// A directory in the temporary folder shared by all ranks of an MPI test,
// created empty by rank 0 before any rank uses it: named after the test
// program, the case and the number of ranks, so that the same test run on
// 1, 2 and 4 ranks at once (CTest -j) does not share one.
#include <mpi.h>

#include <filesystem>
#include <string>

namespace poresph::testing {

inline int world_rank() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

inline int world_size() {
  int n = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &n);
  return n;
}

inline std::string fresh_shared_directory(const std::string& program, const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("poresph-test-" + program + "-" + name + "-" + std::to_string(world_size()) + "-ranks");
  if (world_rank() == 0) {
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  return dir.string();
}

}  // namespace poresph::testing
