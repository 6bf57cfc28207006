#include "geometry/RandomPack.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <sstream>
#include <stdexcept>

#include "core/StopRequest.hpp"
#include "geometry/GrainBins.hpp"
#include "geometry/Grains.hpp"

namespace poresph {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Uniform and normal numbers from std::mt19937_64 by formulas written out
// here: the engine's sequence is fixed by the standard, std's distributions
// are not (libstdc++ and libc++ differ), and a seed must give one pack.
class Draws {
 public:
  explicit Draws(unsigned long long seed) : engine_(seed) {}
  double uniform() { return (static_cast<double>(engine_() >> 11) + 0.5) * 0x1.0p-53; }  // in (0, 1)
  double normal() {  // Box-Muller, one value per pair of draws
    const double u1 = uniform(), u2 = uniform();
    return std::sqrt(-2 * std::log(u1)) * std::cos(2 * kPi * u2);
  }

 private:
  std::mt19937_64 engine_;
};

std::string fail_message(const std::string& what) { return "Grains/Random Pack: " + what; }

// Radii whose volume is the target solid volume (step 1 of RandomPack.hpp).
std::vector<double> draw_radii(const RandomPackSpec& spec, double solid_volume, int dim, Draws& draws,
                               double& scale) {
  constexpr size_t kMostGrains = 1000000;
  constexpr int kMostAttempts = 10000;  // per radius, for a truncated lognormal
  std::vector<double> radii;
  double volume = 0;
  while (volume < solid_volume) {
    if (radii.size() == kMostGrains)
      throw std::invalid_argument(fail_message("the porosity asks for more than " + std::to_string(kMostGrains) +
                                               " grains of these radii; use larger grains or a smaller cell"));
    double r = 0;
    if (spec.distribution == RandomPackSpec::Distribution::Uniform) {
      r = spec.min_radius + (spec.max_radius - spec.min_radius) * draws.uniform();
    } else {
      int attempt = 0;
      do {
        if (++attempt > kMostAttempts)
          throw std::invalid_argument(fail_message(
              "the lognormal distribution (Median Radius, Log Standard Deviation) puts almost no grain between "
              "Min Radius and Max Radius"));
        r = spec.median_radius * std::exp(spec.log_deviation * draws.normal());
      } while (r < spec.min_radius || r > spec.max_radius);
    }
    radii.push_back(r);
    volume += ball_volume(r, dim);
  }
  // With or without the last grain, whichever needs the smaller change of scale.
  const double with_last = std::pow(solid_volume / volume, 1.0 / dim);
  const double last = ball_volume(radii.back(), dim);
  if (radii.size() > 1) {
    const double without_last = std::pow(solid_volume / (volume - last), 1.0 / dim);
    if (std::abs(std::log(without_last)) < std::abs(std::log(with_last))) {
      radii.pop_back();
      scale = without_last;
    } else {
      scale = with_last;
    }
  } else {
    scale = with_last;
  }
  for (double& r : radii) r *= scale;
  return radii;
}

// The relaxation of steps 2 and 3 (RandomPack.hpp): grains at `lambda`
// times their radii, pairs set right until none breaks the rule.
class Relaxation {
 public:
  // Contacts overlap by at most min(overlap, 0.1 of the smaller radius).
  Relaxation(const SceneConfig& scene, double gap, bool contacts, double overlap)
      : scene_(scene), dim_(scene.dimension), gap_(gap), contacts_(contacts), overlap_(overlap) {
    double smallest_side = INFINITY;
    for (int d = 0; d < dim_; ++d) smallest_side = std::min(smallest_side, scene.cell_size[d]);
    tolerance_ = 1e-12 * smallest_side;
  }

  // Sweeps until no pair breaks the rule (true) or `most_sweeps` have not
  // got there (false). `sweeps` counts what was done.
  bool settle(std::vector<Grain>& grains, const std::vector<double>& radii, double lambda, int most_sweeps,
              long long& sweeps) {
    double largest = 0;
    for (double r : radii) largest = std::max(largest, r);
    const double reach = 2 * lambda * largest + gap_ + 1e3 * tolerance_;
    for (int sweep = 0; sweep < most_sweeps; ++sweep) {
      stop_setup_if_asked("growing the random pack (Grains/Random Pack)");
      ++sweeps;
      for (size_t g = 0; g < grains.size(); ++g) grains[g].radius = lambda * radii[g];
      const GrainBins bins(grains, scene_, reach);
      long long broken = 0;
      for (size_t i = 0; i < grains.size(); ++i)
        bins.for_each_near(grains[i].centre, [&](size_t j) {
          if (j > i) broken += set_right(grains[i], grains[j]);
        });
      if (broken == 0) return true;
    }
    return false;
  }

  // The largest overlap a contact of these grains may have.
  double contact_overlap(const Grain& a, const Grain& b) const {
    return contacts_ ? std::min(overlap_, 0.1 * std::min(a.radius, b.radius)) : 0.0;
  }

  // The separation of two grains' surfaces at the nearest image (negative: overlap).
  double separation(const Grain& a, const Grain& b) const {
    const auto r = periodic_difference(b.centre, a.centre, scene_);
    double d_sq = 0;
    for (int k = 0; k < dim_; ++k) d_sq += r[k] * r[k];
    return std::sqrt(d_sq) - a.radius - b.radius;
  }

  // Exact bounds: a throat a hair under the gap would be refused by the
  // scene checks (under one spacing) or counted as a throat (a hair open).
  bool in_contact(const Grain& a, const Grain& b, double s) const {
    return contacts_ && s <= 0 && s >= -contact_overlap(a, b);
  }
  bool open(double s) const { return s >= gap_; }

 private:
  // 1 if the pair broke the rule (and was moved), else 0.
  int set_right(Grain& a, Grain& b) const {
    auto r = periodic_difference(b.centre, a.centre, scene_);
    double d_sq = 0;
    for (int k = 0; k < dim_; ++k) d_sq += r[k] * r[k];
    const double d = std::sqrt(d_sq);
    const double s = d - a.radius - b.radius;
    if (open(s) || in_contact(a, b, s)) return 0;
    // Pulled into contact when nearer to it than to the gap, else pushed to
    // the gap; both a little inside their bounds, which rounding must not cross.
    const double target =
        contacts_ && s < 0.5 * gap_ ? -0.5 * contact_overlap(a, b) : gap_ * (1 + 1e-9) + 1e3 * tolerance_;
    const double move = target - s;
    if (d > 0) {
      for (int k = 0; k < dim_; ++k) r[k] /= d;
    } else {  // coincident centres: any direction, the same every time
      r = {1, 0, 0};
    }
    const double va = ball_volume(a.radius, dim_), vb = ball_volume(b.radius, dim_);
    const double share_a = vb / (va + vb), share_b = va / (va + vb);  // the smaller grain moves further
    for (int k = 0; k < dim_; ++k) {
      a.centre[k] = wrapped(a.centre[k] - move * share_a * r[k], k);
      b.centre[k] = wrapped(b.centre[k] + move * share_b * r[k], k);
    }
    return 1;
  }

  double wrapped(double x, int d) const {
    const double L = scene_.cell_size[d];
    double y = x - L * std::floor(x / L);
    return y >= L ? y - L : y;  // rounding of a tiny negative x
  }

  const SceneConfig& scene_;
  int dim_;
  double gap_;
  bool contacts_;
  double overlap_;
  double tolerance_ = 0;
};

}  // namespace

RandomPack make_random_pack(const RandomPackSpec& spec, const SceneConfig& scene) {
  const int dim = scene.dimension;
  if (!(spec.porosity > 0 && spec.porosity < 1))
    throw std::invalid_argument(fail_message("Porosity must lie between 0 and 1"));
  for (int d = 0; d < dim; ++d)
    if (!scene.periodic[d] || scene.walls != WallType::None)
      throw std::invalid_argument(fail_message("packs a cell periodic in every direction, without walls"));
  if (!(spec.min_radius > 0) || !(spec.max_radius >= spec.min_radius))
    throw std::invalid_argument(fail_message("needs 0 < Min Radius <= Max Radius"));
  if (spec.distribution == RandomPackSpec::Distribution::Lognormal &&
      !(spec.median_radius > 0 && spec.log_deviation >= 0))
    throw std::invalid_argument(fail_message("a lognormal distribution needs Median Radius > 0 and Log Standard "
                                             "Deviation >= 0"));
  const double gap = spec.minimum_gap * scene.particle_spacing;
  double cell_volume = 1, smallest_side = INFINITY;
  for (int d = 0; d < dim; ++d) cell_volume *= scene.cell_size[d], smallest_side = std::min(smallest_side, scene.cell_size[d]);

  RandomPack pack;
  Draws draws(spec.seed);
  std::vector<double> radii = draw_radii(spec, (1 - spec.porosity) * cell_volume, dim, draws, pack.radius_scale);
  double largest = *std::max_element(radii.begin(), radii.end());
  // Each pair must meet at one periodic image only, as the moves see it.
  if (2 * (2 * largest + gap) > smallest_side) {
    std::ostringstream msg;
    msg << "the cell side " << smallest_side << " m is less than twice the largest diameter plus the gap, "
        << 2 * (2 * largest + gap) << " m: a pair of grains could meet through two periodic images. Use a larger "
        << "cell (Domain/Cell Size) or smaller grains";
    throw std::invalid_argument(fail_message(msg.str()));
  }
  pack.grains.resize(radii.size());
  for (size_t g = 0; g < radii.size(); ++g) {
    for (int d = 0; d < dim; ++d) pack.grains[g].centre[d] = scene.cell_size[d] * draws.uniform();
    pack.grains[g].origin = "Grains/Random Pack #" + std::to_string(g + 1);
  }

  // Grown without a gap when contacts are allowed (grains may overlap as
  // contacts do, no more), as a pack of grains settles, and the
  // gap-or-contact rule applied at full size (below): grown under that rule,
  // grains close to one another become contacts early and form a loose,
  // sticky network that jams near porosity 0.6. Without contacts the rule
  // is the gap all along.
  Relaxation growing(scene, spec.contacts ? 0.0 : gap, spec.contacts, gap);
  Relaxation relaxation(scene, gap, spec.contacts, gap);
  constexpr int kMostSweeps = 400;  // per stage; a stage that needs more is retried with less growth
  constexpr double kLargestGrowth = 0.02, kSmallestGrowth = 1e-4;
  double lambda = std::min(1.0, std::pow(0.1, 1.0 / dim));  // a tenth of the solid volume
  double growth = kLargestGrowth, settled_lambda = 0;
  std::vector<Grain> settled = pack.grains;
  while (true) {
    ++pack.stages;
    if (growing.settle(pack.grains, radii, lambda, kMostSweeps, pack.sweeps)) {
      settled = pack.grains;
      settled_lambda = lambda;
      if (lambda == 1.0) break;
      growth = std::min(kLargestGrowth, 1.5 * growth);
    } else {
      pack.grains = settled;
      growth *= 0.5;
      if (growth < kSmallestGrowth || settled_lambda == 0) {
        double reached = 0;
        for (double r : radii) reached += ball_volume(settled_lambda * r, dim);
        std::ostringstream msg;
        msg << "the grains jammed at porosity " << 1 - reached / cell_volume << " before reaching "
            << spec.porosity << " (Minimum Gap " << spec.minimum_gap << " spacings"
            << (spec.contacts ? "" : ", no contacts") << "). Ask for a higher porosity"
            << (spec.minimum_gap > 1 ? ", a smaller gap" : "")  // 1 spacing is the least it may be
            << (spec.contacts ? "" : ", contacts (Contacts = true)") << " or wider-spread radii";
        throw std::invalid_argument(fail_message(msg.str()));
      }
      lambda = settled_lambda;
    }
    lambda = std::min(1.0, lambda * (1 + growth));
  }

  if (spec.contacts && !relaxation.settle(pack.grains, radii, 1.0, 20 * kMostSweeps, pack.sweeps)) {
    std::ostringstream msg;
    msg << "the grains could not keep every throat either closed (a contact) or " << spec.minimum_gap
        << " spacings open at porosity " << spec.porosity << ". Ask for "
        << (spec.minimum_gap > 1 ? "a smaller gap, " : "") << "a higher porosity or grains of more spacings across";
    throw std::invalid_argument(fail_message(msg.str()));
  }

  // Step 4: contacts' lenses counted once; the radii scaled until the exact porosity is the target.
  SceneConfig cell = scene;
  cell.allow_overlapping_grains = true;
  pack.porosity = porosity(pack.grains, cell);
  for (int round = 0; round < 50 && std::abs(pack.porosity - spec.porosity) > 1e-6; ++round) {
    const double factor = std::pow((1 - spec.porosity) / (1 - pack.porosity), 1.0 / dim);
    for (double& r : radii) r *= factor;
    pack.radius_scale *= factor;
    if (!relaxation.settle(pack.grains, radii, 1.0, 20 * kMostSweeps, pack.sweeps))
      throw std::invalid_argument(fail_message("the grains jammed while their contacts were being made"));
    pack.porosity = porosity(pack.grains, cell);
  }
  if (std::abs(pack.porosity - spec.porosity) > 1e-6) {
    std::ostringstream msg;
    msg << "the porosity of the pack, " << pack.porosity << ", did not settle at " << spec.porosity;
    throw std::invalid_argument(fail_message(msg.str()));
  }

  // What was made, for the run's log and the grain file's header.
  largest = 0;
  double smallest = INFINITY;
  for (double r : radii) largest = std::max(largest, r), smallest = std::min(smallest, r);
  pack.narrowest_gap = INFINITY;
  const GrainBins bins(pack.grains, cell, 2 * largest + 3 * gap);
  for (size_t i = 0; i < pack.grains.size(); ++i)
    bins.for_each_near(pack.grains[i].centre, [&](size_t j) {
      if (j <= i) return;
      const double s = relaxation.separation(pack.grains[i], pack.grains[j]);
      if (relaxation.in_contact(pack.grains[i], pack.grains[j], s)) ++pack.contacts;
      else pack.narrowest_gap = std::min(pack.narrowest_gap, s);
    });
  std::ostringstream text;
  text.precision(6);
  text << "Grains/Random Pack: " << pack.grains.size() << (dim == 2 ? " circles" : " spheres") << ", porosity "
       << pack.porosity << " (asked " << spec.porosity << "), radii " << smallest << " to " << largest << " m ("
       << (spec.distribution == RandomPackSpec::Distribution::Uniform ? "uniform" : "lognormal")
       << ", scaled by " << pack.radius_scale << "), " << pack.contacts << " contacts, narrowest open throat "
       << pack.narrowest_gap << " m (" << pack.narrowest_gap / scene.particle_spacing << " spacings; asked "
       << spec.minimum_gap << "), seed " << spec.seed << ", " << pack.stages << " growth stages, " << pack.sweeps
       << " sweeps";
  pack.description = text.str();
  return pack;
}

}  // namespace poresph
