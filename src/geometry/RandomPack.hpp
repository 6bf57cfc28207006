#pragma once
// Random periodic packs of spheres (circles in 2D) at a given porosity
// (Grains/Random Pack), reproducible from a seed:
//
// 1. Radii are drawn from the distribution until their volume reaches the
//    solid volume (1 - porosity) V of the cell, and all are scaled by one
//    factor (within about 1/(3N) of 1 for N grains) so that it is matched.
// 2. Centres are drawn uniformly in the cell, and the grains grown from a
//    tenth of the solid fraction to their radii in stages (collective
//    rearrangement, as Jodrey & Tory 1985 and Clarke & Wiley 1987 pack
//    spheres; Lubachevsky & Stillinger 1990 grow them by event-driven
//    dynamics instead). After each stage every pair that breaks the rule
//    below is set right by moving both grains along the line of centres,
//    the smaller further (in proportion to the other's volume), pair after
//    pair in a fixed order, sweep after sweep, until none breaks it. A
//    stage that does not settle is undone and retried with half the growth.
// 3. The rule, with g the minimum gap: two grains are either at least g
//    apart (an open throat the fluid lattice resolves: the scene checks
//    refuse throats under one particle spacing) or, with contacts allowed,
//    in contact, overlapping by at most min(g, 0.1 r_small): a pair closer
//    than g/2 is pulled into contact (to half that overlap), one from g/2 to
//    g pushed apart to g. Grains of a soil touch; a pack at porosity 0.4 of
//    grains 12 spacings across cannot keep one spacing between all of them
//    (the grains plus half the gap would fill 0.6 (13/12)^3 = 0.76 of the
//    cell, beyond the 0.64 of a random close packing). Without contacts
//    every pair keeps the gap, which limits the porosity from below.
// 4. With contacts the overlaps' lenses are solid counted twice: the radii
//    are scaled again until the exact porosity (geometry/Grains.hpp) is the
//    target to 1e-6, and the rule restored after each scaling.
//
// Collective rearrangement was chosen over random sequential addition
// (which jams near a solid fraction of 0.38, far from 0.6) and over
// force-biased or event-driven growth (the same packs, more machinery): it
// needs only pair moves, which the grain bins (geometry/GrainBins.hpp) keep
// linear in the number of grains, and with a fixed order of pairs and
// std::mt19937_64 draws (the engine's output is fixed by the C++ standard;
// the library's distributions are not, so they are not used)
// the same seed gives the same pack on every machine whose libm agrees on
// log, cos and pow. The spheres used are written to grains_used.txt in the
// output directory, so that a run can be repeated from the file anywhere.
#include <string>
#include <vector>

#include "scene/SceneConfig.hpp"

namespace poresph {

struct RandomPackSpec {
  double porosity = 0;  // target; 0: no pack
  enum class Distribution { Uniform, Lognormal } distribution = Distribution::Uniform;
  double min_radius = 0, max_radius = 0;       // uniform between; lognormal truncated to them
  double median_radius = 0, log_deviation = 0;  // lognormal: ln r ~ N(ln median, deviation^2)
  double minimum_gap = 1;                       // in particle spacings
  bool contacts = true;
  unsigned long long seed = 1;
};

struct RandomPack {
  std::vector<Grain> grains;
  double porosity = 1;            // exact, of the grains made
  long long contacts = 0;         // pairs in contact (overlapping)
  double narrowest_gap = 0;       // narrowest open throat between two grains (m)
  double radius_scale = 1;        // the common factor of step 1 (and 4)
  int stages = 0;                 // growth stages taken
  long long sweeps = 0;           // sweeps over the pairs, all stages
  std::string description;        // one line: what was asked and what was made
};

// The pack of `spec` in the scene's cell (periodic in every direction).
// Throws std::invalid_argument naming the parameter when the request cannot
// be met (an impossible porosity, a gap that leaves no room, a cell too small
// for its largest grain), or when the growth jams before the porosity.
RandomPack make_random_pack(const RandomPackSpec& spec, const SceneConfig& scene);

}  // namespace poresph
