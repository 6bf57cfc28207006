#include "geometry/Grains.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <queue>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "io/TextValues.hpp"

namespace poresph {
namespace {

double squared_distance(const std::array<double, 3>& d, int dim) {
  double s = 0;
  for (int k = 0; k < dim; ++k) s += d[k] * d[k];
  return s;
}

// The grains sorted into bins of the cell at least `width` wide, so that
// every grain whose centre is within `width` of a point (at the nearest
// periodic image) sits in the point's bin or a neighbouring one. The checks
// of a packing then look at neighbours only: set-up grows with the number
// of grains, not with its square (40,000 grains took 86 s pairwise).
class GrainBins {
 public:
  GrainBins(const std::vector<Grain>& grains, const SceneConfig& scene, double width)
      : scene_(scene), dim_(scene.dimension) {
    // No more bins than about four per grain: tiny grains in a large cell
    // would otherwise ask for more bins than memory holds. Wider bins are
    // still correct, only less selective.
    const double most_bins = 4.0 * static_cast<double>(grains.size()) + 1;
    const double per_direction = std::max(1.0, std::floor(std::pow(most_bins, 1.0 / dim_)));
    size_t bins = 1;
    for (int d = 0; d < dim_; ++d) {
      const double fit = width > 0 ? std::floor(scene.cell_size[d] / width) : per_direction;
      count_[d] = static_cast<int>(std::clamp(fit, 1.0, per_direction));
      bins *= count_[d];
    }
    begin_.assign(bins + 1, 0);
    std::vector<size_t> bin_of(grains.size());
    for (size_t g = 0; g < grains.size(); ++g) ++begin_[(bin_of[g] = bin(grains[g].centre)) + 1];
    for (size_t b = 0; b < bins; ++b) begin_[b + 1] += begin_[b];
    members_.resize(grains.size());
    std::vector<size_t> next(begin_.begin(), begin_.end() - 1);
    for (size_t g = 0; g < grains.size(); ++g) members_[next[bin_of[g]]++] = g;  // ascending within a bin
  }

  // f(g) once for every grain in the bins around `point`.
  template <class F>
  void for_each_near(const std::array<double, 3>& point, F&& f) const {
    // Bin indices per direction, each once (with one or two bins along a
    // periodic direction, -1 and +1 wrap onto the same bins).
    int around[3][3] = {}, found[3] = {1, 1, 1};
    for (int d = 0; d < dim_; ++d) {
      const int n = count_[d], k = index(point[d], d);
      found[d] = 0;
      for (int o = -1; o <= 1; ++o) {
        int j = k + o;
        if (scene_.periodic[d]) j = ((j % n) + n) % n;
        else if (j < 0 || j >= n) continue;
        if (std::find(around[d], around[d] + found[d], j) == around[d] + found[d]) around[d][found[d]++] = j;
      }
    }
    for (int a2 = 0; a2 < found[2]; ++a2)
      for (int a1 = 0; a1 < found[1]; ++a1)
        for (int a0 = 0; a0 < found[0]; ++a0) {
          const size_t b = (static_cast<size_t>(around[2][a2]) * count_[1] + around[1][a1]) * count_[0] + around[0][a0];
          for (size_t m = begin_[b]; m < begin_[b + 1]; ++m) f(members_[m]);
        }
  }

 private:
  int index(double x, int d) const {
    double y = x;
    if (scene_.periodic[d]) y -= scene_.cell_size[d] * std::floor(y / scene_.cell_size[d]);
    const double k = std::floor(y / scene_.cell_size[d] * count_[d]);
    return static_cast<int>(std::clamp(k, 0.0, count_[d] - 1.0));  // beyond a wall: the edge bin
  }
  size_t bin(const std::array<double, 3>& x) const {
    size_t b = 0;
    for (int d = dim_ - 1; d >= 0; --d) b = b * count_[d] + index(x[d], d);
    return b;
  }

  const SceneConfig& scene_;
  int dim_;
  std::array<int, 3> count_{{1, 1, 1}};
  std::vector<size_t> begin_, members_;
};

double largest_radius(const std::vector<Grain>& grains) {
  double r = 0;
  for (const auto& g : grains) r = std::max(r, g.radius);
  return r;
}

// f(i, j) for every pair i < j whose surfaces, at the nearest periodic
// image, are closer than `reach` (and perhaps a few more): each pair once.
template <class F>
void for_each_close_pair(const std::vector<Grain>& grains, const SceneConfig& scene, double reach, F&& f) {
  const GrainBins bins(grains, scene, 2 * largest_radius(grains) + reach);
  for (size_t i = 0; i < grains.size(); ++i)
    bins.for_each_near(grains[i].centre, [&](size_t j) {
      if (j > i) f(i, j);
    });
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
  // The first overlapping pair in the order of the input, as a scan of all pairs would name it.
  size_t first = grains.size(), second = grains.size();
  double overlap = 0;
  for_each_close_pair(grains, scene, 0.0, [&](size_t i, size_t j) {
    const double gap =
        std::sqrt(squared_distance(periodic_difference(grains[i].centre, grains[j].centre, scene), dim)) -
        grains[i].radius - grains[j].radius;
    if (gap < 0 && std::make_pair(i, j) < std::make_pair(first, second)) first = i, second = j, overlap = -gap;
  });
  if (first < grains.size()) {
    std::ostringstream msg;
    msg << "grains " << grains[first].origin << " and " << grains[second].origin << " overlap by " << overlap
        << " (set Grains/Allow Overlap to accept this)";
    throw std::invalid_argument(msg.str());
  }
}

ThroatSurvey narrow_throats(const std::vector<Grain>& grains, const SceneConfig& scene, double max_gap,
                            size_t keep) {
  const int dim = scene.dimension;
  struct Found {
    size_t i, j;
    double gap;
    bool operator<(const Found& o) const { return std::tie(gap, i, j) < std::tie(o.gap, o.i, o.j); }
  };
  std::priority_queue<Found> kept;  // the `keep` narrowest so far, the widest of them on top
  ThroatSurvey survey;
  // The narrowest gap between grain i and any image of grain j within one
  // cell (3^dim shifts along periodic directions), the grain's own copy aside.
  auto throat = [&](size_t i, size_t j) {
    // The nearest image first, a few operations: most pairs the bins offer
    // are too far apart, and no other image is nearer.
    const double nearest =
        std::sqrt(squared_distance(periodic_difference(grains[i].centre, grains[j].centre, scene), dim)) -
        grains[i].radius - grains[j].radius;
    if (i != j && nearest > max_gap * (1 + 1e-12)) return;
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
    if (!(narrowest > 1e-12 * scene.cell_size[0] && narrowest < max_gap)) return;
    ++survey.count;
    kept.push({i, j, narrowest});
    if (kept.size() > keep) kept.pop();
  };
  for (size_t i = 0; i < grains.size(); ++i) throat(i, i);
  for_each_close_pair(grains, scene, max_gap, throat);
  std::vector<Found> found;
  for (; !kept.empty(); kept.pop()) found.push_back(kept.top());
  std::reverse(found.begin(), found.end());  // narrowest first; equal gaps in the order of the input
  for (const auto& f : found) survey.narrowest.push_back({&grains[f.i], &grains[f.j], f.gap});
  return survey;
}

std::vector<std::string> check_throats(const std::vector<Grain>& grains, const SceneConfig& scene) {
  const double dx = scene.particle_spacing;
  std::vector<std::string> warnings;
  // Refusals first, over the pairs closer than one spacing only: a packing
  // far finer than the spacing has thousands of neighbours within three.
  auto survey = narrow_throats(grains, scene, dx, 1);
  if (survey.count == 0) survey = narrow_throats(grains, scene, 3 * dx, kThroatWarnings);
  for (const auto& t : survey.narrowest) {
    std::ostringstream msg;
    msg << "the throat between grain " << t.first->origin;
    if (t.first == t.second) msg << " and its periodic image";
    else msg << " and grain " << t.second->origin;
    msg << " is " << t.gap << " wide, " << t.gap / dx << " particle spacings";
    if (t.gap < dx) {
      msg << ": narrower than one spacing, it holds no fluid particle and the flow through it would be lost. "
             "Make the grains touch (Grains/Allow Overlap) or refine Discretization/Particle Spacing";
      if (survey.count > 1) msg << " (" << survey.count << " throats are narrower than one spacing)";
      throw std::invalid_argument(msg.str());
    }
    msg << ": fewer than 3 spacings across, so the permeability through it is underestimated";
    warnings.push_back(msg.str());
  }
  if (survey.count > static_cast<long long>(survey.narrowest.size()))
    warnings.push_back("and " + std::to_string(survey.count - survey.narrowest.size()) +
                       " more throats narrower than 3 particle spacings (the " +
                       std::to_string(survey.narrowest.size()) + " narrowest are listed)");
  return warnings;
}

double porosity(const std::vector<Grain>& grains, const SceneConfig& scene) {
  const int dim = scene.dimension;
  double cell_volume = 1;
  for (int d = 0; d < dim; ++d) cell_volume *= scene.cell_size[d];
  bool overlapping = false;
  for_each_close_pair(grains, scene, 0.0, [&](size_t i, size_t j) {
    overlapping = overlapping ||
                  std::sqrt(squared_distance(periodic_difference(grains[i].centre, grains[j].centre, scene), dim)) <
                      grains[i].radius + grains[j].radius;
  });
  if (!overlapping) {
    constexpr double pi = 3.14159265358979323846;
    double solid = 0;
    for (const auto& g : grains)
      solid += dim == 2 ? pi * g.radius * g.radius : 4.0 / 3.0 * pi * g.radius * g.radius * g.radius;
    return 1.0 - solid / cell_volume;
  }
  // Overlaps: count sample points of a fine grid covered by any grain (the
  // grains near each point only: a point inside a grain is within the
  // largest radius of its centre).
  const GrainBins bins(grains, scene, largest_radius(grains));
  const int n = dim == 2 ? 2000 : 160;
  long long covered = 0, total = 0;
  std::array<double, 3> p{};
  const long long points = dim == 2 ? 1LL * n * n : 1LL * n * n * n;
  for (long long k = 0; k < points; ++k, ++total) {
    long long rest = k;
    for (int d = 0; d < dim; ++d, rest /= n) p[d] = (rest % n + 0.5) * scene.cell_size[d] / n;
    bool inside = false;
    bins.for_each_near(p, [&](size_t g) {
      inside = inside || squared_distance(periodic_difference(p, grains[g].centre, scene), dim) <=
                             grains[g].radius * grains[g].radius;
    });
    covered += inside;
  }
  return 1.0 - static_cast<double>(covered) / total;
}

}  // namespace poresph
