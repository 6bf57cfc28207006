#pragma once
// The few collective operations the solver needs, so that it never calls MPI
// itself. One process, MPI_COMM_SELF or any communicator: the same code.
#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

namespace poresph {

// Wall time this process has spent inside collective operations (where it
// waits for the others, and the exchange itself): a step's wall time less
// this is the work the process did, which the load balance compares
// (app/Simulation.hpp). One clock per process.
inline double& communication_seconds() {
  static double seconds = 0;
  return seconds;
}
// Adds its lifetime to communication_seconds().
class CommunicationTimer {
 public:
  CommunicationTimer() : start_(std::chrono::steady_clock::now()) {}
  ~CommunicationTimer() {
    communication_seconds() += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  CommunicationTimer(const CommunicationTimer&) = delete;
  CommunicationTimer& operator=(const CommunicationTimer&) = delete;

 private:
  std::chrono::steady_clock::time_point start_;
};

class Communicator {
 public:
  explicit Communicator(MPI_Comm comm = MPI_COMM_WORLD) : comm_(comm) {
    MPI_Comm_rank(comm_, &rank_);
    MPI_Comm_size(comm_, &size_);
  }
  int rank() const { return rank_; }
  int size() const { return size_; }
  MPI_Comm comm() const { return comm_; }

  double sum(double x) const { return reduce(x, MPI_SUM); }
  double max(double x) const { return reduce(x, MPI_MAX); }
  long long sum(long long x) const {
    long long r = 0;
    const CommunicationTimer timer;
    MPI_Allreduce(&x, &r, 1, MPI_LONG_LONG, MPI_SUM, comm_);
    return r;
  }
  int sum(int x) const { return static_cast<int>(sum(static_cast<long long>(x))); }
  int max(int x) const {
    int r = 0;
    const CommunicationTimer timer;
    MPI_Allreduce(&x, &r, 1, MPI_INT, MPI_MAX, comm_);
    return r;
  }
  long long max(long long x) const {
    long long r = 0;
    const CommunicationTimer timer;
    MPI_Allreduce(&x, &r, 1, MPI_LONG_LONG, MPI_MAX, comm_);
    return r;
  }
  bool any(bool x) const { return max(x ? 1 : 0) != 0; }
  long long min(long long x) const {
    long long r = 0;
    const CommunicationTimer timer;
    MPI_Allreduce(&x, &r, 1, MPI_LONG_LONG, MPI_MIN, comm_);
    return r;
  }
  // Element-wise sums over processes, in place.
  void sum(long long* values, int n) const {
    const CommunicationTimer timer;
    MPI_Allreduce(MPI_IN_PLACE, values, n, MPI_LONG_LONG, MPI_SUM, comm_);
  }
  void sum(double* values, int n) const {
    const CommunicationTimer timer;
    MPI_Allreduce(MPI_IN_PLACE, values, n, MPI_DOUBLE, MPI_SUM, comm_);
  }

  // Element-wise "any" of 0/1 flags over processes, in place (in pieces:
  // MPI counts in int).
  void any(std::vector<char>& flags) const {
    const CommunicationTimer timer;
    constexpr std::size_t kPiece = 1 << 30;
    for (std::size_t first = 0; first < flags.size(); first += kPiece)
      MPI_Allreduce(MPI_IN_PLACE, flags.data() + first, static_cast<int>(std::min(kPiece, flags.size() - first)),
                    MPI_SIGNED_CHAR, MPI_MAX, comm_);
  }

  double min(double x) const { return reduce(x, MPI_MIN); }
  // The sum modulo 2^64 (of checksums).
  std::uint64_t sum_modulo(std::uint64_t x) const {
    std::uint64_t r = 0;
    const CommunicationTimer timer;
    MPI_Allreduce(&x, &r, 1, MPI_UINT64_T, MPI_SUM, comm_);
    return r;
  }
  // The sum of x over the ranks before this one (0 on rank 0).
  long long sum_before(long long x) const {
    long long r = 0;
    const CommunicationTimer timer;
    MPI_Exscan(&x, &r, 1, MPI_LONG_LONG, MPI_SUM, comm_);
    return rank_ == 0 ? 0 : r;
  }
  // Every rank's values, concatenated in rank order, on rank 0 (empty
  // elsewhere); at most 2^31 - 1 of them in all, MPI counting in int.
  std::vector<long long> gather(const std::vector<long long>& values) const {
    const long long count = static_cast<long long>(values.size());
    std::vector<long long> counts(size_);
    MPI_Gather(&count, 1, MPI_LONG_LONG, counts.data(), 1, MPI_LONG_LONG, 0, comm_);
    std::vector<int> lengths(size_), offsets(size_, 0);
    long long total = 0;
    for (int r = 0; r < size_; ++r) {
      lengths[r] = static_cast<int>(counts[r]);
      offsets[r] = static_cast<int>(total);
      total += counts[r];
    }
    std::vector<long long> all(rank_ == 0 ? static_cast<size_t>(total) : 0);
    MPI_Gatherv(values.data(), static_cast<int>(count), MPI_LONG_LONG, all.data(), lengths.data(), offsets.data(),
                MPI_LONG_LONG, 0, comm_);
    return all;
  }
  // Every rank's values, concatenated in rank order, on every rank; counts:
  // how many each rank gives, the same on every call with the same sizes
  // (the caller keeps them: all_gather_counts).
  std::vector<int> all_gather_counts(int count) const {
    std::vector<int> counts(size_);
    MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm_);
    return counts;
  }
  template <class T>
  void all_gather(const T* values, const std::vector<int>& counts, T* all) const {
    std::vector<int> offsets(size_, 0);
    for (int r = 1; r < size_; ++r) offsets[r] = offsets[r - 1] + counts[r - 1];
    static_assert(std::is_same<T, double>::value || std::is_same<T, long long>::value, "all_gather: double or long long");
    const MPI_Datatype type = std::is_same<T, double>::value ? MPI_DOUBLE : MPI_LONG_LONG;
    MPI_Allgatherv(values, counts[rank_], type, all, counts.data(), offsets.data(), type, comm_);
  }
  // Rank 0's flag, on every rank.
  bool broadcast(bool flag) const {
    int value = flag ? 1 : 0;
    MPI_Bcast(&value, 1, MPI_INT, 0, comm_);
    return value != 0;
  }

  // The processes of this communicator on this machine (which share its memory).
  int on_this_machine() const {
    MPI_Comm machine;
    MPI_Comm_split_type(comm_, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &machine);
    int n = 1;
    MPI_Comm_size(machine, &n);
    MPI_Comm_free(&machine);
    return n;
  }
  // The problem of the lowest rank that has one, on every rank ("" when none has):
  // a refusal found on some processes is every process's.
  std::string first_problem(const std::string& problem) const {
    int first = problem.empty() ? size_ : rank_;
    MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_INT, MPI_MIN, comm_);
    if (first == size_) return "";
    int length = static_cast<int>(problem.size());
    MPI_Bcast(&length, 1, MPI_INT, first, comm_);
    std::string message = rank_ == first ? problem : std::string(static_cast<size_t>(length), '\0');
    MPI_Bcast(message.data(), length, MPI_CHAR, first, comm_);
    return message;
  }

  // Every rank's text, concatenated in rank order, on rank 0 (empty elsewhere).
  std::string gather_text(const std::string& text) const {
    const int length = static_cast<int>(text.size());
    std::vector<int> lengths(size_), offsets(size_, 0);
    MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, comm_);
    int total = 0;
    for (int r = 0; r < size_; ++r) offsets[r] = total, total += lengths[r];
    std::string all(rank_ == 0 ? total : 0, '\0');
    MPI_Gatherv(text.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR, 0, comm_);
    return all;
  }

 private:
  double reduce(double x, MPI_Op op) const {
    double r = 0;
    const CommunicationTimer timer;
    MPI_Allreduce(&x, &r, 1, MPI_DOUBLE, op, comm_);
    return r;
  }
  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
};

}  // namespace poresph
