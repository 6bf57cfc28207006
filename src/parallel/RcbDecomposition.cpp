// Kept in a file of its own: the Zoltan2 headers take half a minute to compile.
#include "parallel/RcbDecomposition.hpp"

#include <Teuchos_DefaultMpiComm.hpp>
#include <Zoltan2_BasicVectorAdapter.hpp>
#include <Zoltan2_PartitioningProblem.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "geometry/Lattice.hpp"

namespace poresph {
namespace {

// "2,2,3": one binary cut per level where it can, so that Zoltan2's
// multi-jagged partitioner does recursive coordinate bisection.
std::string cuts_per_level(int parts) {
  std::vector<int> factors;
  for (int f = 2; f * f <= parts; ++f)
    while (parts % f == 0) factors.push_back(f), parts /= f;
  if (parts > 1) factors.push_back(parts);
  std::string text;
  for (size_t k = 0; k < factors.size(); ++k) text += (k ? "," : "") + std::to_string(factors[k]);
  return text.empty() ? "1" : text;
}

// The boxes of `parts` parts of the particles-to-be (coordinates and ids
// of this process's share), by Zoltan2 on the processes of `comm`.
// With `weights` (one a point), the parts hold equal sums of them.
template <int Dim>
std::vector<Box<Dim>> rcb_boxes(const std::array<double, Dim>& cell, const std::array<bool, Dim>& periodic,
                                std::vector<double>& coordinates, std::vector<long long>& ids,
                                const Communicator& comm, int parts, const std::vector<double>* point_weights = nullptr) {
  const int n = static_cast<int>(ids.size());

  using Types = Zoltan2::BasicUserTypes<double, int, long long>;
  using Adapter = Zoltan2::BasicVectorAdapter<Types>;
  std::vector<const double*> entries;
  std::vector<int> strides;
  for (int d = 0; d < Dim; ++d) entries.push_back(coordinates.data() + d), strides.push_back(Dim);
  std::vector<const double*> weights;
  std::vector<int> weight_strides;
  if (point_weights) weights.push_back(point_weights->data()), weight_strides.push_back(1);
  Adapter adapter(n, ids.data(), entries, strides, weights, weight_strides);

  Teuchos::ParameterList parameters("zoltan2");
  parameters.set("algorithm", std::string("multijagged"));
  parameters.set("num_global_parts", parts);
  parameters.set("mj_parts", cuts_per_level(parts));
  parameters.set("mj_keep_part_boxes", true);
  const auto teuchos_comm = Teuchos::rcp(new Teuchos::MpiComm<int>(comm.comm()));
  Zoltan2::PartitioningProblem<Adapter> problem(&adapter, &parameters, teuchos_comm);
  problem.solve();

  // Zoltan2's outer faces are the points' extent: extend them to the cell.
  const auto& part_boxes = problem.getSolution().getPartBoxesView();
  std::vector<Box<Dim>> boxes(parts);
  std::array<double, Dim> low, high;
  low.fill(INFINITY), high.fill(-INFINITY);
  for (const auto& b : part_boxes)
    for (int d = 0; d < Dim; ++d) low[d] = std::min(low[d], b.getlmins()[d]), high[d] = std::max(high[d], b.getlmaxs()[d]);
  for (const auto& b : part_boxes) {
    Box<Dim>& box = boxes.at(b.getpId());
    for (int d = 0; d < Dim; ++d) {
      box.lo[d] = b.getlmins()[d] <= low[d] ? (periodic[d] ? 0.0 : -INFINITY) : b.getlmins()[d];
      box.hi[d] = b.getlmaxs()[d] >= high[d] ? (periodic[d] ? cell[d] : INFINITY) : b.getlmaxs()[d];
    }
  }
  return boxes;
}

}  // namespace

template <int Dim>
Decomposition<Dim> rcb_decomposition(const SceneConfig& scene, const Communicator& comm) {
  std::array<double, Dim> cell{};
  std::array<bool, Dim> periodic{};
  for (int d = 0; d < Dim; ++d) cell[d] = scene.cell_size[d], periodic[d] = scene.periodic[d];
  const int parts = comm.size();
  if (parts == 1) {
    std::array<std::vector<double>, Dim> whole;
    for (int d = 0; d < Dim; ++d) whole[d] = {0.0, cell[d]};
    return Decomposition<Dim>::cartesian(cell, periodic, whole);
  }

  // The particles-to-be of an x slab per rank: every lattice point is
  // classified once, by one rank, and no rank holds them all.
  double lo[Dim], hi[Dim];
  for (int d = 0; d < Dim; ++d) lo[d] = -1e300, hi[d] = 1e300;
  lo[0] = cell[0] * comm.rank() / parts;
  hi[0] = comm.rank() + 1 == parts ? cell[0] : cell[0] * (comm.rank() + 1) / parts;
  const auto seeds = fill_lattice<Dim>(scene, lo, hi);
  const int n = static_cast<int>(seeds.size());
  std::vector<double> coordinates(static_cast<size_t>(n) * Dim);
  std::vector<long long> ids(n);
  for (int i = 0; i < n; ++i) {
    for (int d = 0; d < Dim; ++d) coordinates[i * Dim + d] = seeds[i].x[d];
    ids[i] = seeds[i].id;
  }
  // The decomposition into `count` parts, or why there is none; every
  // process gets the same boxes, so the same answer.
  auto split = [&](int count, std::string& why) -> std::optional<Decomposition<Dim>> {
    try {
      Decomposition<Dim> decomposition(rcb_boxes<Dim>(cell, periodic, coordinates, ids, comm, count), cell, periodic);
      decomposition.check(count);
      return decomposition;
    } catch (const std::exception& e) {
      why = e.what();
      return std::nullopt;
    }
  };
  std::string why, ignored;
  auto decomposition = split(parts, why);
  if (!decomposition) {
    // Too many processes for too few particles: say how many would do.
    long long particles = comm.sum(static_cast<long long>(n));
    int fewer = parts - 1;
    while (fewer > 1 && !split(fewer, ignored)) --fewer;
    std::ostringstream msg;
    msg << "the cell cannot be split into " << parts << " sub-domains for " << parts << " processes (" << why
        << "): its " << particles << " particles at Discretization/Particle Spacing " << scene.particle_spacing
        << " are too few to share so many ways. Run on at most " << fewer << " process" << (fewer == 1 ? "" : "es")
        << " (mpiexec -n " << fewer << "), or at a finer spacing";
    throw std::invalid_argument(msg.str());
  }
  return *decomposition;
}

template <int Dim>
Decomposition<Dim> rcb_decomposition_of_particles(const SceneConfig& scene, std::vector<double>& coordinates,
                                                  std::vector<long long>& ids, const std::vector<double>& weights,
                                                  const Communicator& comm) {
  std::array<double, Dim> cell{};
  std::array<bool, Dim> periodic{};
  for (int d = 0; d < Dim; ++d) cell[d] = scene.cell_size[d], periodic[d] = scene.periodic[d];
  Decomposition<Dim> decomposition(rcb_boxes<Dim>(cell, periodic, coordinates, ids, comm, comm.size(), &weights), cell,
                                   periodic);
  decomposition.check(comm.size());
  return decomposition;
}

template Decomposition<2> rcb_decomposition<2>(const SceneConfig&, const Communicator&);
template Decomposition<3> rcb_decomposition<3>(const SceneConfig&, const Communicator&);
template Decomposition<2> rcb_decomposition_of_particles<2>(const SceneConfig&, std::vector<double>&,
                                                            std::vector<long long>&, const std::vector<double>&,
                                                            const Communicator&);
template Decomposition<3> rcb_decomposition_of_particles<3>(const SceneConfig&, std::vector<double>&,
                                                            std::vector<long long>&, const std::vector<double>&,
                                                            const Communicator&);

}  // namespace poresph
