#include "geometry/Grains.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <queue>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "geometry/GrainBins.hpp"
#include "io/PathCheck.hpp"
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
  const std::string cannot = "Grains/File: cannot open '" + path + "': ";
  // A directory or a device reads as no lines at all: zero grains, porosity 1, without a word.
  if (const std::string problem = regular_file_problem(path, "a grain file"); !problem.empty())
    throw std::invalid_argument(cannot + problem);
  std::ifstream in(path);
  if (!in) throw std::invalid_argument(cannot + std::strerror(errno));
  std::vector<Grain> grains;
  std::string line;
  bool header_allowed = true;
  // A grain is its centre and radius, and optionally its solid's density:
  // the density column only under a header that names it last (a column
  // more without one may be an id, and is refused as before).
  const std::string columns = dimension == 2 ? "cx cy r" : "cx cy cz r";
  const int plain = dimension + 1, with_density = dimension + 2;
  int per_grain = plain;
  for (int number = 1; std::getline(in, line); ++number) {
    // A text editor's UTF-8 byte order mark is no part of the first number;
    // a file in UTF-16 (every other byte zero) is not read as garbage numbers.
    if (number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
    if (line.find('\0') != std::string::npos ||
        (number == 1 && (line.rfind("\xFF\xFE", 0) == 0 || line.rfind("\xFE\xFF", 0) == 0)))
      throw std::invalid_argument("Grains/File '" + path + "':" + std::to_string(number) +
                                  ": the file is not text in UTF-8 or ASCII (it holds zero bytes, as UTF-16 does): "
                                  "save it as plain text");
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    // DEM and packing tools write spheres as CSV as often as in columns:
    // commas and semicolons separate like blanks (a decimal comma is not read).
    for (char& c : line)
      if (c == ',' || c == ';') c = ' ';
    std::istringstream fields(line);
    std::vector<std::string> words;
    for (std::string word; fields >> word;) words.push_back(word);
    if (words.empty()) continue;
    // A first line of column names ("x y z r", "cx,cy,cz,radius") is a
    // header: every word starts with a letter and none reads as a number
    // (strtod takes "nan" and "inf", which stay errors on a grain line).
    const bool names_only = std::all_of(words.begin(), words.end(), [](const std::string& w) {
      char* end = nullptr;
      std::strtod(w.c_str(), &end);
      return std::isalpha(static_cast<unsigned char>(w[0])) && end == w.c_str();
    });
    if (header_allowed && names_only) {
      const int named = static_cast<int>(words.size());
      std::string last = words.back();
      for (char& c : last) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      const bool density_named = last.rfind("dens", 0) == 0 || last == "rho";
      if (named != plain && !(named == with_density && density_named))
        throw std::invalid_argument(path + ":" + std::to_string(number) + ": the header names " +
                                    std::to_string(named) + " columns; a grain has " + std::to_string(plain) + " (" +
                                    columns + "), or " + std::to_string(with_density) + " with its density last (" +
                                    columns + " density)");
      per_grain = named;
      header_allowed = false;
      continue;
    }
    header_allowed = false;
    std::vector<double> values;
    for (const auto& word : words) {
      const auto parsed = parse_number<double>(word);  // as every number PoreSPH reads: NaN is no coordinate
      if (!parsed.value)
        throw std::invalid_argument(path + ":" + std::to_string(number) + ": '" + word + "' " + parsed.problem);
      values.push_back(*parsed.value);
    }
    const int found = static_cast<int>(values.size());
    if (found != per_grain)
      throw std::invalid_argument(
          path + ":" + std::to_string(number) + ": expected " + std::to_string(per_grain) + " numbers (" + columns +
          (per_grain == with_density ? " density, as the header names them" : "") + "), found " +
          std::to_string(found) +
          (found == with_density ? std::string(dimension == 2 ? " (as a file of 3D grains has)" : "") +
                                       "; a density column needs a first line naming the columns, '" + columns +
                                       " density'"
                                 : ""));
    Grain g;
    for (int d = 0; d < dimension; ++d) g.centre[d] = values[d];
    g.radius = values[dimension];
    g.origin = path + ":" + std::to_string(number);
    if (found == with_density) {
      g.density = values[dimension + 1];
      if (!(g.density > 0))
        throw std::invalid_argument(path + ":" + std::to_string(number) + ": density " + words[dimension + 1] +
                                    " kg/m^3: a grain's density must be positive");
    }
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

double overlap_volume(double r1, double r2, double d, int dim) {
  constexpr double pi = 3.14159265358979323846;
  if (d >= r1 + r2) return 0.0;
  const double small = std::min(r1, r2);
  if (d <= std::abs(r1 - r2)) return ball_volume(small, dim);
  if (dim == 3)  // two spherical caps (e.g. Weisstein, "Sphere-Sphere Intersection")
    return pi * (r1 + r2 - d) * (r1 + r2 - d) * (d * d + 2 * d * r2 - 3 * r2 * r2 + 2 * d * r1 + 6 * r2 * r1 - 3 * r1 * r1) /
           (12 * d);
  const double a1 = std::acos(std::clamp((d * d + r1 * r1 - r2 * r2) / (2 * d * r1), -1.0, 1.0));
  const double a2 = std::acos(std::clamp((d * d + r2 * r2 - r1 * r1) / (2 * d * r2), -1.0, 1.0));
  return r1 * r1 * a1 + r2 * r2 * a2 -
         0.5 * std::sqrt(std::max(0.0, (-d + r1 + r2) * (d + r1 - r2) * (d - r1 + r2) * (d + r1 + r2)));
}

double porosity(const std::vector<Grain>& grains, const SceneConfig& scene) {
  const int dim = scene.dimension;
  double cell_volume = 1;
  for (int d = 0; d < dim; ++d) cell_volume *= scene.cell_size[d];
  double solid = 0;
  for (const auto& g : grains) solid += ball_volume(g.radius, dim);
  // Overlapping pairs (grains in contact in a packing), each with the
  // ball around its lens: the lens lies within the ball centred on the
  // circle where the surfaces meet, of that circle's radius, when neither
  // cap is more than half its grain.
  struct Lens {
    size_t i, j;
    std::array<double, 3> centre;
    double radius;
  };
  std::vector<Lens> lenses;
  bool exact = true;
  double largest = 0;
  for (const auto& g : grains) largest = std::max(largest, g.radius);
  // A pair could meet through two periodic images in a cell narrower than two diameters.
  for (int d = 0; d < dim; ++d) exact = exact && (!scene.periodic[d] || scene.cell_size[d] >= 4 * largest);
  for_each_close_pair(grains, scene, 0.0, [&](size_t i, size_t j) {
    const auto r = periodic_difference(grains[j].centre, grains[i].centre, scene);
    const double d = std::sqrt(squared_distance(r, dim));
    const double r1 = grains[i].radius, r2 = grains[j].radius;
    if (d >= r1 + r2) return;
    const double x1 = d > 0 ? (d * d + r1 * r1 - r2 * r2) / (2 * d) : -1;
    if (x1 < 0 || x1 > d) {  // a cap beyond half its grain, or one grain inside the other
      exact = false;
      return;
    }
    Lens lens{i, j, {}, std::sqrt(std::max(0.0, r1 * r1 - x1 * x1))};
    for (int k = 0; k < dim; ++k) lens.centre[k] = grains[i].centre[k] + r[k] * x1 / d;
    lenses.push_back(lens);
    solid -= overlap_volume(r1, r2, d, dim);
  });
  if (lenses.empty()) return 1.0 - solid / cell_volume;
  // Pairwise overlaps only: no third grain reaches into a lens's ball, so
  // no point is counted in three grains and the sum above is exact.
  if (exact) {
    const GrainBins bins(grains, scene, 2 * largest);
    for (const auto& lens : lenses) {
      bins.for_each_near(lens.centre, [&](size_t k) {
        if (k == lens.i || k == lens.j) return;
        const double reach = lens.radius + grains[k].radius;
        if (squared_distance(periodic_difference(lens.centre, grains[k].centre, scene), dim) < reach * reach)
          exact = false;
      });
      if (!exact) break;
    }
  }
  if (exact) return 1.0 - solid / cell_volume;
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

std::string grain_file_text(const std::vector<Grain>& grains, int dimension, const std::string& header) {
  std::string text;
  std::istringstream lines(header);
  for (std::string line; std::getline(lines, line);) text += "# " + line + "\n";
  // Densities (the grain file's column) are written back when the grains
  // have them, under the header line that names the column.
  const bool densities = !grains.empty() && grains.front().density > 0;
  const std::string columns = dimension == 2 ? "cx cy r" : "cx cy cz r";
  text += densities ? "# centre and radius (m), density (kg/m^3)\n" + columns + " density\n" : "# " + columns + " (m)\n";
  char buffer[48];
  for (const auto& g : grains) {
    for (int d = 0; d < dimension; ++d) {
      std::snprintf(buffer, sizeof buffer, "%.17g ", g.centre[d]);
      text += buffer;
    }
    std::snprintf(buffer, sizeof buffer, "%.17g", g.radius);
    text += buffer;
    if (densities) {
      std::snprintf(buffer, sizeof buffer, " %.17g", g.density);
      text += buffer;
    }
    text += "\n";
  }
  return text;
}

std::string grains_used_text(const SceneConfig& scene) {
  std::string header = "The grains of scene " + scene.name + ", " +
                       (scene.grains_note.empty() ? std::string("as given in the scene") : scene.grains_note) +
                       ".\nGrains/File reads this file back exactly" +
                       (scene.allow_overlapping_grains ? " (with Grains/Allow Overlap = true)." : ".");
  return grain_file_text(scene.grains, scene.dimension, header);
}

}  // namespace poresph
