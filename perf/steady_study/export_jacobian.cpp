// The Jacobian of a fixed-particle scene's rates with respect to the fluid
// particles' velocity and density, by probing, for the steady-solver study
// (docs/steady_solver.md; the scipy side is perf/steady_study/study.py).
//
// Unknowns per fluid particle: v (Dim components), then rho. The residual is
// what the time loop integrates: R_v = dv/dt - kappa v (kappa: the exactly
// integrated wall drag, PredictorCorrector.hpp), R_rho = drho/dt. Columns of
// particles whose lattice indices agree modulo M (M >= 12 spacings per axis,
// beyond twice the reach of any rate's dependence: wall pressure and no-slip
// extrapolation included) are probed together, by central differences.
//
//   poresph_export_jacobian SCENE.xml OUT_PREFIX [--set overrides as in poresph]...
// writes OUT_PREFIX_{J,R0,particles,info}.txt. With the environment variable
// STATE=FILE (per fluid particle: Dim velocity and one density increment) it
// writes only the residual at the scene's start state plus that increment,
// OUT_PREFIX_Rstate.txt, to check a linear solve against the nonlinear rates.
// Serial, one process.
#include <Kokkos_Core.hpp>
#include <mpi.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <unordered_map>
#include <vector>

#include "app/Simulation.hpp"
#include "io/Parameters.hpp"
#include "scene/SceneBuilder.hpp"

namespace {

using namespace poresph;
using HostMatrix = Kokkos::View<double**, Kokkos::LayoutRight, Kokkos::HostSpace>;
using HostVector = Kokkos::View<double*, Kokkos::HostSpace>;

template <int Dim>
class RateProbe {
 public:
  explicit RateProbe(const SceneConfig& scene) : scene_(scene), sim_(scene) {
    auto& P = sim_.particles();
    owned_ = P.owned;
    auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.x);
    auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.kind);
    const double dx = scene.particle_spacing;
    for (int d = 0; d < Dim; ++d) lattice_[d] = static_cast<int>(std::lround(scene.cell_size[d] / dx));
    index_.resize(owned_);
    for (int a = 0; a < owned_; ++a) {
      for (int d = 0; d < Dim; ++d) index_[a][d] = static_cast<int>(std::floor(x(a, d) / dx));
      if (kind(a) == kFluid) fluid_.push_back(a);
    }
    // Copies, not mirrors: on the host backend a mirror view is the View itself.
    v_start_ = HostMatrix("v_start", P.v.extent(0), Dim);
    rho_start_ = HostVector("rho_start", P.rho.extent(0));
    Kokkos::deep_copy(v_start_, P.v);
    Kokkos::deep_copy(rho_start_, P.rho);
    for (int d = 0; d < Dim; ++d) {
      modulus_[d] = lattice_[d];
      for (int m = 12; m <= lattice_[d]; ++m)
        if (lattice_[d] % m == 0) {
          modulus_[d] = m;
          break;
        }
    }
  }

  int fluid() const { return static_cast<int>(fluid_.size()); }
  int colours() const {
    int c = 1;
    for (int d = 0; d < Dim; ++d) c *= modulus_[d];
    return c;
  }
  int colour_of(int a) const {
    int c = 0;
    for (int d = Dim - 1; d >= 0; --d) c = c * modulus_[d] + index_[a][d] % modulus_[d];
    return c;
  }
  long long lattice_key(const std::array<int, Dim>& i) const {
    long long key = 0, stride = 1;
    for (int d = 0; d < Dim; ++d) {
      key += ((i[d] % lattice_[d]) + lattice_[d]) % lattice_[d] * stride;
      stride *= lattice_[d];
    }
    return key;
  }

  // The start state, plus eps on one unknown of every fluid particle of one
  // colour (colour < 0: none), plus an increment per fluid unknown if given.
  void set_state(int unknown, int colour, double eps, const std::vector<double>* increment = nullptr) {
    auto& P = sim_.particles();
    HostMatrix v("v", P.v.extent(0), Dim);
    HostVector rho("rho", P.rho.extent(0));
    Kokkos::deep_copy(v, v_start_);
    Kokkos::deep_copy(rho, rho_start_);
    for (int f = 0; f < fluid(); ++f) {
      const int a = fluid_[f];
      if (increment) {
        for (int d = 0; d < Dim; ++d) v(a, d) += (*increment)[f * (Dim + 1) + d];
        rho(a) += (*increment)[f * (Dim + 1) + Dim];
      }
      if (colour >= 0 && colour_of(a) == colour) {
        if (unknown < Dim)
          v(a, unknown) += eps;
        else
          rho(a) += eps;
      }
    }
    Kokkos::deep_copy(P.v, v);
    Kokkos::deep_copy(P.rho, rho);
  }

  std::vector<double> residual() {
    auto& P = sim_.particles();
    sim_.compute_rates();
    auto dvdt = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.dvdt);
    auto drhodt = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.drhodt);
    auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.v);
    HostVector drag("drag", owned_);
    if (P.has_surfaces) Kokkos::deep_copy(drag, Kokkos::subview(P.wall_drag, std::make_pair(0, owned_)));
    std::vector<double> R(static_cast<size_t>(fluid()) * (Dim + 1));
    for (int f = 0; f < fluid(); ++f) {
      const int a = fluid_[f];
      for (int d = 0; d < Dim; ++d) R[f * (Dim + 1) + d] = dvdt(a, d) - drag(a) * v(a, d);
      R[f * (Dim + 1) + Dim] = drhodt(a);
    }
    return R;
  }

  // The fluid particle of a colour nearest (periodically) to fluid particle
  // `row`: the only one of that colour whose probe can reach it.
  int column_for(int row, int colour, double& distance) const {
    std::array<int, Dim> i;
    double d2 = 0;
    const int a = fluid_[row];
    for (int d = 0; d < Dim; ++d) {
      const int cd = colour % modulus_[d];
      colour /= modulus_[d];
      int delta = ((index_[a][d] - cd) % modulus_[d] + modulus_[d]) % modulus_[d];
      if (delta > modulus_[d] / 2) delta -= modulus_[d];
      d2 += double(delta) * delta;
      i[d] = index_[a][d] - delta;
    }
    distance = std::sqrt(d2);
    const auto it = fluid_by_key_.find(lattice_key(i));
    return it == fluid_by_key_.end() ? -1 : it->second;
  }

  void index_fluid() {
    for (int f = 0; f < fluid(); ++f) {
      std::array<int, Dim> i;
      for (int d = 0; d < Dim; ++d) i[d] = index_[fluid_[f]][d];
      fluid_by_key_[lattice_key(i)] = f;
    }
  }

  void write_jacobian(const std::string& out, double eps_v, double eps_rho) {
    index_fluid();
    constexpr int U = Dim + 1;
    std::ofstream J(out + "_J.txt");
    J.precision(17);
    const double reach = 6.0 * scene_.smoothing_length_ratio + 1.0;  // lattice spacings
    long long entries = 0;
    for (int c = 0; c < colours(); ++c) {
      for (int u = 0; u < U; ++u) {
        const double eps = u < Dim ? eps_v : eps_rho;
        set_state(u, c, eps);
        const auto plus = residual();
        set_state(u, c, -eps);
        const auto minus = residual();
        for (int row = 0; row < fluid(); ++row) {
          bool touched = false;
          for (int q = 0; q < U; ++q) touched |= plus[row * U + q] != minus[row * U + q];
          if (!touched) continue;
          double distance = 0;
          const int column = column_for(row, c, distance);
          if (column < 0 || distance > reach) {
            std::fprintf(stderr, "row %d: changed by colour %d with no fluid column within reach\n", row, c);
            continue;
          }
          for (int q = 0; q < U; ++q) {
            const double value = (plus[row * U + q] - minus[row * U + q]) / (2 * eps);
            if (value != 0) {
              J << row * U + q << ' ' << column * U + u << ' ' << value << '\n';
              ++entries;
            }
          }
        }
      }
    }
    set_state(0, -1, 0);
    write_vector(out + "_R0.txt", residual());
    std::ofstream particles(out + "_particles.txt");
    particles.precision(17);
    const double dx = scene_.particle_spacing;
    for (int f = 0; f < fluid(); ++f) {
      for (int d = 0; d < Dim; ++d) particles << (index_[fluid_[f]][d] + 0.5) * dx << ' ';
      for (int d = 0; d < Dim; ++d) particles << index_[fluid_[f]][d] << ' ';
      particles << '\n';
    }
    std::ofstream info(out + "_info.txt");
    info.precision(17);
    double volume = 1;
    for (int d = 0; d < Dim; ++d) volume *= scene_.cell_size[d];
    info << "dim " << Dim << "\nnf " << fluid() << "\nn " << owned_ << "\ndx " << dx << "\nnu "
         << scene_.kinematic_viscosity << "\nrho0 " << scene_.density << "\nc " << sim_.derived().sound_speed
         << "\ndt " << sim_.time_step() << "\nmass " << scene_.density * std::pow(dx, Dim) << "\nvolume " << volume
         << "\nF ";
    for (int d = 0; d < Dim; ++d) info << scene_.body_force[d] << ' ';
    info << "\nN ";
    for (int d = 0; d < Dim; ++d) info << lattice_[d] << ' ';
    info << "\nentries " << entries << '\n';
    std::printf("fluid %d, entries %lld, colours %d\n", fluid(), entries, colours());
  }

  void write_residual_at(const std::string& state_file, const std::string& out) {
    std::ifstream in(state_file);
    std::vector<double> increment(static_cast<size_t>(fluid()) * (Dim + 1));
    for (double& x : increment) in >> x;
    if (!in) throw std::runtime_error(state_file + ": expected " + std::to_string(increment.size()) + " numbers");
    set_state(0, -1, 0, &increment);
    write_vector(out + "_Rstate.txt", residual());
  }

 private:
  static void write_vector(const std::string& path, const std::vector<double>& values) {
    std::ofstream o(path);
    o.precision(17);
    for (double x : values) o << x << '\n';
  }

  SceneConfig scene_;
  Simulation<Dim, Kokkos::Serial> sim_;
  int owned_ = 0;
  int lattice_[Dim];
  int modulus_[Dim];
  std::vector<std::array<int, Dim>> index_;  // lattice indices of owned particles
  std::vector<int> fluid_;                   // owned particles that are fluid
  std::unordered_map<long long, int> fluid_by_key_;
  HostMatrix v_start_;
  HostVector rho_start_;
};

template <int Dim>
void run(const SceneConfig& scene, const std::string& out) {
  if (scene.particle_motion != ParticleMotion::Fixed)
    throw std::invalid_argument("the Jacobian is probed for fixed particles only (Discretization/Particle Motion)");
  RateProbe<Dim> probe(scene);
  if (const char* state_file = std::getenv("STATE"))
    probe.write_residual_at(state_file, out);
  else
    probe.write_jacobian(out, 1e-6, 1e-6);
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  Kokkos::initialize(argc, argv);
  int status = 0;
  try {
    if (argc < 3) throw std::invalid_argument("usage: poresph_export_jacobian SCENE.xml OUT_PREFIX [PARAMETER=VALUE]...");
    std::vector<std::string> overrides(argv + 3, argv + argc);
    overrides.push_back("Run/Progress=never");
    const auto params = poresph::read_parameters(argv[1], overrides);
    const auto scene =
        poresph::scene_from_parameters(*params, std::filesystem::path(argv[1]).parent_path().string());
    if (scene.dimension == 2)
      run<2>(scene, argv[2]);
    else
      run<3>(scene, argv[2]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "poresph_export_jacobian: %s\n", e.what());
    status = 2;
  }
  Kokkos::finalize();
  MPI_Finalize();
  return status;
}
