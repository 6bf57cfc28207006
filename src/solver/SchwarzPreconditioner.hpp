#pragma once
// Restricted additive Schwarz (Cai & Sarkis 1999) on an operator of the
// fluid particles of a fixed-particle scene: the lattice cut into blocks of
// `block` points a side, each extended by `overlap` points a side; the
// operator restricted to an extended block's fluid points and solved there
// by dense LU; each block's solution kept on its own points. Two levels: a
// coarse solve first, one unknown per connected part of a block's own fluid
// points with the Galerkin operator P^T A P, and the local solves of the
// residual it leaves (one product of the operator an application). The steady
// solver's DG has weak modes in passages one or two particles wide that are
// local, within about 12 spacings, and that a lattice Laplacian's cycle does
// not resolve (docs/steady_solver.md, "What fails on a blobs image").
//
// The operator's entries are probed: the fluid points whose lattice
// coordinates agree modulo M_d along every axis (M_d beyond twice the
// operator's reach, and the cell's wrap no nearer) are one colour, applied
// together, and each row a colour changes belongs to the one point of that
// colour within reach. One product per colour: (2 reach + 1)^Dim or more.
//
// Every process holds every fluid point's place and the gathered vector;
// process b mod P factors and solves block b. Like LatticePreconditioner:
// the same arithmetic on any number of processes, enough for a few.
#include <Kokkos_Core.hpp>
#include <Teuchos_LAPACK.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "core/Math.hpp"
#include "parallel/Communicator.hpp"

namespace poresph {

// w = A^-1 w for A = P L U of n x n in LAPACK's getrf form (column-major,
// L's unit diagonal implied, pivots 1-based row interchanges).
KOKKOS_INLINE_FUNCTION void lu_solve(int n, const double* lu, const int* pivots, double* w) {
  for (int k = 0; k < n; ++k) {
    const int p = pivots[k] - 1;
    if (p != k) {
      const double t = w[k];
      w[k] = w[p], w[p] = t;
    }
  }
  for (int j = 0; j < n; ++j) {
    const double wj = w[j];
    const double* column = lu + static_cast<long long>(j) * n;
    for (int i = j + 1; i < n; ++i) w[i] -= column[i] * wj;
  }
  for (int j = n - 1; j >= 0; --j) {
    const double* column = lu + static_cast<long long>(j) * n;
    const double wj = w[j] / column[j];
    w[j] = wj;
    for (int i = 0; i < j; ++i) w[i] -= column[i] * wj;
  }
}

// The smallest M >= least that tiles n points periodically without bringing
// two points of one residue nearer than `least`: n mod M is 0 or at least
// `least`. n itself (every point its own residue) if nothing smaller does.
inline int colour_modulus(int n, int least) {
  for (int m = least; m < n; ++m)
    if (n % m == 0 || n % m >= least) return m;
  return n;
}

template <int Dim, class ExecSpace>
class SchwarzPreconditioner {
 public:
  using MemorySpace = typename ExecSpace::memory_space;
  using View = Kokkos::View<double*, MemorySpace>;

  SchwarzPreconditioner() = default;

  // x: positions of the owned particles; fluid: 1 for a fluid particle, 0
  // else; lattice: points per axis of the cell at spacing dx. apply(in, out):
  // the operator on vectors of the owned particles, coupling no two points
  // more than `reach` spacings apart along an axis, kept for the coarse
  // level's residual (it must stay valid while this is applied). Each local block, and
  // the coarse operator, gets `shift` times its largest diagonal entry added
  // to its diagonal: a closed pocket's block is singular, and so is the
  // coarse operator on each region's constant where the operator is.
  template <class Positions, class Operator>
  SchwarzPreconditioner(const ExecSpace& space, const Communicator& comm, const Positions& x, const View& fluid,
                        int owned, const std::array<int, Dim>& lattice, double dx, int block, int overlap, int reach,
                        double shift, Operator&& apply)
      : space_(space), comm_(comm), lattice_(lattice) {
    auto hx = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), x);
    auto hf = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fluid);
    std::vector<long long> mine;
    for (int i = 0; i < owned; ++i) {
      if (hf(i) == 0) continue;
      own_host_.push_back(i);
      std::array<int, Dim> c;
      for (int d = 0; d < Dim; ++d) c[d] = static_cast<int>(std::floor(hx(i, d) / dx));
      mine.push_back(key_of(c));
    }
    counts_ = comm_.all_gather_counts(static_cast<int>(mine.size()));
    long long total = 0;
    for (int r = 0; r < comm_.size(); ++r) {
      if (r == comm_.rank()) offset_ = total;
      total += counts_[r];
    }
    keys_.resize(total);
    comm_.all_gather(mine.data(), counts_, keys_.data());
    by_key_.reserve(total);
    for (long long g = 0; g < total; ++g) by_key_.emplace_back(keys_[g], g);
    std::sort(by_key_.begin(), by_key_.end());
    axis_blocks(block, overlap);
    collect_members();
    find_aggregates();
    const auto entries = probe(owned, reach, apply);
    factor(entries, shift);
    factor_coarse(shift);
    operator_ = apply;
    coarse_in_ = View("schwarz_coarse_in", owned), coarse_residual_ = View("schwarz_coarse_residual", owned);
    gathered_ = View("schwarz_gathered", total);
    result_ = View("schwarz_result", total);
    own_ = Kokkos::View<int*, MemorySpace>("schwarz_own", own_host_.size());
    auto own = Kokkos::create_mirror_view(own_);
    for (size_t k = 0; k < own_host_.size(); ++k) own(k) = own_host_[k];
    Kokkos::deep_copy(own_, own);
  }

  bool available() const { return !keys_.empty(); }
  // Rows a probe changed with no point of its colour within reach: 0 unless
  // the operator reaches further than it was said to.
  long long unmatched() const { return unmatched_; }
  // The blocks this process solves.
  int blocks() const { return static_cast<int>(block_start_host_.size()) - 1; }
  // The coarse level's aggregates, and per fluid point (in the gathered
  // order: process by process, each in its particles' order) its own;
  // whether the coarse level is used.
  int aggregates() const { return aggregates_; }
  const std::vector<int>& aggregate() const { return aggregate_; }
  bool two_level() const { return !coarse_lu_.empty(); }
  // What this process holds for it, in doubles (for the memory report): the
  // blocks' and the coarse level's factors, per member its point, pivot and
  // whether it is the block's own (about 2 doubles), per fluid point its
  // aggregate, and the gathered vector and its result.
  double values_held() const {
    return static_cast<double>(factors_.extent(0)) + static_cast<double>(coarse_lu_.size()) +
           static_cast<double>(aggregate_.size()) + 2.0 * static_cast<double>(members_.extent(0)) +
           2.0 * static_cast<double>(keys_.size()) + static_cast<double>(own_host_.size());
  }

  // z = P Ac^-1 P^T r + the local solves of what is left, r - A P Ac^-1 P^T r.
  void apply(const View& r, const View& z) const {
    if (coarse_lu_.empty()) {
      apply_local(r, z);
      return;
    }
    solve_coarse(r, coarse_in_);
    operator_(coarse_in_, coarse_residual_);
    const auto residual = coarse_residual_;
    static const std::string label = "poresph::schwarz::coarse_residual";
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(space_, 0, r.extent(0)),
        KOKKOS_LAMBDA(int i) { residual(i) = r(i) - residual(i); });
    space_.fence();
    apply_local(coarse_residual_, z);
    const auto coarse = coarse_in_;
    static const std::string label_add = "poresph::schwarz::add_coarse";
    Kokkos::parallel_for(
        label_add, Kokkos::RangePolicy<ExecSpace>(space_, 0, r.extent(0)), KOKKOS_LAMBDA(int i) { z(i) += coarse(i); });
    space_.fence();
  }

  // The coarse level alone: z = P Ac^-1 P^T r, P the aggregates' indicators.
  void solve_coarse(const View& r, const View& z) const {
    auto hr = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), r);
    std::vector<double>& c = coarse_values_;
    c.assign(aggregates_, 0.0);
    for (size_t k = 0; k < own_host_.size(); ++k) c[aggregate_[offset_ + k]] += hr(own_host_[k]);
    if (comm_.size() > 1) comm_.sum(c.data(), aggregates_);
    lu_solve(aggregates_, coarse_lu_.data(), coarse_pivots_.data(), c.data());
    auto hz = Kokkos::create_mirror_view(z);
    Kokkos::deep_copy(hz, 0.0);
    for (size_t k = 0; k < own_host_.size(); ++k) hz(own_host_[k]) = c[aggregate_[offset_ + k]];
    Kokkos::deep_copy(z, hz);
  }

  // z = the sum over blocks of each block's local solve of r, on its own points.
  void apply_local(const View& r, const View& z) const {
    const auto gathered = gathered_, result = result_;
    const auto own = own_;
    const long long offset = offset_;
    if (comm_.size() == 1) {
      static const std::string label = "poresph::schwarz::gather";
      Kokkos::parallel_for(
          label, Kokkos::RangePolicy<ExecSpace>(space_, 0, own.extent(0)),
          KOKKOS_LAMBDA(int k) { gathered(k) = r(own(k)); });
    } else {
      auto hr = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), r);
      std::vector<double> values(own_host_.size());
      for (size_t k = 0; k < own_host_.size(); ++k) values[k] = hr(own_host_[k]);
      auto hg = Kokkos::create_mirror_view(gathered_);
      comm_.all_gather(values.data(), counts_, hg.data());
      Kokkos::deep_copy(gathered_, hg);
      Kokkos::deep_copy(space_, result_, 0.0);
    }
    const auto start = block_start_, members = members_, pivots = pivots_;
    const auto factor_start = factor_start_;
    const auto factors = factors_;
    const auto work = work_;
    const auto owns = owns_;
    static const std::string label_solve = "poresph::schwarz::local_solves";
    Kokkos::parallel_for(
        label_solve, Kokkos::RangePolicy<ExecSpace>(space_, 0, blocks()), KOKKOS_LAMBDA(int b) {
          const long long first = start(b);
          const int n = static_cast<int>(start(b + 1) - first);
          double* w = &work(first);
          for (int k = 0; k < n; ++k) w[k] = gathered(members(first + k));
          lu_solve(n, &factors(factor_start(b)), &pivots(first), w);
          for (int k = 0; k < n; ++k)
            if (owns(first + k)) result(members(first + k)) = w[k];
        });
    space_.fence();
    if (comm_.size() > 1) {
      auto hres = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), result_);
      comm_.sum(hres.data(), static_cast<int>(hres.extent(0)));
      Kokkos::deep_copy(result_, hres);
    }
    Kokkos::deep_copy(space_, z, 0.0);
    static const std::string label_scatter = "poresph::schwarz::scatter";
    Kokkos::parallel_for(
        label_scatter, Kokkos::RangePolicy<ExecSpace>(space_, 0, own.extent(0)),
        KOKKOS_LAMBDA(int k) { z(own(k)) = result(offset + k); });
    space_.fence();
  }

 private:
  struct Entry {
    long long row, column;
    double value;
  };

  long long key_of(const std::array<int, Dim>& c) const {
    long long key = 0, stride = 1;
    for (int d = 0; d < Dim; ++d) {
      key += static_cast<long long>(((c[d] % lattice_[d]) + lattice_[d]) % lattice_[d]) * stride;
      stride *= lattice_[d];
    }
    return key;
  }
  std::array<int, Dim> coordinates(long long key) const {
    std::array<int, Dim> c;
    for (int d = 0; d < Dim; ++d) c[d] = static_cast<int>(key % lattice_[d]), key /= lattice_[d];
    return c;
  }
  long long find(long long key) const {
    const auto it = std::lower_bound(by_key_.begin(), by_key_.end(), std::make_pair(key, 0LL));
    return it != by_key_.end() && it->first == key ? it->second : -1;
  }

  // Along each axis, the blocks whose extended range holds coordinate c
  // (within `overlap` of the block's own points, periodically; a block whose
  // extension would wrap onto itself holds the whole axis).
  void axis_blocks(int block, int overlap) {
    block_ = block;
    for (int d = 0; d < Dim; ++d) {
      const int n = lattice_[d];
      block_count_[d] = (n + block - 1) / block;
      held_[d].assign(n, {});
      for (int j = 0; j < block_count_[d]; ++j) {
        const int first = j * block, last = std::min(n, first + block);
        const bool whole = last - first + 2 * overlap >= n;
        for (int c = 0; c < n; ++c) {
          const int before = ((first - c) % n + n) % n, after = ((c - (last - 1)) % n + n) % n;
          const bool inside = c >= first && c < last;
          if (whole || inside || before <= overlap || after <= overlap) held_[d][c].push_back(j);
        }
      }
    }
  }
  // Whether some block's extended range holds both points.
  bool share_a_block(const std::array<int, Dim>& a, const std::array<int, Dim>& b) const {
    for (int d = 0; d < Dim; ++d) {
      const auto &ha = held_[d][a[d]], &hb = held_[d][b[d]];
      bool common = false;
      for (int j : ha) common = common || std::find(hb.begin(), hb.end(), j) != hb.end();
      if (!common) return false;
    }
    return true;
  }
  // The blocks (flat index over the block grid) whose extended range holds c.
  std::vector<int> blocks_holding(const std::array<int, Dim>& c) const {
    std::vector<int> flat{0};
    int stride = 1;
    for (int d = 0; d < Dim; ++d) {
      std::vector<int> next;
      for (int f : flat)
        for (int j : held_[d][c[d]]) next.push_back(f + j * stride);
      flat = std::move(next);
      stride *= block_count_[d];
    }
    return flat;
  }
  // The block whose own range holds c.
  int block_owning(const std::array<int, Dim>& c) const {
    int flat = 0, stride = 1;
    for (int d = 0; d < Dim; ++d) flat += (c[d] / block_) * stride, stride *= block_count_[d];
    return flat;
  }
  bool is_mine(int flat) const { return flat % comm_.size() == comm_.rank(); }

  // Each of this process's blocks: its fluid points (global indices, sorted)
  // and which of them it owns (its own range, not the overlap).
  void collect_members() {
    int all_blocks = 1;
    for (int d = 0; d < Dim; ++d) all_blocks *= block_count_[d];
    std::vector<std::vector<long long>> points(all_blocks);
    for (long long g = 0; g < static_cast<long long>(keys_.size()); ++g)
      for (int b : blocks_holding(coordinates(keys_[g])))
        if (is_mine(b)) points[b].push_back(g);
    for (int b = 0; b < all_blocks; ++b)
      if (is_mine(b) && !points[b].empty()) {
        local_block_.push_back(b);
        block_points_.push_back(std::move(points[b]));
      }
  }

  // The operator's entries between points that share a block, by one product
  // per colour; gathered from every process.
  template <class Operator>
  std::vector<Entry> probe(int owned, int reach, Operator& apply) {
    std::array<int, Dim> modulus;
    int colours = 1;
    for (int d = 0; d < Dim; ++d) modulus[d] = colour_modulus(lattice_[d], 2 * reach + 1), colours *= modulus[d];
    std::vector<std::array<int, Dim>> own_coordinates(own_host_.size());
    std::vector<int> colour(own_host_.size());
    for (size_t k = 0; k < own_host_.size(); ++k) {
      own_coordinates[k] = coordinates(keys_[offset_ + k]);
      int c = 0;
      for (int d = Dim - 1; d >= 0; --d) c = c * modulus[d] + own_coordinates[k][d] % modulus[d];
      colour[k] = c;
    }
    View in("schwarz_probe", owned), out("schwarz_probe_out", owned);
    auto hin = Kokkos::create_mirror_view(in);
    std::vector<Entry> entries;
    for (int c = 0; c < colours; ++c) {
      // Every process takes part in every product, with or without points of this colour.
      Kokkos::deep_copy(hin, 0.0);
      for (size_t k = 0; k < own_host_.size(); ++k)
        if (colour[k] == c) hin(own_host_[k]) = 1.0;
      Kokkos::deep_copy(in, hin);
      apply(in, out);
      auto hout = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), out);
      std::array<int, Dim> residue;
      for (int d = 0, rest = c; d < Dim; ++d) residue[d] = rest % modulus[d], rest /= modulus[d];
      for (size_t k = 0; k < own_host_.size(); ++k) {
        const double value = hout(own_host_[k]);
        if (value == 0) continue;
        // Per axis, the coordinate of this residue nearest (periodically) to the row's.
        std::array<int, Dim> column;
        bool within = true;
        for (int d = 0; d < Dim; ++d) {
          const int n = lattice_[d], p = own_coordinates[k][d];
          int best = -1, best_distance = n;
          for (int q = residue[d]; q < n; q += modulus[d]) {
            const int distance = std::min(std::abs(q - p), n - std::abs(q - p));
            if (distance < best_distance) best = q, best_distance = distance;
          }
          column[d] = best;
          within = within && best_distance <= reach;
        }
        const long long g = within ? find(key_of(column)) : -1;
        if (g < 0) {
          ++unmatched_;
          continue;
        }
        if (!coarse_.empty()) coarse_[aggregate_[offset_ + k] + aggregate_[g] * aggregates_] += value;
        if (share_a_block(own_coordinates[k], column))
          entries.push_back({offset_ + static_cast<long long>(k), g, value});
      }
    }
    unmatched_ = comm_.sum(unmatched_);
    if (!coarse_.empty()) comm_.sum(coarse_.data(), static_cast<int>(coarse_.size()));
    if (comm_.size() == 1) return entries;
    const int count = static_cast<int>(entries.size());
    const auto counts = comm_.all_gather_counts(count);
    long long total = 0;
    for (int n : counts) total += n;
    std::vector<long long> rows(count), columns(count), all_rows(total), all_columns(total);
    std::vector<double> values(count), all_values(total);
    for (int e = 0; e < count; ++e)
      rows[e] = entries[e].row, columns[e] = entries[e].column, values[e] = entries[e].value;
    comm_.all_gather(rows.data(), counts, all_rows.data());
    comm_.all_gather(columns.data(), counts, all_columns.data());
    comm_.all_gather(values.data(), counts, all_values.data());
    std::vector<Entry> all(total);
    for (long long e = 0; e < total; ++e) all[e] = {all_rows[e], all_columns[e], all_values[e]};
    return all;
  }

  // Each block's matrix from the entries, shifted and factored; then laid out for apply.
  void factor(const std::vector<Entry>& entries, double shift) {
    const int blocks = static_cast<int>(local_block_.size());
    // Laid out block after block: members, own flags and pivots, and the
    // matrices, each filled, shifted and factored in place.
    std::vector<long long> start{0}, factor_start{0};
    for (int s = 0; s < blocks; ++s) {
      const long long n = static_cast<long long>(block_points_[s].size());
      start.push_back(start.back() + n);
      factor_start.push_back(factor_start.back() + n * n);
    }
    int all_blocks = 1;
    for (int d = 0; d < Dim; ++d) all_blocks *= block_count_[d];
    std::vector<int> slot_of_block(all_blocks, -1);  // flat block index -> this process's slot, or -1
    for (int s = 0; s < blocks; ++s) slot_of_block[local_block_[s]] = s;
    auto position = [&](int s, long long g) -> long long {
      const auto& p = block_points_[s];
      const auto it = std::lower_bound(p.begin(), p.end(), g);
      return it != p.end() && *it == g ? it - p.begin() : -1;
    };
    std::vector<double> factors(factor_start.back(), 0.0);
    for (const Entry& e : entries)
      for (int b : blocks_holding(coordinates(keys_[e.row]))) {
        const int s = slot_of_block[b];
        if (s < 0) continue;
        const long long i = position(s, e.row), j = position(s, e.column);
        if (i < 0 || j < 0) continue;
        factors[factor_start[s] + i + j * (start[s + 1] - start[s])] += e.value;
      }
    std::vector<long long> members(start.back());
    std::vector<int> owns(start.back()), pivots(start.back());
    for (int s = 0; s < blocks; ++s) {
      const int n = static_cast<int>(block_points_[s].size());
      double* a = &factors[factor_start[s]];
      // An exactly singular block (no entries at all, say): the identity instead.
      if (shifted_lu(n, a, &pivots[start[s]], shift) != 0) {
        std::fill(a, a + static_cast<long long>(n) * n, 0.0);
        for (int i = 0; i < n; ++i) a[i + i * static_cast<long long>(n)] = 1.0, pivots[start[s] + i] = i + 1;
      }
      for (int k = 0; k < n; ++k) {
        const long long g = block_points_[s][k];
        members[start[s] + k] = g;
        owns[start[s] + k] = block_owning(coordinates(keys_[g])) == local_block_[s];
      }
    }
    block_start_host_ = start;
    block_start_ = to_device<long long>("schwarz_block_start", start);
    factor_start_ = to_device<long long>("schwarz_factor_start", factor_start);
    members_ = to_device<long long>("schwarz_members", members);
    owns_ = to_device<int>("schwarz_owns", owns);
    pivots_ = to_device<int>("schwarz_pivots", pivots);
    factors_ = to_device<double>("schwarz_factors", factors);
    work_ = View("schwarz_work", start.back());
  }

  // a (n x n, column-major) plus shift times its largest diagonal entry on
  // its diagonal, factored in place by LAPACK's getrf; getrf's info.
  static int shifted_lu(int n, double* a, int* pivots, double shift) {
    double largest = 0;
    for (int i = 0; i < n; ++i) largest = std::max(largest, std::fabs(a[i + i * static_cast<long long>(n)]));
    for (int i = 0; i < n; ++i) a[i + i * static_cast<long long>(n)] += shift * largest;
    int info = 0;
    Teuchos::LAPACK<int, double>().GETRF(n, n, a, n, pivots, &info);
    return info;
  }

  // The coarse level's aggregates: per block, the parts of its own fluid
  // points joined by lattice neighbours (corners included) within it.
  void find_aggregates() {
    const long long total = static_cast<long long>(keys_.size());
    aggregate_.assign(total, -1);
    aggregates_ = 0;
    std::vector<long long> stack;
    for (long long seed = 0; seed < total; ++seed) {
      if (aggregate_[seed] >= 0) continue;
      const int block = block_owning(coordinates(keys_[seed]));
      aggregate_[seed] = aggregates_;
      stack.assign(1, seed);
      while (!stack.empty()) {
        const auto c = coordinates(keys_[stack.back()]);
        stack.pop_back();
        for (int offset = 0; offset < ipow(3, Dim); ++offset) {
          std::array<int, Dim> n = c;
          for (int d = 0, rest = offset; d < Dim; ++d, rest /= 3) n[d] += rest % 3 - 1;
          const long long g = find(key_of(n));
          if (g < 0 || aggregate_[g] >= 0 || block_owning(coordinates(keys_[g])) != block) continue;
          aggregate_[g] = aggregates_;
          stack.push_back(g);
        }
      }
      ++aggregates_;
    }
    if (aggregates_ <= kMaxAggregates) coarse_.assign(static_cast<size_t>(aggregates_) * aggregates_, 0.0);
  }
  static constexpr int ipow(int base, int exponent) { return exponent == 0 ? 1 : base * ipow(base, exponent - 1); }

  // Ac = P^T A P (summed while probing), shifted as the blocks are, and
  // factored; every process the same.
  void factor_coarse(double shift) {
    if (coarse_.empty()) return;
    coarse_pivots_.assign(aggregates_, 0);
    if (shifted_lu(aggregates_, coarse_.data(), coarse_pivots_.data(), shift) == 0) coarse_lu_ = std::move(coarse_);
    std::vector<double>().swap(coarse_);
  }

  template <class T>
  static Kokkos::View<T*, MemorySpace> to_device(const std::string& label, const std::vector<T>& values) {
    Kokkos::View<T*, MemorySpace> view(label, values.size());
    auto host = Kokkos::create_mirror_view(view);
    for (size_t k = 0; k < values.size(); ++k) host(k) = values[k];
    Kokkos::deep_copy(view, host);
    return view;
  }

  ExecSpace space_;
  Communicator comm_;
  std::array<int, Dim> lattice_{};
  int block_ = 1;  // points a side of a block's own range
  std::array<int, Dim> block_count_{};
  std::array<std::vector<std::vector<int>>, Dim> held_;  // per axis and coordinate: the blocks holding it
  std::vector<int> own_host_;                            // owned fluid particles, in the order gathered
  std::vector<int> counts_;                              // fluid particles per process
  long long offset_ = 0;                                 // this process's first in the gathered order
  std::vector<long long> keys_;                          // per gathered point: its lattice point
  std::vector<std::pair<long long, long long>> by_key_;  // (lattice point, gathered index), sorted
  std::vector<int> local_block_;                         // this process's blocks (flat index)
  std::vector<std::vector<long long>> block_points_;     // their fluid points
  std::vector<long long> block_start_host_{0};
  long long unmatched_ = 0;
  // The coarse level: per gathered point its aggregate; Ac while probing,
  // then its factors (none: more aggregates than kMaxAggregates, whose
  // dense factors would take 288 MB or more, or a singular Ac).
  static constexpr int kMaxAggregates = 6000;
  std::vector<int> aggregate_;
  int aggregates_ = 0;
  std::vector<double> coarse_, coarse_lu_;
  std::vector<int> coarse_pivots_;
  mutable std::vector<double> coarse_values_;
  std::function<void(const View&, const View&)> operator_;  // A, for the residual the coarse level leaves
  View coarse_in_, coarse_residual_;
  Kokkos::View<long long*, MemorySpace> block_start_, factor_start_, members_;
  Kokkos::View<int*, MemorySpace> owns_, pivots_, own_;
  Kokkos::View<double*, MemorySpace> factors_;
  View gathered_, result_, work_;
};

}  // namespace poresph
