#include "geometry/Grains.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "io/TextValues.hpp"

namespace poresph {
namespace {

double squared_distance(const std::array<double, 3>& d, int dim) {
  double s = 0;
  for (int k = 0; k < dim; ++k) s += d[k] * d[k];
  return s;
}

}  // namespace

std::vector<Grain> read_grain_file(const std::string& path, int dimension) {
  namespace fs = std::filesystem;
  std::error_code error;
  const auto status = fs::status(path, error);
  const std::string cannot = "Grains/File: cannot open '" + path + "': ";
  if (!fs::exists(status)) throw std::invalid_argument(cannot + "no such file");
  // A directory or a device reads as no lines at all: zero grains, porosity 1, without a word.
  if (fs::is_directory(status)) throw std::invalid_argument(cannot + "it is a directory, not a grain file");
  if (!fs::is_regular_file(status)) throw std::invalid_argument(cannot + "it is not a regular file");
  std::ifstream in(path);
  if (!in) throw std::invalid_argument(cannot + std::strerror(errno));
  std::vector<Grain> grains;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    std::istringstream fields(line);
    std::vector<double> values;
    std::string word;
    while (fields >> word) {
      const auto parsed = parse_number<double>(word);  // as every number PoreSPH reads: NaN is no coordinate
      if (!parsed.value)
        throw std::invalid_argument(path + ":" + std::to_string(number) + ": '" + word + "' " + parsed.problem);
      values.push_back(*parsed.value);
    }
    if (values.empty()) continue;
    if (static_cast<int>(values.size()) != dimension + 1)
      throw std::invalid_argument(path + ":" + std::to_string(number) + ": expected " +
                                  std::to_string(dimension + 1) + " numbers (" +
                                  (dimension == 2 ? "cx cy r" : "cx cy cz r") + "), found " +
                                  std::to_string(values.size()));
    Grain g;
    for (int d = 0; d < dimension; ++d) g.centre[d] = values[d];
    g.radius = values[dimension];
    g.origin = path + ":" + std::to_string(number);
    grains.push_back(g);
  }
  if (in.bad()) throw std::invalid_argument(cannot + std::strerror(errno));
  if (grains.empty())
    throw std::invalid_argument("Grains/File '" + path +
                                "' holds no grain (only blank lines or comments); a scene without grains "
                                "leaves Grains/File empty");
  return grains;
}

std::vector<Grain> grains_from_list(const std::vector<double>& values, int dimension) {
  const size_t per_grain = dimension + 1;
  if (values.size() % per_grain != 0)
    throw std::invalid_argument("Grains/Inline must hold " + std::to_string(per_grain) +
                                " numbers per grain (centre, radius); got " + std::to_string(values.size()));
  std::vector<Grain> grains;
  for (size_t k = 0; k < values.size() / per_grain; ++k) {
    Grain g;
    for (int d = 0; d < dimension; ++d) g.centre[d] = values[k * per_grain + d];
    g.radius = values[k * per_grain + dimension];
    g.origin = "Grains/Inline #" + std::to_string(k + 1);
    grains.push_back(g);
  }
  return grains;
}

std::array<double, 3> periodic_difference(const std::array<double, 3>& a, const std::array<double, 3>& b,
                                          const SceneConfig& scene) {
  std::array<double, 3> d{};
  for (int k = 0; k < scene.dimension; ++k) {
    d[k] = a[k] - b[k];
    if (scene.periodic[k]) d[k] -= scene.cell_size[k] * std::round(d[k] / scene.cell_size[k]);
  }
  return d;
}

void check_grains(const std::vector<Grain>& grains, const SceneConfig& scene) {
  const int dim = scene.dimension;
  for (const auto& g : grains) {
    for (int d = 0; d < dim; ++d)
      if (!std::isfinite(g.centre[d])) {
        std::ostringstream msg;
        msg << "grain " << g.origin << " has centre coordinate " << d << " = " << g.centre[d]
            << "; it must be a finite number";
        throw std::invalid_argument(msg.str());
      }
    if (!(g.radius > 0)) {
      std::ostringstream msg;
      msg << "grain " << g.origin << " has radius " << g.radius << "; radii must be positive";
      throw std::invalid_argument(msg.str());
    }
    for (int d = 0; d < dim; ++d)
      if (2 * g.radius > scene.cell_size[d]) {
        std::ostringstream msg;
        msg << "grain " << g.origin << " (radius " << g.radius << ") is wider than the cell side "
            << scene.cell_size[d] << " in direction " << d;
        throw std::invalid_argument(msg.str());
      }
  }
  if (scene.allow_overlapping_grains) return;
  for (size_t i = 0; i < grains.size(); ++i)
    for (size_t j = i + 1; j < grains.size(); ++j) {
      const double gap = std::sqrt(squared_distance(periodic_difference(grains[i].centre, grains[j].centre, scene), dim)) -
                         grains[i].radius - grains[j].radius;
      if (gap < 0) {
        std::ostringstream msg;
        msg << "grains " << grains[i].origin << " and " << grains[j].origin << " overlap by " << -gap
            << " (set Grains/Allow Overlap to accept this)";
        throw std::invalid_argument(msg.str());
      }
    }
}

std::vector<Throat> narrow_throats(const std::vector<Grain>& grains, const SceneConfig& scene, double max_gap) {
  const int dim = scene.dimension;
  std::vector<Throat> throats;
  for (size_t i = 0; i < grains.size(); ++i)
    for (size_t j = i; j < grains.size(); ++j) {
      // Every image of grain j near grain i (3^dim shifts along periodic directions).
      double narrowest = INFINITY;
      const int images = dim == 2 ? 9 : 27;
      for (int k = 0; k < images; ++k) {
        std::array<double, 3> offset{};
        bool skip = false;
        int rest = k, zero_shift = 0;
        for (int d = 0; d < dim; ++d, rest /= 3) {
          const int shift = rest % 3 - 1;
          if (shift != 0 && !scene.periodic[d]) skip = true;
          zero_shift += shift == 0;
          offset[d] = grains[j].centre[d] + shift * scene.cell_size[d] - grains[i].centre[d];
        }
        if (skip || (i == j && zero_shift == dim)) continue;
        narrowest = std::min(narrowest, std::sqrt(squared_distance(offset, dim)) - grains[i].radius - grains[j].radius);
      }
      // Touching or overlapping grains leave no throat between them.
      if (narrowest > 1e-12 * scene.cell_size[0] && narrowest < max_gap)
        throats.push_back({&grains[i], &grains[j], narrowest});
    }
  std::sort(throats.begin(), throats.end(), [](const Throat& a, const Throat& b) { return a.gap < b.gap; });
  return throats;
}

std::vector<std::string> check_throats(const std::vector<Grain>& grains, const SceneConfig& scene) {
  const double dx = scene.particle_spacing;
  std::vector<std::string> warnings;
  for (const auto& t : narrow_throats(grains, scene, 3 * dx)) {
    std::ostringstream msg;
    msg << "the throat between grain " << t.first->origin;
    if (t.first == t.second) msg << " and its periodic image";
    else msg << " and grain " << t.second->origin;
    msg << " is " << t.gap << " wide, " << t.gap / dx << " particle spacings";
    if (t.gap < dx) {
      msg << ": narrower than one spacing, it holds no fluid particle and the flow through it would be lost. "
             "Make the grains touch (Grains/Allow Overlap) or refine Discretization/Particle Spacing";
      throw std::invalid_argument(msg.str());
    }
    msg << ": fewer than 3 spacings across, so the permeability through it is underestimated";
    warnings.push_back(msg.str());
  }
  return warnings;
}

double porosity(const std::vector<Grain>& grains, const SceneConfig& scene) {
  const int dim = scene.dimension;
  double cell_volume = 1;
  for (int d = 0; d < dim; ++d) cell_volume *= scene.cell_size[d];
  bool overlapping = false;
  for (size_t i = 0; i < grains.size() && !overlapping; ++i)
    for (size_t j = i + 1; j < grains.size(); ++j)
      if (std::sqrt(squared_distance(periodic_difference(grains[i].centre, grains[j].centre, scene), dim)) <
          grains[i].radius + grains[j].radius) {
        overlapping = true;
        break;
      }
  if (!overlapping) {
    constexpr double pi = 3.14159265358979323846;
    double solid = 0;
    for (const auto& g : grains)
      solid += dim == 2 ? pi * g.radius * g.radius : 4.0 / 3.0 * pi * g.radius * g.radius * g.radius;
    return 1.0 - solid / cell_volume;
  }
  // Overlaps: count sample points of a fine grid covered by any grain.
  const int n = dim == 2 ? 2000 : 160;
  long long covered = 0, total = 0;
  std::array<double, 3> p{};
  const long long points = dim == 2 ? 1LL * n * n : 1LL * n * n * n;
  for (long long k = 0; k < points; ++k, ++total) {
    long long rest = k;
    for (int d = 0; d < dim; ++d, rest /= n) p[d] = (rest % n + 0.5) * scene.cell_size[d] / n;
    for (const auto& g : grains)
      if (squared_distance(periodic_difference(p, g.centre, scene), dim) <= g.radius * g.radius) {
        ++covered;
        break;
      }
  }
  return 1.0 - static_cast<double>(covered) / total;
}

}  // namespace poresph
