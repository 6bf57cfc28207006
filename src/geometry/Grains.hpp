#pragma once
// Soil grains: circles in 2D, spheres in 3D, in the periodic unit cell.
// Read from a text file (one grain a line: cx cy r, or cx cy cz r) or from
// an inline list, and checked before any work is done.
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "scene/SceneConfig.hpp"

namespace poresph {

// Parses a grain file: `#` starts a comment, blank lines are skipped, every
// other line holds dimension + 1 numbers. Throws std::invalid_argument naming
// the file and line.
std::vector<Grain> read_grain_file(const std::string& path, int dimension);

// Grains from a flat list cx, cy, r, cx, cy, r, ... (dimension + 1 per grain).
std::vector<Grain> grains_from_list(const std::vector<double>& values, int dimension);

// The area (2D, per metre of depth) or volume (3D) of a grain of radius r.
inline double ball_volume(double r, int dim) {
  constexpr double pi = 3.14159265358979323846;
  return dim == 2 ? pi * r * r : 4.0 / 3.0 * pi * r * r * r;
}

// f(index, from_centre, dist) for every point (i + 1/2) dx of a lattice of
// `count` points a side whose distance from the grain's centre is at most
// its radius + reach: index wrapped on periodic axes and left as it falls on
// the others (the caller bounds it), from_centre the point's unwrapped
// offset. Only the grain's bounding box is scanned, so a grain costs its
// volume, not the lattice's.
template <int Dim, class F>
void for_each_point_of_grain(const Grain& grain, double dx, double reach, const std::array<bool, 3>& periodic,
                             const int (&count)[Dim], F&& f) {
  int box_lo[Dim], box_hi[Dim];
  long long box = 1;
  for (int d = 0; d < Dim; ++d) {
    box_lo[d] = static_cast<int>(std::floor((grain.centre[d] - grain.radius) / dx - 0.5));
    box_hi[d] = static_cast<int>(std::ceil((grain.centre[d] + grain.radius) / dx - 0.5));
    box *= box_hi[d] - box_lo[d] + 1;
  }
  for (long long b = 0; b < box; ++b) {
    int index[Dim];
    double from_centre[Dim];
    double dist_sq = 0;
    long long rest = b;
    for (int d = 0; d < Dim; ++d) {
      const int span = box_hi[d] - box_lo[d] + 1;
      const int unwrapped = box_lo[d] + static_cast<int>(rest % span);
      rest /= span;
      from_centre[d] = (unwrapped + 0.5) * dx - grain.centre[d];
      dist_sq += from_centre[d] * from_centre[d];
      index[d] = periodic[d] ? ((unwrapped % count[d]) + count[d]) % count[d] : unwrapped;
    }
    const double dist = std::sqrt(dist_sq);
    if (dist <= grain.radius + reach) f(index, from_centre, dist);
  }
}

// Displacement a - b to the nearest periodic image along periodic directions.
std::array<double, 3> periodic_difference(const std::array<double, 3>& a, const std::array<double, 3>& b,
                                          const SceneConfig& scene);

// Refuses, naming the grains: a non-positive radius, a grain wider than the
// cell, and (unless allowed) two grains that overlap.
void check_grains(const std::vector<Grain>& grains, const SceneConfig& scene);

// A pore throat: the narrowest gap between two grains (or a grain and its
// own periodic image), where the flow through a packing is decided.
struct Throat {
  const Grain* first;
  const Grain* second;  // the same grain for a throat with its own image
  double gap;           // surface to surface
};

// Throats open (gap > 0) but narrower than max_gap: how many there are, and
// the `keep` narrowest of them, narrowest first (equal gaps in input order).
// A packing far finer than the spacing can have a narrow throat at every
// grain; the count keeps the memory bounded without hiding how many.
struct ThroatSurvey {
  std::vector<Throat> narrowest;
  long long count = 0;
};
ThroatSurvey narrow_throats(const std::vector<Grain>& grains, const SceneConfig& scene, double max_gap,
                            size_t keep);

// Warnings listed one by one; beyond this many, one more says how many others there are.
constexpr size_t kThroatWarnings = 100;

// A throat narrower than the particle spacing holds no fluid particle, so
// the flow through it would be silently lost: refused, naming the grains
// (close it with touching grains, or refine the spacing). Throats resolved
// by fewer than three spacings are returned as warnings: k through them is
// underestimated.
std::vector<std::string> check_throats(const std::vector<Grain>& grains, const SceneConfig& scene);

// Fraction of the cell not covered by grains: exact for separate grains and
// for grains that overlap pairwise (in contact, as in a pack: each lens
// subtracted once), sampled on a fine grid where three grains may share a
// point or a grain reaches past half of another.
double porosity(const std::vector<Grain>& grains, const SceneConfig& scene);

// The volume (area in 2D) common to two spheres (circles) of radii r1, r2
// whose centres are d apart.
double overlap_volume(double r1, double r2, double d, int dim);

// The grains as a grain file (Grains/File reads it back exactly): `header`
// as comment lines, then one grain a line, cx cy [cz] r, 17 digits.
std::string grain_file_text(const std::vector<Grain>& grains, int dimension, const std::string& header);

// grains_used.txt of a run: the scene's grains with how they were made
// (the random pack's note, or "as given in the scene").
std::string grains_used_text(const SceneConfig& scene);

}  // namespace poresph
