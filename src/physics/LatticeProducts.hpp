#pragma once
// The pressure gradient and the velocity divergence of fixed particles on
// one lattice (core/LatticeRows.hpp) as stencil sums over the lattice's
// sites: what the pair loop of the pressure term alone, or of continuity
// alone, adds to the fluid particles (physics/terms/PressureTerm.hpp,
// ContinuityTerm.hpp), for values given per particle slot (owned and
// ghosts). The steady solver's preconditioner applies these two operators
// hundreds of times a solve (solver/SteadySolver.hpp).
//
//   gradient:   a_i = -sum_j m_j (P_i + P_j) F_ij r_ij
//                   = -(P_i M_i + sum_k (m P)(s_i + step_k) F_k r_k),
//   divergence: d_i =  sum_j m_j (u_i - u_j) . F_ij r_ij
//                   =  u_i . M_i - sum_k (m u)(s_i + step_k) . F_k r_k,
//   viscous:    a_i = (2 nu / rho0) sum_j m_j F_ij (w_i - w_j)
//                   = (2 nu / rho0) (w_i M0_i - sum_k (m w)(s_i + step_k) F_k),
// with M_i = sum_j m_j F_ij r_ij over the particles in i's reach, s_i the
// site of particle i, k the stencil's offsets within the kernel's support
// (F_k = (1/r) dW/dr there, r_k = x_i - x_j) and (m P), (m u) the values
// times the masses spread over the sites, zero where no particle is. The
// viscous term is Morris's between fluid particles (physics/terms/
// ViscousTerm.hpp) with fixed particles' 1/rho0 for every 1/rho: its masses
// are given zero on other particles, whose share is the no-slip term's wall
// drag, and M0_i is their stencil sum (take_fluid_masses()). The pair loop
// finds each neighbour through masks and a map and adds each pair
// to both ends; here every fluid particle gathers from all its stencil's
// sites, and consecutive particles along x read consecutive sites, so the
// sum over a run of them is a vector operation per offset (runs of at most
// kRun consecutive fluid particles, summed as kRun lanes whatever their
// length: the lanes past a run's end read sites that are discarded, and the
// spread values are padded for them). Where some fluid particle's stencil
// leaves the map's box (a lattice with no particles beyond its fluid along
// an axis), the products are not made: built() is false.
#include <Kokkos_Core.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/LatticeRows.hpp"
#include "core/Particles.hpp"
#include "core/Vec.hpp"

namespace poresph {

template <int Dim, class ExecSpace>
class LatticeProducts {
 public:
  using MemorySpace = typename ExecSpace::memory_space;
  using Scalars = Kokkos::View<double*, MemorySpace>;
  using Rows = Kokkos::View<double**, Kokkos::LayoutRight, MemorySpace>;  // a row of Dim values per particle
  using Lattice = LatticeRows<Dim, ExecSpace>;
  static_assert(Kokkos::SpaceAccessibility<Kokkos::HostSpace, MemorySpace>::accessible,
                "the offsets are chosen on the host");
  // Sites a run holds at most: one vector register of doubles (AVX-512),
  // whose sums stay in registers.
  static constexpr int kRun = 8;

  LatticeProducts() = default;

  // From the rows of a built list and the particles as they are (owned and
  // ghosts: positions, kinds and masses current).
  LatticeProducts(const ExecSpace& space, const Lattice& rows, const Particles<Dim, MemorySpace>& P)
      : space_(space), rows_(rows), owned_(P.owned) {
    // The offsets within the support (F = 0 beyond it: the list's skin).
    const auto& stencil = rows.stencil();
    std::vector<int> ids;
    for (int id = 0; id < stencil.size(); ++id)
      if (stencil.of_distance(id) != 0.0) ids.push_back(id);
    offsets_ = static_cast<int>(ids.size());
    step_ = Kokkos::View<int*, MemorySpace>("LatticeProducts::step", offsets_);
    weight_ = Kokkos::View<double**, Kokkos::LayoutLeft, MemorySpace>("LatticeProducts::weight", offsets_, Dim);
    scalar_weight_ = Scalars("LatticeProducts::scalar_weight", offsets_);
    for (int k = 0; k < offsets_; ++k) {
      step_(k) = rows.step(ids[k]);
      scalar_weight_(k) = stencil.of_distance(ids[k]);
      for (int d = 0; d < Dim; ++d) weight_(k, d) = stencil.of_distance(ids[k]) * stencil.separation(ids[k], d);
    }
    // The runs of consecutive sites of owned fluid particles, each of
    // whose stencils lies inside the map's box.
    int reach[Dim] = {};
    for (int id : ids)
      for (int d = 0; d < Dim; ++d)
        reach[d] = std::max(reach[d], static_cast<int>(std::lround(std::fabs(stencil.separation(id, d)) /
                                                                    rows.spacing())));
    std::vector<int> fluid_sites;
    for (int i = 0; i < owned_; ++i) {
      if (P.kind(i) != kFluid) continue;
      const int site = rows.site(i);
      long long stride = 1;
      for (int d = 0; d < Dim; ++d) {
        const long long along = site / stride % rows.extent(d);
        if (along < reach[d] || along >= rows.extent(d) - reach[d]) return;  // not built
        stride *= rows.extent(d);
      }
      fluid_sites.push_back(site);
    }
    std::sort(fluid_sites.begin(), fluid_sites.end());
    std::vector<int> run_site, run_length;
    for (std::size_t k = 0; k < fluid_sites.size(); ++k) {
      const bool extends = !run_site.empty() && fluid_sites[k] == run_site.back() + run_length.back() &&
                           run_length.back() < kRun;
      if (extends) ++run_length.back();
      else run_site.push_back(fluid_sites[k]), run_length.push_back(1);
    }
    runs_ = static_cast<int>(run_site.size());
    run_site_ = Kokkos::View<int*, MemorySpace>("LatticeProducts::run_site", runs_);
    run_length_ = Kokkos::View<int*, MemorySpace>("LatticeProducts::run_length", runs_);
    for (int r = 0; r < runs_; ++r) run_site_(r) = run_site[r], run_length_(r) = run_length[r];
    site_values_ = Scalars("LatticeProducts::site_values", static_cast<std::size_t>(rows.sites()) * Dim + kRun);
    // M_i: the masses spread over the sites, gathered with the weights.
    moment_ = Rows("LatticeProducts::moment", owned_, Dim);
    spread(P.m, Scalars(), 1);
    const auto moment = moment_;
    gather(1, KOKKOS_LAMBDA(int i, const double* sum) {
      for (int d = 0; d < Dim; ++d) moment(i, d) = sum[d];
    });
  }

  bool built() const { return site_values_.extent(0) > 0; }
  // What the products hold, in doubles (ints count half).
  double values_held() const {
    return static_cast<double>(site_values_.extent(0)) + Dim * owned_ + runs_ + (Dim + 1.5) * offsets_ +
           static_cast<double>(viscous_moment_.size());
  }

  // out(i, d) = -sum_j m_j (P_i + P_j) F_ij r_ij[d] for the owned fluid
  // particles i (other rows untouched); P (`values`) and m (`mass`) a value per slot.
  void gradient(const Scalars& values, const Scalars& mass, const Rows& out) const {
    spread(values, mass, 1);
    const auto moment = moment_;
    gather(1, KOKKOS_LAMBDA(int i, const double* sum) {
      for (int d = 0; d < Dim; ++d) out(i, d) = -(values(i) * moment(i, d) + sum[d]);
    });
  }

  // out(i) = sum_j m_j (u_i - u_j) . F_ij r_ij for the owned fluid particles
  // i (other rows untouched); u a row per slot, m a value per slot.
  void divergence(const Rows& velocities, const Scalars& mass, const Scalars& out) const {
    spread(velocities, mass, Dim);
    const auto moment = moment_;
    gather(Dim, KOKKOS_LAMBDA(int i, const double* sum) {
      double own = 0;
      for (int d = 0; d < Dim; ++d) own += velocities(i, d) * moment(i, d);
      out(i) = own - sum[0];
    });
  }

  // The viscous term's M0_i: the stencil sums of the masses of fluid
  // particles (a value per slot, zero on the slots of other particles).
  void take_fluid_masses(const Scalars& mass) {
    viscous_moment_ = Scalars("LatticeProducts::viscous_moment", owned_);
    const auto moment = viscous_moment_;
    spread(mass, Scalars(), 1);
    gather_by_distance<1>(KOKKOS_LAMBDA(int i, const double* sum) { moment(i) = sum[0]; });
  }
  bool has_fluid_masses() const { return viscous_moment_.extent(0) > 0; }

  // out(i, d) = coefficient sum_j m_j F_ij (w_i - w_j)[d] over the fluid
  // particles j for the owned fluid particles i (other rows untouched); w a
  // row per slot, mass as in take_fluid_masses(). Morris's viscous term
  // where every 1/rho is 1/rho0 (fixed particles): coefficient 2 nu / rho0.
  void viscous(const Rows& velocities, const Scalars& mass, double coefficient, const Rows& out) const {
    const auto moment = viscous_moment_;
    spread(velocities, mass, Dim);
    gather_by_distance<Dim>(KOKKOS_LAMBDA(int i, const double* sum) {
      for (int d = 0; d < Dim; ++d) out(i, d) = coefficient * (velocities(i, d) * moment(i) - sum[d]);
    });
  }

 private:
  // m_j times the values of slot j at its site (component c at c * sites +
  // site), zero at sites without a particle. No mass view: the values alone.
  template <class Values>
  void spread(const Values& values, const Scalars& mass, int components) const {
    const int sites = rows_.sites();
    const auto site_values = site_values_;
    const auto map = rows_;
    const bool weighed = mass.extent(0) > 0;
    static const std::string label = "poresph::LatticeProducts::spread";
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(space_, 0, sites), KOKKOS_LAMBDA(int s) {
          const int j = map.slot_at(s);
          for (int c = 0; c < components; ++c) {
            double value = 0;
            if (j >= 0) {
              if constexpr (Values::rank == 1) value = values(j);
              else value = values(j, c);
              if (weighed) value *= mass(j);
            }
            site_values(static_cast<std::size_t>(c) * sites + s) = value;
          }
        });
    space_.fence();
  }

  // For every run of owned fluid particles, the stencil sums of the spread
  // values, over kRun lanes; then take(i, sum) for each of its particles i
  // (one component: sum[d], the weights' d-th times the values; Dim
  // components: their dot product with the weights, in sum[0]).
  template <class Take>
  void gather(int components, const Take& take) const {
    const std::size_t sites = rows_.sites();
    const int offsets = offsets_;
    const auto site_values = site_values_;
    const auto step = step_;
    const auto weight = weight_;
    const auto run_site = run_site_, run_length = run_length_;
    const auto map = rows_;
    static const std::string label = "poresph::LatticeProducts::gather";
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(space_, 0, runs_), KOKKOS_LAMBDA(int r) {
          const int first = run_site(r);
          double sum[Dim][kRun] = {};
          if (components == 1) {
            for (int k = 0; k < offsets; ++k) {
              const double* from = site_values.data() + (first + step(k));
              for (int d = 0; d < Dim; ++d) {
                const double w = weight(k, d);
                for (int t = 0; t < kRun; ++t) sum[d][t] += w * from[t];
              }
            }
          } else {
            for (int k = 0; k < offsets; ++k) {
              const double* from = site_values.data() + (first + step(k));
              double w[Dim];
              for (int c = 0; c < Dim; ++c) w[c] = weight(k, c);
              for (int t = 0; t < kRun; ++t) {
                double dot = 0;
                for (int c = 0; c < Dim; ++c) dot += w[c] * from[c * sites + t];
                sum[0][t] += dot;
              }
            }
          }
          for (int t = 0; t < run_length(r); ++t) {
            double of_particle[Dim];
            for (int d = 0; d < Dim; ++d) of_particle[d] = sum[d][t];
            take(map.slot_at(first + t), of_particle);
          }
        });
    space_.fence();
  }

  // The same for the weights F_k alone: for every run of owned fluid
  // particles, sum[c] = sum_k F_k times component c of the spread values
  // (Components of them, at most Dim). A function apart from gather(): with
  // the three weighings as one template, the divergence's gather took 2.7
  // times as long (perf record on the image pack).
  template <int Components, class Take>
  void gather_by_distance(const Take& take) const {
    static_assert(Components >= 1 && Components <= Dim);
    const std::size_t sites = rows_.sites();
    const int offsets = offsets_;
    const auto site_values = site_values_;
    const auto step = step_;
    const auto scalar_weight = scalar_weight_;
    const auto run_site = run_site_, run_length = run_length_;
    const auto map = rows_;
    static const std::string label = "poresph::LatticeProducts::gather_by_distance";
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(space_, 0, runs_), KOKKOS_LAMBDA(int r) {
          const int first = run_site(r);
          double sum[Dim][kRun] = {};
          for (int k = 0; k < offsets; ++k) {
            const double* from = site_values.data() + (first + step(k));
            const double w = scalar_weight(k);
            for (int c = 0; c < Components; ++c)
              for (int t = 0; t < kRun; ++t) sum[c][t] += w * from[c * sites + t];
          }
          for (int t = 0; t < run_length(r); ++t) {
            double of_particle[Dim];
            for (int d = 0; d < Dim; ++d) of_particle[d] = sum[d][t];
            take(map.slot_at(first + t), of_particle);
          }
        });
    space_.fence();
  }

  ExecSpace space_;
  Lattice rows_;
  int owned_ = 0, offsets_ = 0, runs_ = 0;
  Kokkos::View<int*, MemorySpace> step_;                          // offset k -> its site difference
  Kokkos::View<double**, Kokkos::LayoutLeft, MemorySpace> weight_;  // offset k -> F_k r_k
  Scalars scalar_weight_;                                           // offset k -> F_k
  Kokkos::View<int*, MemorySpace> run_site_, run_length_;
  Scalars site_values_;  // the spread values, component-major
  Rows moment_;          // M_i of the owned particles
  Scalars viscous_moment_;  // M0_i of the owned particles (take_fluid_masses())
};

}  // namespace poresph
