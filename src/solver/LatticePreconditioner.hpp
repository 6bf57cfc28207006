#pragma once
// A lattice Laplacian (solver/LatticeMultigrid.hpp) as the preconditioner of
// an operator on the fluid particles of a fixed-particle scene: the compact
// one (stride 1) for the velocity block, the wide one (stride 2, the 2^Dim
// sub-lattices of spacing 2, each a compact Laplacian) for the pressure
// operator DG, whose weak modes, like the wide Laplacian's, sit at the
// corners of the Brillouin zone (docs/steady_solver.md).
//
// Every process holds the whole lattice: the right-hand side is gathered
// (MPI_Allgatherv), and the sub-lattices' cycles are shared out, sub-lattice
// l to process l mod the processes; the pattern weights' coarse corrections
// and the cycles' results are gathered again, and each process keeps the
// values of its own particles. The arithmetic is the same on any number of
// processes. Set-up and memory are those of the whole lattice on each
// process: enough for a few processes, not for many.
#include <Kokkos_Core.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "parallel/Communicator.hpp"
#include "solver/LatticeMultigrid.hpp"
#include "solver/LatticeSharpening.hpp"

namespace poresph {

template <int Dim, class ExecSpace>
class LatticePreconditioner {
 public:
  using MemorySpace = typename ExecSpace::memory_space;
  using View = Kokkos::View<double*, MemorySpace>;
  using Multigrid = LatticeMultigrid<Dim, ExecSpace>;

  LatticePreconditioner() = default;

  // x: positions of the owned particles; fluid: 1 for a fluid particle, 0
  // else; lattice: points per axis of the cell at spacing dx; stride 1 or 2.
  template <class Positions>
  LatticePreconditioner(const ExecSpace& space, const Communicator& comm, const Positions& x, const View& fluid,
                        int owned, const std::array<int, Dim>& lattice, double dx, int stride)
      : space_(space), comm_(comm) {
    auto hx = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), x);
    auto hf = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fluid);
    std::vector<long long> mine;
    for (int i = 0; i < owned; ++i) {
      if (hf(i) == 0) continue;
      own_.push_back(i);
      long long g = 0, s = 1;
      for (int d = 0; d < Dim; ++d) {
        g += static_cast<long long>(std::floor(hx(i, d) / dx)) * s;
        s *= lattice[d];
      }
      mine.push_back(g);
    }
    counts_ = comm_.all_gather_counts(static_cast<int>(mine.size()));
    long long total = 0;
    for (int c : counts_) total += c;
    std::vector<long long> all(total);
    comm_.all_gather(mine.data(), counts_, all.data());
    // Stride 2: along an axis of an even number of points, the points two
    // apart make two lattices (even and odd coordinates), point c at c / 2 of
    // its own; along an odd one, they make one ring through all of them, point
    // c at c (n + 1) / 2 mod n, where c + 2 is the next. Stride 1: the lattice.
    std::array<int, Dim> shape;
    int lattices = 1;
    std::array<bool, Dim> split{};
    for (int d = 0; d < Dim; ++d) {
      split[d] = stride == 2 && lattice[d] % 2 == 0;
      shape[d] = split[d] ? lattice[d] / 2 : lattice[d];
      pattern_bit_[d] = split[d] ? pattern_bits_++ : -1;
      if (split[d]) lattices *= 2;
    }
    long long points = 1;
    for (int d = 0; d < Dim; ++d) points *= shape[d];
    std::vector<std::vector<char>> active(lattices, std::vector<char>(points, 0));
    sub_.resize(total), local_.resize(total);
    for (long long k = 0; k < total; ++k) {
      long long rest = all[k], local = 0, s = 1;
      int sub = 0, bit = 0;
      for (int d = 0; d < Dim; ++d) {
        const long long c = rest % lattice[d];
        rest /= lattice[d];
        long long position = c;
        if (split[d]) {
          sub |= static_cast<int>(c % 2) << bit++;
          position = c / 2;
        } else if (stride == 2) {
          position = c * ((lattice[d] + 1) / 2) % lattice[d];
        }
        local += position * s;
        s *= shape[d];
      }
      sub_[k] = sub, local_[k] = local;
      active[sub][local] = 1;
    }
    lattice_ = lattice;
    lattice_index_ = std::move(all);
    for (int l = 0; l < lattices; ++l) {
      mine_.push_back(is_mine(l));
      multigrid_.emplace_back(space, shape, active[l]);
    }
    // The sub-lattices in gathered order: by owner, then by index.
    const int processes = comm_.size();
    slot_.resize(lattices);
    int slot = 0;
    std::vector<int> owned_lattices(processes, 0);
    for (int r = 0; r < processes; ++r)
      for (int l = r; l < lattices; l += processes) slot_[l] = slot++, ++owned_lattices[r];
    const long long coarse_points = multigrid_.front().coarse_correction().extent(0);
    for (int r = 0; r < processes; ++r) {
      z_counts_.push_back(static_cast<int>(owned_lattices[r] * points));
      coarse_counts_.push_back(static_cast<int>(owned_lattices[r] * coarse_points));
    }
    points_ = points, coarse_points_ = coarse_points;
    gathered_ = std::vector<double>(total);
    offset_ = 0;
    for (int r = 0; r < comm_.rank(); ++r) offset_ += counts_[r];
  }

  bool available() const { return !multigrid_.empty(); }

  // Sign patterns: with stride 2, pattern m (bits over the split axes, in
  // axis order) is (-1)^(m . c) at lattice coordinate c; it is constant on
  // each sub-lattice, so every point of a block of 2^bits points (one per
  // sub-lattice, the same point of each) sees the pattern's Walsh function
  // of its sub-lattice index. pattern_bit(d): axis d's bit, or -1.
  int patterns() const { return 1 << pattern_bits_; }
  int pattern_bit(int axis) const { return pattern_bit_[axis]; }
  // Weights w_m of the patterns' smooth parts: the sub-lattices' cycles
  // meet at their second level, where a point is the same block of 4^Dim
  // lattice points on every sub-lattice, and pattern m's part of the coarse
  // correction there is multiplied by w_m; the post-smoothing then takes
  // the weight back from what is not smooth. With c_m the operator's size
  // against L on pattern m times a smooth mode, w_m = c_0 / c_m would make
  // the cycle the operator's inverse on the smooth part of every pattern,
  // where L alone is right on the smooth modes only; the steady solver takes
  // (c_0 / c_m)^(1/2), which measured better (SteadySolver).
  void set_pattern_weights(const std::vector<double>& weights) { pattern_weights_ = weights; }
  // The cycle's result multiplied by prod_d (1 + beta sin^2(k_d / 2)) on the
  // whole lattice (solver/LatticeSharpening.hpp); beta = 0: not.
  void set_sharpening(double beta) {
    sharpening_ = beta;
    lattice_active_.clear(), lattice_z_.clear(), lattice_scratch_.clear();
    if (beta == 0) return;
    long long points = 1;
    for (int d = 0; d < Dim; ++d) points *= lattice_[d];
    lattice_active_.assign(static_cast<size_t>(points), 0.0f);
    for (long long g : lattice_index_) lattice_active_[g] = 1.0f;
    // Zero off the unknowns, and kept so: every apply writes the unknowns'
    // points only, and every pass of the sharpening leaves the others 0.
    lattice_z_.assign(static_cast<size_t>(points), 0.0f);
    lattice_scratch_.assign(static_cast<size_t>(points), 0.0f);
  }
  // What this process holds for it, in doubles (for the memory report): per
  // gathered value the value, its sub-lattice, its point there and on the
  // whole lattice; per lattice point the gathered z (with more than one
  // process) and the multigrid's diagonal, its inverse, couplings, x and b
  // on every level (a 2^-Dim geometric series); with the sharpening, its
  // mask and two fields (floats) over the whole lattice.
  double values_held() const {
    double values = 3.5 * static_cast<double>(gathered_.size()) + static_cast<double>(own_.size());
    values += 1.5 * static_cast<double>(lattice_active_.size());
    const double levels = (1 << Dim) / ((1 << Dim) - 1.0);
    const double level_value = sizeof(typename Multigrid::Field::value_type) / double(sizeof(double));
    const double gathered_z = comm_.size() > 1 ? 1.0 : 0.0;
    for (const auto& multigrid : multigrid_)
      values += (gathered_z + (4.0 + Dim) * levels * level_value) * static_cast<double>(multigrid.size());
    return values;
  }

  // z = (one V-cycle of the lattice Laplacian per sub-lattice) r, on the fluid entries.
  void apply(const View& r, const View& z) const {
    auto hr = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), r);
    const int lattices = static_cast<int>(multigrid_.size());
    const bool alone = comm_.size() == 1;
    // Every value lands on its own point of its sub-lattice's finest
    // right-hand side, the same points at every apply: the other points
    // keep the zero they were made with. Alone, straight from r.
    std::vector<decltype(Kokkos::create_mirror_view(multigrid_[0].finest_b()))> hb(lattices);
    std::vector<float*> b(lattices, nullptr);
    for (int l = 0; l < lattices; ++l)
      if (is_mine(l)) hb[l] = Kokkos::create_mirror_view(multigrid_[l].finest_b()), b[l] = hb[l].data();
    if (alone) {
      for (size_t k = 0; k < own_.size(); ++k) b[sub_[k]][local_[k]] = static_cast<float>(hr(own_[k]));
    } else {
      std::vector<double>& mine = own_values_;
      mine.resize(own_.size());
      for (size_t k = 0; k < own_.size(); ++k) mine[k] = hr(own_[k]);
      comm_.all_gather(mine.data(), counts_, gathered_.data());
      for (size_t k = 0; k < gathered_.size(); ++k)
        if (mine_[sub_[k]]) b[sub_[k]][local_[k]] = static_cast<float>(gathered_[k]);
    }
    for (int l = 0; l < lattices; ++l)
      if (is_mine(l)) {
        Kokkos::deep_copy(multigrid_[l].finest_b(), hb[l]);
        multigrid_[l].cycle_down();
      }
    if (!pattern_weights_.empty() && coarse_points_ > 0) {
      // Every sub-lattice's coarse correction, weighed where it is a block's
      // pattern amplitudes, and each process's own written back.
      gather_own(coarse_counts_, coarse_points_, [&](int l) { return multigrid_[l].coarse_correction(); },
                 own_coarse_, all_coarse_);
      std::vector<HostSlice> coarse;
      for (int l = 0; l < lattices; ++l) coarse.push_back(slice(all_coarse_, slot_[l], coarse_points_));
      weigh_patterns(coarse);
      for (int l = 0; l < lattices; ++l)
        if (is_mine(l)) copy_values(coarse[l], multigrid_[l].coarse_correction());
    }
    for (int l = 0; l < lattices; ++l)
      if (is_mine(l)) multigrid_[l].cycle_up();
    // The result of gathered value g: alone, on its sub-lattice's finest x;
    // else from every process's sub-lattices gathered.
    std::vector<decltype(Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), multigrid_[0].finest_x()))> hx(
        lattices);
    std::vector<const float*> x(lattices, nullptr);
    if (alone) {
      for (int l = 0; l < lattices; ++l)
        hx[l] = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), multigrid_[l].finest_x()), x[l] = hx[l].data();
    } else {
      gather_own(z_counts_, points_, [&](int l) { return multigrid_[l].finest_x(); }, own_z_, all_z_);
    }
    auto result = [&](long long g) -> double {
      return alone ? static_cast<double>(x[sub_[g]][local_[g]]) : all_z_[slot_[sub_[g]] * points_ + local_[g]];
    };
    auto out = Kokkos::create_mirror_view(z);
    Kokkos::deep_copy(out, 0.0);
    if (sharpening_ > 0) {
      // Every process sharpens the whole lattice, which it holds anyway,
      // and keeps its own points.
      for (size_t g = 0; g < lattice_index_.size(); ++g)
        lattice_z_[lattice_index_[g]] = static_cast<float>(result(static_cast<long long>(g)));
      sharpen_lattice<Dim>(lattice_z_, lattice_scratch_, lattice_, lattice_active_, sharpening_);
      for (size_t k = 0; k < own_.size(); ++k) out(own_[k]) = lattice_z_[lattice_index_[offset_ + k]];
    } else {
      for (size_t k = 0; k < own_.size(); ++k) out(own_[k]) = result(offset_ + static_cast<long long>(k));
    }
    Kokkos::deep_copy(z, out);
  }

 private:
  using HostSlice = Kokkos::View<double*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>>;
  bool is_mine(int lattice) const { return lattice % comm_.size() == comm_.rank(); }
  static HostSlice slice(std::vector<double>& values, long long slot, long long length) {
    return HostSlice(values.data() + slot * length, length);
  }
  // to = from, where the two may hold different scalars (the multigrid's
  // levels hold floats), through host copies.
  template <class From, class To>
  static void copy_values(const From& from, const To& to) {
    auto host_from = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), from);
    auto host_to = Kokkos::create_mirror_view(to);
    using Value = typename To::value_type;
    for (size_t p = 0; p < from.extent(0); ++p) host_to(p) = static_cast<Value>(host_from(p));
    Kokkos::deep_copy(to, host_to);
  }
  // all = every sub-lattice's values(l) (length each), in gathered order;
  // own: this process's, the buffer it sends. With one process they are one.
  template <class ValuesOf>
  void gather_own(const std::vector<int>& counts, long long length, ValuesOf values, std::vector<double>& own,
                  std::vector<double>& all) const {
    const int lattices = static_cast<int>(multigrid_.size());
    const bool alone = comm_.size() == 1;
    own.resize(alone ? 0 : static_cast<size_t>(counts[comm_.rank()]));
    all.resize(static_cast<size_t>(lattices * length));
    long long first_slot = lattices;
    for (int l = 0; l < lattices; ++l)
      if (is_mine(l)) first_slot = std::min<long long>(first_slot, slot_[l]);
    for (int l = 0; l < lattices; ++l)
      if (is_mine(l))
        copy_values(values(l), alone ? slice(all, slot_[l], length) : slice(own, slot_[l] - first_slot, length));
    if (!alone) comm_.all_gather(own.data(), counts, all.data());
  }

  // Per point (a block of the lattice): the Walsh-Hadamard transform of its
  // 2^bits values (one per sub-lattice) gives 2^bits times the pattern
  // amplitudes; scale amplitude m by w_m and transform back (the transform
  // is its own inverse up to 2^bits).
  template <class Values>
  void weigh_patterns(std::vector<Values>& values) const {
    const int n = patterns();
    const long long points = static_cast<long long>(values.front().extent(0));
    std::vector<double> v(n);
    auto transform = [&]() {
      for (int half = 1; half < n; half *= 2)
        for (int s = 0; s < n; ++s)
          if (!(s & half)) {
            const double a = v[s], b = v[s + half];
            v[s] = a + b, v[s + half] = a - b;
          }
    };
    for (long long p = 0; p < points; ++p) {
      for (int s = 0; s < n; ++s) v[s] = values[s](p);
      transform();
      for (int m = 0; m < n; ++m) v[m] *= pattern_weights_[m] / n;
      transform();
      for (int s = 0; s < n; ++s) values[s](p) = v[s];
    }
  }

  ExecSpace space_;
  Communicator comm_;
  std::vector<int> own_;           // owned fluid particles, in the order gathered
  std::vector<int> counts_;        // fluid particles per process
  long long offset_ = 0;           // this process's first in the gathered order
  std::vector<int> sub_;           // per gathered value: its sub-lattice
  std::vector<long long> local_;   // and its point there
  std::vector<char> mine_;         // per sub-lattice: is_mine(), looked up per value without a division
  std::vector<Multigrid> multigrid_;
  std::vector<long long> slot_;                // per sub-lattice: its place in the gathered order
  std::vector<int> z_counts_, coarse_counts_;  // per process: the values of its sub-lattices it gives
  long long points_ = 0, coarse_points_ = 0;   // a sub-lattice's points, and its second level's
  // This process's values and everyone's, kept from one apply to the next:
  // a vector made afresh each time was fresh pages each time (glibc maps
  // blocks this large), 15,000 page faults a second on problem III at 0.00125 L.
  mutable std::vector<double> own_values_, gathered_, own_z_, all_z_, own_coarse_, all_coarse_;
  std::array<int, Dim> pattern_bit_{};
  int pattern_bits_ = 0;
  std::vector<double> pattern_weights_;  // empty: all 1
  std::array<int, Dim> lattice_{};        // points per axis of the whole lattice
  std::vector<long long> lattice_index_;  // per gathered value: its point on the whole lattice
  double sharpening_ = 0;                 // beta; 0: none
  std::vector<float> lattice_active_;     // with a sharpening: 1 on the unknowns' points, else 0
  mutable std::vector<float> lattice_z_, lattice_scratch_;
};

}  // namespace poresph
