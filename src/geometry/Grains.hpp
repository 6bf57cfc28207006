#pragma once
// Soil grains: circles in 2D, spheres in 3D, in the periodic unit cell.
// Read from a text file (one grain a line: cx cy r, or cx cy cz r) or from
// an inline list, and checked before any work is done.
#include <array>
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
