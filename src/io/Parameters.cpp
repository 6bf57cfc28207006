#include "io/Parameters.hpp"

#include <Teuchos_Array.hpp>
#include <Teuchos_StandardParameterEntryValidators.hpp>
#include <Teuchos_StringInputSource.hpp>
#include <Teuchos_XMLObject.hpp>
#include <Teuchos_XMLParameterListCoreHelpers.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <type_traits>

#include "io/PathCheck.hpp"
#include "io/TextValues.hpp"
#include "io/XmlText.hpp"

namespace poresph {
namespace {

using Teuchos::Array;
using Teuchos::ParameterList;
using Teuchos::RCP;
using Teuchos::rcp;

constexpr double kHuge = std::numeric_limits<double>::max();

RCP<const Teuchos::ParameterEntryValidator> real_in(double lo, double hi) {
  return rcp(new Teuchos::EnhancedNumberValidator<double>(lo, hi));
}
RCP<const Teuchos::ParameterEntryValidator> int_in(int lo, int hi) {
  return rcp(new Teuchos::EnhancedNumberValidator<int>(lo, hi));
}
RCP<const Teuchos::ParameterEntryValidator> reals_in(double lo, double hi) {
  return rcp(new Teuchos::ArrayNumberValidator<double>(rcp(new Teuchos::EnhancedNumberValidator<double>(lo, hi))));
}
RCP<const Teuchos::ParameterEntryValidator> ints_in(int lo, int hi) {
  return rcp(new Teuchos::ArrayNumberValidator<int>(rcp(new Teuchos::EnhancedNumberValidator<int>(lo, hi))));
}
RCP<const Teuchos::ParameterEntryValidator> one_of(std::initializer_list<std::string> words) {
  return rcp(new Teuchos::StringValidator(Array<std::string>(words)));
}

RCP<ParameterList> make_valid_parameters() {
  auto list = rcp(new ParameterList("PoreSPH"));
  {
    auto& s = list->sublist("Scene", false, "What the run is called.");
    s.set("Name", std::string("scene"),
          "Name written to summary.json; the output directory is poresph-NAME unless --output names one. "
          "No path separators.");
  }
  {
    auto& s = list->sublist("Domain", false, "The periodic unit cell [0, L_x) x [0, L_y) (x [0, L_z)).");
    s.set("Cell Size", Array<double>(), "REQUIRED. Side lengths of the cell; 2 values for a 2D run, 3 for 3D.",
          reals_in(0.0, kHuge));
    s.set("Periodic", Array<int>(),
          "Per direction, 1 = periodic, 0 = bounded by walls. Empty: periodic in every direction.", ints_in(0, 1));
  }
  {
    auto& s = list->sublist("Fluid", false, "The fluid and the force that drives it.");
    s.set("Density", 1000.0, "Reference density rho0 (kg/m^3); particle mass is rho0 dx^N.", real_in(0.0, kHuge));
    s.set("Kinematic Viscosity", 1e-6, "REQUIRED. Kinematic viscosity nu (m^2/s), >= 0.", real_in(0.0, kHuge));
    s.set("Body Force", Array<double>(), "Body acceleration F (m/s^2), one value per direction. Empty: none.",
          reals_in(-kHuge, kHuge));
    s.set("Sound Speed", 0.0,
          "Speed of sound c (m/s). 0: c^2 = max(V^2/delta, nu V/(delta L), |F| L/delta) from the scales below.",
          real_in(0.0, kHuge));
    s.set("Density Variation", 0.01, "delta, the density variation the sound-speed rule aims at.",
          real_in(1e-6, 0.5));
    s.set("Raise Sound Speed", false,
          "Raise c from the delta rule to the largest value the viscous and body-force time-step limits "
          "allow (0.25 h / c = the smaller of them): the same time step, a stiffer fluid whose pressure "
          "waves settle sooner. Pays where the viscous limit sets dt (fine spacings). Not with Sound Speed. "
          "Fixed particles (Discretization/Particle Motion) always raise c unless Sound Speed is given: their "
          "steady state does not depend on it, and it settles sooner.");
    s.set("Velocity Scale", 0.0,
          "V for the sound-speed rule (m/s). 0: the largest of the wall speeds, the speeds of moving grains' "
          "surfaces at the start (Grains/Initial Velocity and Initial Spin) and |F| L^2/(8 nu).",
          real_in(0.0, kHuge));
    s.set("Background Pressure", 0.0,
          "Fraction beta of c^2 rho0 kept in the momentum equation, which sees p - (1 - beta) c^2 rho0. "
          "1: p = c^2 rho itself, as printed in Morris et al. 1999. A uniform pressure has no gradient, but "
          "through the SPH gradient of a disordered or sheared particle arrangement it exerts spurious forces "
          "proportional to itself (docs/validation.md); a small beta keeps the pressure positive where the "
          "fluid is rarefied, which prevents clumping.",
          real_in(0.0, 1.0));
    s.set("Length Scale", 0.0, "L for the sound-speed rule (m). 0: the largest cell side.", real_in(0.0, kHuge));
    s.set("Convection", true,
          "Fixed particles: keep the convective term (v.grad)v of the Navier-Stokes equations, which lowers k "
          "once the Reynolds number nears 1. false: Stokes flow (creeping scenes), a little cheaper. "
          "Lagrangian particles carry convection in their own motion.");
  }
  {
    auto& s = list->sublist("Discretization", false, "Particles, kernel and time stepping.");
    s.set("Particle Spacing", 0.0,
          "Initial lattice spacing dx (m); must divide every periodic cell side. This or Spacings Across Throat "
          "is REQUIRED, not both.",
          real_in(0.0, kHuge));
    s.set("Spacings Across Throat", 0.0,
          "Instead of Particle Spacing: the spacing is the narrowest pore throat between grains (the gap the "
          "throat check measures), or the width an image's widest pore path narrows to, divided by this, made a little finer so that the cell holds a whole number "
          "of spacings. Resolution where the flow is decided. 0: not used.",
          real_in(0.0, 1e6));
    s.set("Particle Motion", std::string("fixed"),
          "'fixed': particles stay on their lattice and only velocity, density and pressure evolve (Eulerian "
          "SPH with the convective term, Fluid/Convection): the arrangement cannot lose its order, nothing "
          "enters a grain, neighbour lists never change, and a steady flow stays steady. 'lagrangian': "
          "particles move with the flow, as in Morris et al. 1999 (with Particle Shifting against disorder "
          "near grains). docs/method.md compares them.",
          one_of({"fixed", "lagrangian"}));
    s.set("Wall Pressure", std::string("extrapolated"),
          "Pressure of the boundary particles of grains and walls. 'extrapolated': from the fluid next to them "
          "plus the body force's hydrostatic part (Adami, Hu & Adams 2012), so that a steady flow has a steady "
          "wall. 'continuity': their own density by the continuity equation, as in Morris et al. 1999, which "
          "past a curved surface keeps changing while the fluid flows (docs/method.md).",
          one_of({"extrapolated", "continuity"}));
    s.set("Smoothing Length Ratio", 1.0,
          "h / dx of the quintic kernel (support 3h), from 0.9: below it the kernel reaches too few neighbours "
          "for the viscous term, and k comes out too high whatever the spacing (the square array c = 0.2: +1.1 % "
          "at 0.8, +39 % at 0.6, +167 % at 0.5; -3e-5 at 0.9). Solver/Method = steady is measured at 1; from 1.5 "
          "it did not converge where the march does (docs/method.md).",
          real_in(0.9, 3.0));
    s.set("Density Resummation Interval", 0,
          "Re-initialise fluid density by summation every this many steps; 0 = never. Lagrangian particles "
          "only (on a fixed lattice the sum never changes).",
          int_in(0, 1 << 30));
    s.set("Neighbour Skin", 0.2,
          "Verlet skin in units of h: neighbour lists hold pairs within 3h + skin and are rebuilt once some "
          "particle has moved half the skin. 0 = rebuild every evaluation. Fixed particles need none.",
          real_in(0.0, 3.0));
    s.set("Particle Shifting", 0.0,
          "Particle shifting coefficient A (Lind et al. 2012): each step fluid particles move by "
          "-A h |v| dt grad C towards uniform spacing (at most 0.05 dx), velocities corrected to first order. "
          "0 = off. Lagrangian particles only.",
          real_in(0.0, 100.0));
    s.set("Time Step", 0.0,
          "Fixed time step (s). 0: min(0.25 h/c, 0.125 h^2/nu, 0.25 sqrt(h/|F|)). A larger value is refused.",
          real_in(0.0, kHuge));
  }
  {
    auto& s = list->sublist("Walls", false, "Plane no-slip walls.");
    s.set("Type", std::string("none"),
          "'none', or 'channel': walls at y = 0 and y = L_y (needs Domain/Periodic 0 in y), "
          "boundary particles 3h thick beyond them.",
          one_of({"none", "channel"}));
    s.set("Lower Velocity", 0.0, "x velocity of the wall at y = 0 (m/s).", real_in(-kHuge, kHuge));
    s.set("Upper Velocity", 0.0, "x velocity of the wall at y = L_y (m/s).", real_in(-kHuge, kHuge));
  }
  {
    auto& s = list->sublist("Phases", false,
                            "Two immiscible fluids on fixed particles (Discretization/Particle Motion = fixed): phase "
                            "0 is the Fluid sublist's fluid and fills the cell but for the region of phase 1, which "
                            "is set at the start (with Interface = fixed a particle never changes phase). The "
                            "viscous term between two particles takes the harmonic mean of their dynamic viscosities, "
                            "which keeps the "
                            "shear stress continuous across an interface (docs/method.md). With Surface Tension > 0 "
                            "the interface pulls by the continuum surface force. With Interface = moving the phases "
                            "follow the flow as a phase field, and wet the solids by Contact Angle.");
    s.set("Count", 1,
          "Number of fluid phases: 1 (the Fluid sublist's alone; the rest of this sublist must be left out) or 2.",
          int_in(1, 2));
    s.set("Single Phase Permeability", 0.0,
          "The cell's single-phase permeability k (m^2), e.g. from a run without Phases: with it summary.json "
          "reports each phase's relative permeability k_r = (superficial velocity x dynamic viscosity / (density "
          "x |body force|)) / k. 0: no k_r.",
          real_in(0.0, kHuge));
    s.set("Surface Tension", 0.0,
          "Surface tension sigma between the two phases (N/m), >= 0; 0: none. The continuum surface force "
          "sigma kappa n / rho of Morris (2000) from a colour function on the fixed lattice, computed once at "
          "set-up (docs/method.md); with Interface = fixed it needs Count = 2, a cell periodic in every "
          "direction and no grains, image or walls. With Interface = moving: sigma kappa grad(phi) / rho from "
          "the phase field, every step, with wetting on any solid.",
          real_in(0.0, kHuge));
    s.set("Colour", std::string("volume fraction"),
          "The colour function the surface tension's normals and curvature are taken from: 'volume fraction' "
          "(each particle's share of its lattice cell that phase 1's region covers) or 'phase' (its phase, 0 "
          "or 1: a staircase on the lattice; docs/method.md compares them).",
          one_of({"volume fraction", "phase"}));
    s.set("Driven Phase", std::string("both"),
          "Which phase Fluid/Body Force acts on: 'both', or '0' or '1', that phase alone (the other is dragged "
          "along by the first across their interface). With one phase driven, each phase's relative "
          "permeability in summary.json is its coupling coefficient to the driven phase, "
          "k_r,ij = (U_i mu_i / (rho_j |F|)) / k; over the two one-phase runs they add up to the run with both "
          "driven (docs/method.md).",
          one_of({"both", "0", "1"}));
    s.set("Interface", std::string("fixed"),
          "'fixed': each particle keeps the phase it is given at the start, and the interface stays where it was "
          "put. 'moving': the phases are a phase field phi (1 in phase 1, 0 in phase 0) on the fixed lattice, "
          "carried by the flow and kept a layer of Interface Width by the conservative Allen-Cahn equation; a "
          "particle is of phase 1 where phi >= 1/2, the surface tension is taken from phi every step, and the "
          "solids wet by Contact Angle (docs/method.md). Moving needs Solver/Method = explicit and Convergence/Levels "
          "= 1; the field is whole on every process (its memory and work do not fall with the processes).",
          one_of({"fixed", "moving"}));
    s.set("Interface Width", 0.75,
          "With Interface = moving: the phase field's layer width epsilon in particle spacings (phi = 1 / (1 + "
          "exp(-s / epsilon)) across it), from 0.5 to 4; 0.75, where a drop at rest has the weakest currents "
          "(docs/method.md).",
          real_in(0.5, 4.0));
    s.set("Interface Mobility", 0.0,
          "With Interface = moving: the Allen-Cahn mobility gamma (m/s), >= 0, how fast the layer is kept at its "
          "width; 0: the capillary speed sigma / mu of the more viscous phase, capped where the explicit update "
          "would need more than one sub-step per time step (docs/method.md).",
          real_in(0.0, kHuge));
    s.set("Contact Angle", 90.0,
          "With Interface = moving: the static contact angle on every solid (grains, image, walls), in degrees "
          "from 0 to 180, measured through phase 0 (as Phase 1/Drainage/Contact Angle): below 90 phase 0 wets "
          "the solid.",
          real_in(0.0, 180.0));
    s.set("Contact Angles", Array<double>(),
          "With Interface = moving: a static contact angle per solid instead of Contact Angle's one, in degrees "
          "from 0 to 180 through phase 0: with an image, one per Image/Solid Values entry, in its order (a mixed-wet "
          "image: each solid value wets at its own angle); with grains, one per grain, in the grains' order. Plane "
          "walls (Walls/Type) keep Contact Angle. Empty: Contact Angle on every solid.",
          reals_in(0.0, 180.0));
    s.set("Force Steps", Array<double>(),
          "With Interface = moving: a stepped body force, the drive of a capillary-pressure-controlled drainage "
          "(or imbibition). Factors f_1, ..., f_n (each >= 0) of Fluid/Body Force: Run/End Time is cut into n "
          "equal spans, and during the i-th the body force is f_i times Fluid/Body Force (on the phases Driven "
          "Phase names). phases_history.csv, a row every check (at most 100 steps apart), then carries the force "
          "in a column 'body_force' (its component along the driven axis): a span's last row is where it ended, at "
          "rest if the span was long enough (docs/method.md). k and k_r are reported against Fluid/Body Force. "
          "Empty: the force holds.",
          reals_in(0.0, kHuge));
    auto& p = s.sublist("Phase 1", false,
                        "The second fluid and the region it fills (with Count = 2): a box (Region Low, Region "
                        "High), a disc/sphere (Region Centre, Region Radius) or the Drainage sublist's rule: "
                        "one of them.");
    p.set("Name", std::string("phase 1"), "Name of the phase in summary.json (phase 0 is 'fluid').");
    p.set("Density", 0.0,
          "Reference density of the phase (kg/m^3). 0: Fluid/Density. Only a density ratio of 1 is supported "
          "for now: any other value is refused.",
          real_in(0.0, kHuge));
    p.set("Kinematic Viscosity", 0.0,
          "REQUIRED with Count = 2. Kinematic viscosity nu of the phase (m^2/s), > 0, from 0.01 to 100 times "
          "Fluid/Kinematic Viscosity (the ratios validated); its dynamic viscosity is its density times nu.",
          real_in(0.0, kHuge));
    p.set("Region Low", Array<double>(),
          "Lower corner of the axis-aligned box [low, high) the phase fills, one value per direction, inside "
          "the cell: a particle whose lattice point lies in the box is of this phase. With Count = 2, the box "
          "or Region Centre and Region Radius is required.",
          reals_in(-kHuge, kHuge));
    p.set("Region High", Array<double>(), "Upper corner of the box (see Region Low).", reals_in(-kHuge, kHuge));
    p.set("Region Centre", Array<double>(),
          "Centre of the disc (2D) or sphere (3D) the phase fills instead of a box, one value per direction, "
          "inside the cell: a particle whose lattice point lies closer to it than Region Radius (across "
          "periodic faces, to the nearest image) is of this phase.",
          reals_in(-kHuge, kHuge));
    p.set("Region Radius", 0.0, "Radius of the disc or sphere (m), > 0 with Region Centre.", real_in(-kHuge, kHuge));
    p.set("Image Values", Array<int>(),
          "Instead of a region: the values of the image's voxels that this phase fills (Image, a segmented "
          "image of the solid and two fluids; none of them a Solid Value). A fluid particle takes the phase "
          "of the voxel holding its lattice point (on a face between voxels, the one above); one inside a "
          "solid voxel (the walls lie between voxels, smoothed) that of most pore voxels about it.",
          ints_in(0, 65535));
    auto& drainage = p.sublist(
        "Drainage", false,
        "Instead of a region: the phase is the non-wetting fluid placed by quasi-static drainage, the "
        "morphological rule of Hilpert & Miller (2001): at ball radius r it fills every ball of radius r that "
        "fits in the pore space and whose centre reaches the inlet through centres of such balls; capillary "
        "pressure Pc = (dim - 1) sigma cos(theta) / r. Measured on the fixed particles' lattice; needs a solid "
        "(grains, an image or walls). Give Saturation, Radius or Capillary Pressure. The run writes "
        "drainage.csv, the saturation against r (and Pc) down to half a spacing, and summary.json's "
        "'drainage' (docs/method.md).");
    drainage.set("Saturation", 0.0,
                 "Target saturation of the phase in (0, 1]: r is that of the drainage's first step (a row of "
                 "drainage.csv) that fills at least this share of the fluid particles. 0: Radius sets r (a row "
                 "of drainage.csv too).",
                 real_in(0.0, kHuge));
    drainage.set("Radius", 0.0, "The ball radius r (m), > 0. 0: Saturation or Capillary Pressure sets r.",
                 real_in(-kHuge, kHuge));
    drainage.set("Capillary Pressure", 0.0,
                 "The capillary pressure Pc (Pa), > 0, instead of Saturation or Radius: the balls' radius is "
                 "r = (dim - 1) sigma cos(theta) / Pc, with Surface Tension (required) and Contact Angle. 0: "
                 "Saturation or Radius sets r.",
                 real_in(-kHuge, kHuge));
    drainage.set("Inlet", std::string("x"),
                 "Where the phase enters: 'x', 'y' or 'z', the cell's face across that (periodic) axis (a reservoir "
                 "at x = 0, which across the periodic face is also x = L), or 'anywhere' (every ball that fits is "
                 "filled).",
                 one_of({"x", "y", "z", "anywhere"}));
    drainage.set("Trapping", false,
                 "Trap the wetting phase: the cell is a sample between two reservoirs (nothing wraps across the "
                 "Inlet's face), the non-wetting phase entering next to x = 0 (for Inlet = x) and the wetting "
                 "phase leaving next to x = L; wetting phase that no path of wetting phase joins to that outlet "
                 "stays, and the balls of later steps fit in the pore space less it (its residual saturation). "
                 "Not with Inlet = anywhere.");
    drainage.set("Contact Angle", 0.0,
                 "Static contact angle theta (degrees) measured through phase 0, the wetting fluid, in [0, 90): "
                 "it enters Pc only.",
                 real_in(-kHuge, kHuge));
    drainage.set("Surface Tension", 0.0,
                 "sigma (N/m) for the capillary pressure reported; 0: Pc not reported (r and the curvature "
                 "(dim - 1) cos(theta) / r are). No force: the placed interface is at rest.",
                 real_in(0.0, kHuge));
  }
  {
    auto& s = list->sublist("Grains", false, "Soil grains: circles in 2D, spheres in 3D. They may cross the periodic "
                                             "boundary and then act on both sides.");
    s.set("File", std::string(""),
          "Text file of grains, one a line: 'cx cy r' (2D) or 'cx cy cz r' (3D), separated by blanks, commas or "
          "semicolons (as DEM and packing tools write them), '#' comments, and an optional first line naming "
          "the columns. Moving grains (Grains/Motion) may take each its own solid density (kg/m^3) as one more "
          "column, 'cx cy r density' ('cx cy cz r density'), on every line, instead of Grains/Density. A "
          "relative path is relative to the scene file's folder. Every grain scene writes the grains it used to "
          "grains_used.txt in its output directory, in this format.");
    s.set("Inline", Array<double>(), "Grains in the XML: cx, cy, r, cx, cy, r, ... (cx, cy, cz, r in 3D).",
          reals_in(-kHuge, kHuge));
    s.set("Allow Overlap", false, "Accept overlapping grains; otherwise an overlap is an error naming them.");
    s.set("Motion", std::string("fixed"),
          "'fixed': the grains hold still. 'free': each grain is a rigid body that the fluid's force and torque "
          "(summed over its boundary particles from the pair terms) and Grains/Gravity move and turn. "
          "'rotating': each grain keeps its centre and turns freely. Moving grains need moving fluid "
          "(Discretization/Particle Motion = lagrangian) and Grains/Density (or each grain's in Grains/File).",
          one_of({"fixed", "free", "rotating"}));
    s.set("Density", 0.0, "Density of the grains' solid (kg/m^3), for their mass and moment of inertia "
                          "(Grains/Motion free or rotating); 0 with a density column in Grains/File, which gives "
                          "each grain its own.",
          real_in(0.0, kHuge));
    s.set("Gravity", Array<double>(),
          "Gravity (m/s^2), one value per direction, on moving grains and the fluid alike. In a periodic cell the "
          "suspension is held up as a whole by a uniform pressure gradient on fluid and grains by volume, so "
          "that the grains settle against the fluid (docs/method.md, 'Grains that move'). Empty: none.",
          reals_in(-kHuge, kHuge));
    s.set("Held", Array<int>(),
          "Grains that hold still while the others move (Grains/Motion free or rotating): their indices, from 0, "
          "in the order the grains are given (a pack the free grains are carried through). A scene with held "
          "grains rests on them: along a periodic direction the fluid is held up by its hydrostatic pressure "
          "gradient alone, and a free grain feels its weight less its buoyancy. Empty: every grain moves.",
          ints_in(0, std::numeric_limits<int>::max()));
    s.set("Prescribed", Array<int>(),
          "Grains that keep their Initial Velocity and Initial Spin throughout, whatever the fluid and the "
          "contacts do (Grains/Motion = free): their indices, from 0 (a stirrer, a grain pulled through a pack). "
          "To a contact they are of infinite mass; a scene with prescribed grains rests on them, as on held "
          "grains (Grains/Held). Empty: none.",
          ints_in(0, std::numeric_limits<int>::max()));
    s.set("Initial Spin", Array<double>(),
          "Angular velocity of the moving grains at the start (rad/s): in 2D one value (about z) for every grain "
          "or one for each grain; in 3D three components for every grain, or three for each grain in turn. "
          "Empty: none.",
          reals_in(-kHuge, kHuge));
    s.set("Initial Velocity", Array<double>(),
          "Velocity of the moving grains at the start (m/s): one value per direction for every grain, or one "
          "per direction for each grain in turn (vx, vy, vx, vy, ...). Empty: at rest.",
          reals_in(-kHuge, kHuge));
    {
      auto& c = s.sublist("Contact", false,
                          "Contact between moving grains and of a grain with a channel wall (Grains/Motion = free): a "
                          "soft-sphere law, Hertz's normal force in 3D (cylinders pressed along a line in 2D) with "
                          "damping for the restitution and Coulomb friction, acting where the gap between two "
                          "surfaces closes below Cutoff Spacings (physics/ContactLaw.hpp, docs/method.md).");
      c.set("Young Modulus", 0.0,
            "Young's modulus of the grains' solid (Pa). The time step then resolves the shortest collision at the "
            "flow's velocity scale in 40 steps, which for a real solid can make it very small. 0: the modulus that "
            "makes that collision last 40 of the fluid's time steps (soft, and free of cost).",
            real_in(0.0, kHuge));
      c.set("Poisson Ratio", 0.3, "Poisson's ratio of the grains' solid.", real_in(0.0, 0.5));
      c.set("Restitution", 0.9,
            "Coefficient of restitution of a head-on collision (the speed after over the speed before, in the "
            "absence of fluid), in (0, 1]; the same at every speed of impact.",
            real_in(1e-6, 1.0));
      c.set("Friction", 0.3, "Coulomb friction coefficient of the contact (tangential force at most this times "
                             "the normal force).",
            real_in(0.0, 100.0));
      c.set("Cutoff Spacings", 1.0,
            "The gap between two surfaces, in particle spacings, below which they are in contact: no fluid "
            "particle fits there, and the lubrication force that would keep them apart is not resolved. 0: "
            "contact at touching.",
            real_in(0.0, 100.0));
    }
    auto& p = s.sublist("Random Pack", false,
                        "A random periodic pack of grains made at set-up (src/geometry/RandomPack.hpp: radii drawn "
                        "to the porosity, grains grown from random centres by collective rearrangement), the same "
                        "for the same seed. The grains used are written to grains_used.txt in the output "
                        "directory: Grains/File = that file (with Porosity = 0 here and Allow Overlap = true) "
                        "repeats the run. Not with Grains/File or Grains/Inline.");
    p.set("Porosity", 0.0, "Target porosity of the cell, met exactly (to 1e-6). 0: no pack.", real_in(0.0, 0.99));
    p.set("Radius Distribution", std::string("uniform"),
          "'uniform': radii uniform between Min Radius and Max Radius (equal for a monodisperse pack). "
          "'lognormal': ln r normal about ln(Median Radius) with Log Standard Deviation, truncated to "
          "[Min Radius, Max Radius]. All radii are then scaled by one factor (within about 1/(3N) of 1 for N "
          "grains) so that the porosity is met.",
          one_of({"uniform", "lognormal"}));
    p.set("Min Radius", 0.0, "Smallest radius drawn (m).", real_in(0.0, kHuge));
    p.set("Max Radius", 0.0, "Largest radius drawn (m).", real_in(0.0, kHuge));
    p.set("Median Radius", 0.0, "'lognormal': the median radius (m).", real_in(0.0, kHuge));
    p.set("Log Standard Deviation", 0.0, "'lognormal': the standard deviation of ln r.", real_in(0.0, 10.0));
    p.set("Minimum Gap", 1.0,
          "Narrowest open throat between two grains, in particle spacings (at least 1: the scene checks refuse "
          "a throat under one spacing, and warn under three). Grains closer than that are in contact.",
          real_in(1.0, 1000.0));
    p.set("Contacts", true,
          "Grains may touch, overlapping by at most min(Minimum Gap, 0.1 of the smaller radius), as the grains "
          "of a soil do; false: every pair keeps Minimum Gap, which limits how dense a pack can be.");
    p.set("Seed", 1, "Seed of the random draws (std::mt19937_64).", int_in(0, std::numeric_limits<int>::max()));
  }
  {
    auto& s = list->sublist("Image", false,
                            "A segmented image (a micro-CT volume, a thin section) as the solid, instead of Grains. "
                            "Voxel (i, j, k) covers [i, i+1) x [j, j+1) x [k, k+1) voxel sizes from the origin. Read "
                            "and checked before any work; the walls are placed on the surface found between the voxels, with the "
                            "grains' no-slip physics (docs/method.md).");
    s.set("File", std::string(""),
          "The image, by extension: .png (2D, 8 or 16-bit greyscale), .tif or .tiff (2D, or 3D as a stack of "
          "pages, page p at z = p; 8 or 16-bit greyscale), .raw (headerless, with Shape and Type). The first row "
          "of a PNG or TIFF page is at the largest y (y up, as displayed); a raw volume is x fastest, then y, "
          "then z; .h5 or .hdf5 (an integer dataset, Dataset, [y][x] or [z][y][x] as stored, x fastest, as a raw "
          "volume and as h5py writes a numpy array a[z, y, x]; uint8 or wider, labels 0 to 65535). A relative "
          "path is relative to the scene file's folder. Empty: no image.");
    s.set("Dataset", std::string(""),
          "REQUIRED for an HDF5 File (.h5, .hdf5), and only for one: the dataset's path inside the file, e.g. "
          "'/segmented'.");
    s.set("Shape", Array<int>(),
          "Voxels per direction, {nx, ny} (2D) or {nx, ny, nz} (3D): REQUIRED for .raw, checked against the "
          "file's size; for .png and .tif, checked against the image when given.",
          ints_in(1, std::numeric_limits<int>::max()));
    s.set("Type", std::string("uint8"), "Value type of a .raw file: 'uint8', or 'uint16' (little-endian).",
          one_of({"uint8", "uint16"}));
    s.set("Solid Values", Array<int>(),
          "REQUIRED with File. The voxel values that are solid; every other value is pore.", ints_in(0, 65535));
    s.set("Voxel Size", 0.0,
          "REQUIRED with File. Side of a voxel (m). Domain/Cell Size must equal the image's extent (voxels "
          "times this, after Mirror) to 1e-9 relative.",
          real_in(0.0, kHuge));
    s.set("Mirror", false,
          "Follow the image by its mirror image along the driven axis (that of Fluid/Body Force), so that a "
          "sample whose two faces do not match becomes periodic along the flow, as users of LBM codes do; the "
          "cell is then twice the image along that axis. Not with Permeability/Tensor.");
  }
  {
    auto& s = list->sublist("Permeability", false,
                            "Darcy permeability k_ij = nu <u_i> / F_j, <u> the superficial velocity.");
    s.set("Tensor", false,
          "Drive each direction the cell is periodic in with |Fluid/Body Force|, in turn, and report the full "
          "tensor (no flow crosses a channel's walls: their axis is not driven); otherwise drive along the body "
          "force (which must lie along one axis) and report that column.");
    s.set("Steady Tolerance", 0.0,
          "Stop once k is steady to this relative tolerance: its change over the last span and the change "
          "still to come, predicted from the exponential approach of three values a span apart, are both "
          "below it. The span is the larger of Steady Window and the flow's spin-up time k / (nu porosity). "
          "0 = run to End Time.",
          real_in(0.0, 1.0));
    s.set("Linearity Check", false,
          "Repeat the finest level at half the body force, starting from its end, and report darcy_linearity, "
          "the relative change of each k component: above 1 % a warning says the flow is not in the Darcy "
          "regime.");
    s.set("Steady Window", 0.0,
          "Shortest span (s) of the steady-state test; the flow's spin-up time k / (nu porosity) sets it when "
          "longer. 0: the spin-up time alone.",
          real_in(0.0, kHuge));
  }
  {
    auto& s = list->sublist("Convergence", false,
                            "A resolution ladder: the run goes through several spacings, coarse to fine, each "
                            "level starting from the one before, and reports k with its uncertainty from the grid "
                            "convergence index (docs/method.md).");
    s.set("Levels", 1,
          "Number of levels; the finest has Discretization/Particle Spacing (or Spacings Across Throat), each "
          "coarser one Refinement Ratio times the next. 1: one resolution.",
          int_in(1, 10));
    s.set("Refinement Ratio", 2.0,
          "Spacing of a level over that of the next finer one (> 1; rounded so that the cell holds whole "
          "numbers of spacings).",
          real_in(1.05, 10.0));
  }
  {
    auto& s = list->sublist("Run", false, "How long to run.");
    s.set("End Time", 0.0, "REQUIRED. Simulated time to reach (s).", real_in(0.0, kHuge));
    s.set("Max Steps", 0, "Stop after this many steps at the latest; 0 = no limit.", int_in(0, 1 << 30));
    s.set("Backend", std::string("default"),
          "Kokkos execution space of the kernels: 'serial', 'openmp' (a Kokkos built with OpenMP: "
          "scripts/build-trilinos-openmp.sh) or 'default' (OpenMP where the build has it, else Serial).",
          one_of({"default", "serial", "openmp"}));
    s.set("Threads", 0, "Threads per process for the OpenMP backend; 0 = Kokkos's default (OMP_NUM_THREADS).",
          int_in(0, 1024));
    s.set("Memory Limit", 0.0,
          "Memory (GB) the run's processes may use on one machine. Before allocating anything, the particle "
          "count (every lattice point), the gridded view and the memory they need are estimated, and a run "
          "that would not fit is refused, naming both. 0: the memory the machine has available "
          "(MemAvailable in /proc/meminfo).",
          real_in(0.0, kHuge));
    s.set("Progress", std::string("auto"),
          "Progress line (step, time, % done, ETA): 'auto' = only on a terminal and not under mpiexec, "
          "'always', 'never'.",
          one_of({"auto", "always", "never"}));
  }
  {
    auto& s = list->sublist("Solver", false,
                            "How the steady state is found (docs/steady_solver.md).");
    s.set("Method", std::string("explicit"),
          "'explicit': march the equations in time (pseudo-time for fixed particles) until k is steady or "
          "Run/End Time; transients and moving particles need it. 'steady': fixed particles only; solve for the "
          "state whose rates are zero (up to the uniform density drift a wall makes) by Newton's method, each "
          "step by flexible GMRES with a block (LSC) preconditioner, with the time loop's own operators: the same "
          "discrete answer without pseudo-time. Run/End Time and Run/Max Steps do not apply to it, nor the "
          "channel's start-up profiles (profiles.csv, profile_error: a transient).",
          one_of({"explicit", "steady"}));
    s.set("Tolerance", 1e-4,
          "'steady': converged when the residual of the steady equations, the uniform density drift removed, "
          "is below this fraction of its size at rest (v = 0, rho = rho0). k then differs from a solve to "
          "1e-6 by far less than from the march's (docs/steady_solver.md, \"The default tolerance\").",
          real_in(1e-14, 0.5));
    s.set("Permeability Tolerance", 1e-3,
          "'steady': converged only when, besides the residual, the last Newton step moved the superficial "
          "velocity (so k) by less than this fraction of itself. On an image whose passages are one particle "
          "wide, a residual below Tolerance can leave k a quarter off: the pressure modes the SPH gradient "
          "hardly sees carry k and hardly show in the residual (docs/steady_solver.md, 'k settled').",
          real_in(1e-14, 0.5));
    s.set("Linear Tolerance", 1e-8,
          "'steady': the least relative residual a Newton step's linear solve is asked for (each step asks for "
          "what takes the residual to a tenth of Tolerance, were the equations linear).",
          real_in(1e-14, 0.5));
    s.set("Max Nonlinear Iterations", 10, "'steady': Newton steps at most.", int_in(1, 1000));
    s.set("Max Linear Iterations", 1000,
          "'steady': outer GMRES iterations per Newton step at most. A solve that does not converge within "
          "them ends with a warning, exit status 4 and its last state in the final checkpoint.",
          int_in(1, 1 << 20));
    s.set("Krylov Restart", 30,
          "'steady': restart length of the outer GMRES, the one each Newton step is solved by (vectors kept; "
          "memory grows with it, as far as the iterations reach). Where a linear solve stalls with nothing inner "
          "left to make more exact (or with the DG solves on blocks, DG Preconditioner), its cycles are made 4 "
          "times longer, up to 16 times this, if their vectors fit in a quarter of the free memory "
          "(docs/steady_solver.md, 'Longer outer cycles').",
          int_in(2, 1000));
    s.set("Inner Krylov Restart", 30,
          "'steady': restart length of the preconditioner's inner GMRES solves (at most Max Inner Iterations).",
          int_in(2, 1000));
    s.set("Inner Tolerance", 0.0,
          "'steady': relative tolerance of the preconditioner's inner solves (the pressure operator DG and the "
          "velocity block). 0 = by the dimension: 0.05 in 2D, 0.01 in 3D (docs/steady_solver.md, 'The inner "
          "tolerance by the dimension'). A Newton step taken only to settle k asks for 0.01 at most, and a looser "
          "tolerance is divided by 5 (not below 0.01) whenever a linear solve has not halved its residual over "
          "Krylov Restart iterations while most of its DG solves ended by the tolerance, not at the cap (see "
          "Raised Inner Iterations).",
          real_in(0, 0.9));
    s.set("Max Inner Iterations", 100,
          "'steady': iterations of each inner solve at most, to start with (see Raised Inner Iterations). An "
          "image whose passages are one or two particles wide can need 1000 (docs/steady_solver.md, 'What fails "
          "on a blobs image'); an unconverged solve's warning says when its inner solves came near it.",
          int_in(1, 1 << 20));
    s.set("Raised Inner Iterations", 1600,
          "'steady': what Max Inner Iterations is raised to at most, 4 times at a time, when a linear solve has "
          "not halved its residual over Krylov Restart iterations while most of its DG solves ended at the cap. "
          "At or below Max Inner Iterations: never raised.",
          int_in(1, 1 << 20));
    s.set("DG Preconditioner", std::string("auto"),
          "'steady': what preconditions the inner solves of the pressure operator DG. 'lattice': a cycle of the "
          "wide lattice Laplacian. 'schwarz' (2D only): exact solves on blocks of 8 x 8 lattice points extended by 2 "
          "a side, with a coarse level of one unknown per block's connected part; a set-up of 729 or more products "
          "of DG, and up to 2.6 kB a fluid particle more. 'auto': 'lattice', switched to 'schwarz' in 2D where the "
          "lattice cycle's DG solves stall at their cap (instead of raising it; see Raised Inner Iterations). "
          "Measured: on the grain scenes of input/ auto never switches; on three 2D blobs images it took 0.02 to "
          "0.6 of the lattice's time and schwarz alone 0.003 to 0.17; where passages are one particle wide, auto "
          "converges once the outer cycles are lengthened (Krylov Restart), in minutes (docs/steady_solver.md, "
          "'Local solves for DG', 'Longer outer cycles').",
          one_of({"lattice", "schwarz", "auto"}));
  }
  {
    auto& s = list->sublist("Parallel", false, "How the cell is divided among MPI processes.");
    s.set("Decomposition", std::string("rcb"),
          "'rcb': Zoltan2 recursive coordinate bisection weighted by the particles each box will hold; "
          "'grid': the paper's Cartesian process grid. A scene of an Image is always divided by the grid: each "
          "process reads the piece of the image its box needs (docs/method.md).",
          one_of({"rcb", "grid"}));
    s.set("Process Grid", Array<int>(),
          "'grid': processes per direction (their product is the number of ranks). Empty: the factorisation "
          "whose boxes are closest to cubes.",
          ints_in(1, 1 << 20));
    s.set("X Cuts", Array<double>(),
          "'grid': sub-cell boundaries along x from 0 to L_x (the paper's adjusted boundaries). Empty: equal.",
          reals_in(0.0, kHuge));
    s.set("Y Cuts", Array<double>(), "As X Cuts, along y.", reals_in(0.0, kHuge));
    s.set("Z Cuts", Array<double>(), "As X Cuts, along z.", reals_in(0.0, kHuge));
    s.set("Rebalance Threshold", 0.0,
          "Moving particles on 2 or more processes, 'rcb': every Rebalance Interval steps the time each process "
          "spent working (its steps' wall time less its time in collective operations) is compared; when the slowest "
          "process's time over the mean passes this, Zoltan2 divides the cell anew with each particle weighted "
          "by its process's measured time per particle, and particles move to their new owners. So a process "
          "that is slower (a shared core) gets less. A division waits until the time the slowest process lost past "
          "the threshold since the last division (its excess over the mean) reaches what the last division cost "
          "(measured; the first divides at once). 0: never; otherwise at least 1. balance_history.csv "
          "records the time per step, the imbalance and both times either way.",
          real_in(0.0, kHuge));
    s.set("Rebalance Interval", 100, "Steps between the measurements of the balance (Rebalance Threshold).",
          int_in(1, std::numeric_limits<int>::max()));
  }
  {
    auto& s = list->sublist("Output", false, "What a run writes besides summary.json.");
    s.set("Final Particles CSV", false,
          "Write particles.csv of the final state (id, kind, position, velocity, density, pressure); "
          "perf/plot_velocity.py draws it.");
    s.set("Field Interval", 0.0,
          "Simulated time (s) between HDF5 field files (fields_NNNNNN.h5, described for ParaView by "
          "particles.xmf and grid.xmf); the initial and final states are written too. 0: no field files.",
          real_in(0.0, kHuge));
    s.set("Fields", std::string("velocity density pressure kind grain id"),
          "Particle fields in each field file, separated by spaces or commas, out of: velocity density "
          "pressure kind grain id phase (with Phases/Count = 2: a fluid particle's phase, 0 or 1; -1 for "
          "boundary particles) colour (with Phases/Interface = moving: its phase field phi, 0 at boundary "
          "particles). Positions are always written.");
    s.set("Grid Points", Array<int>(),
          "Points per direction of a regular grid of the cell on which the SPH-interpolated velocity and "
          "pressure are written with each field file (ParaView shows it as an image). Empty: no grid.",
          ints_in(1, 1 << 20));
    s.set("Checkpoint Interval", 0,
          "Steps between checkpoints (checkpoint.h5, the state `poresph SCENE.xml --restart` continues from). "
          "0: only the final one.",
          int_in(0, std::numeric_limits<int>::max()));
    s.set("Final Checkpoint", true, "Write checkpoint.h5 at the end of the run.");
  }
  {
    auto& s = list->sublist("Checks", false, "Conditions that stop a run, with a checkpoint of the last good state.");
    s.set("Density Variation Limit", 0.1,
          "Largest |rho/rho0 - 1| of a fluid particle before the run stops; NaN or Inf in any field and a "
          "particle outrunning the time step's CFL limits always stop it.",
          real_in(1e-6, kHuge));
  }
  {
    auto& s = list->sublist("Diagnostics", false, "Checks against known solutions.");
    s.set("Profile Sample Times", Array<double>(),
          "Channel scenes: times (s) at which v_x is compared with the start-up series solution; the end "
          "of the run is always compared too.",
          reals_in(0.0, kHuge));
  }
  return list;
}

std::vector<std::string> split_path(const std::string& path) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(path);
  while (std::getline(in, part, '/')) parts.push_back(part);
  return parts;
}

// Edit distance, for "did you mean" on a misspelt name.
size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t above = row[j];
      const bool same = std::tolower(static_cast<unsigned char>(a[i - 1])) ==
                        std::tolower(static_cast<unsigned char>(b[j - 1]));
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (same ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// "; did you mean 'Kinematic Viscosity'?" when a valid name of the group is
// within a few edits of `name`; otherwise the group's names.
std::string suggestion(const ParameterList& valid, const std::string& name) {
  std::string best, names;
  size_t best_distance = 4;  // more edits than this is another word, not a typo
  for (auto it = valid.begin(); it != valid.end(); ++it) {
    const std::string& candidate = valid.name(it);
    names += (names.empty() ? "" : ", ") + candidate;
    if (candidate == name) continue;  // the name itself is no suggestion (a value given for a group, say)
    const size_t d = edit_distance(name, candidate);
    if (d < best_distance) best_distance = d, best = candidate;
  }
  if (!best.empty()) return "; did you mean '" + best + "'?";
  return "; the group holds: " + names;
}

// Sets `name` in `target` from its text, as the type of the valid entry:
// the one way a value is read, from the scene's XML and from --set alike.
// `where` says where the text came from, for the message.
void set_from_text(ParameterList& target, const Teuchos::ParameterEntry& expected, const std::string& name,
                   const std::string& text, const std::string& where) {
  auto take = [&](auto parsed) {
    if (!parsed.value) throw ParameterError(where + ": '" + text + "' " + parsed.problem);
    return *parsed.value;
  };
  if (expected.isType<double>()) target.set(name, take(parse_number<double>(text)));
  else if (expected.isType<int>()) target.set(name, take(parse_number<int>(text)));
  else if (expected.isType<std::string>()) target.set(name, text);
  else if (expected.isType<bool>()) target.set(name, take(parse_bool(text)));
  else if (expected.isType<Array<double>>()) target.set(name, Array<double>(take(parse_array<double>(text))));
  else if (expected.isType<Array<int>>()) target.set(name, Array<int>(take(parse_array<int>(text))));
  else throw ParameterError(where + ": this parameter cannot be given as text");
}

// Teuchos's XML reader takes "0.005abc" as 0.005 and lets a second
// <Parameter> of the same name replace the first without a word. So the
// scene's XML is walked here instead: each value goes through
// set_from_text, as --set does, and a name given twice in one list is
// refused. What Teuchos writes besides (validators, dependencies, and
// attributes such as docString or isUsed in parameters_used.xml) is ignored.
void read_xml_list(const Teuchos::XMLObject& xml, const ParameterList& valid, ParameterList& target,
                   const std::string& path, const std::string& file) {
  std::set<std::string> seen;
  for (int k = 0; k < xml.numChildren(); ++k) {
    const Teuchos::XMLObject& child = xml.getChild(k);
    const std::string& tag = child.getTag();
    if (path.empty() && (tag == "Validators" || tag == "Dependencies")) continue;
    const std::string group = path.empty() ? "at the top level" : "in group " + path.substr(0, path.size() - 1);
    if (tag != "ParameterList" && tag != "Parameter")
      throw ParameterError(file + ": unexpected <" + tag + "> " + group +
                           " (a scene holds <ParameterList> and <Parameter> elements)");
    if (!child.hasAttribute("name"))
      throw ParameterError(file + ": a <" + tag + "> " + group + " has no name");
    const std::string& name = child.getAttribute("name");
    const std::string full = path + name;
    if (!seen.insert(name).second)
      throw ParameterError(file + ": " + full + " is given twice " + group +
                           "; remove one (which of them should count is not for PoreSPH to guess)");
    if (tag == "ParameterList") {
      if (valid.isParameter(name) && !valid.isSublist(name))
        throw ParameterError(file + ": " + full + " is a parameter, not a group of them: write it as <Parameter name=\"" +
                             name + "\" type=\"" + valid.getEntry(name).getAny().typeName() + "\" value=\"...\"/>");
      if (!valid.isSublist(name))
        throw ParameterError(file + ": there is no parameter group '" + full + "'" + suggestion(valid, name) +
                             " (see poresph --help-parameters)");
      read_xml_list(child, valid.sublist(name), target.sublist(name), full + "/", file);
      continue;
    }
    if (valid.isSublist(name))
      throw ParameterError(file + ": " + full + " is a group of parameters, not a value: write it as <ParameterList "
                           "name=\"" + name + "\"> holding its <Parameter> elements (see poresph --help-parameters)");
    if (!valid.isParameter(name))
      throw ParameterError(file + ": unknown parameter " + full + suggestion(valid, name) +
                           " (see poresph --help-parameters)");
    const auto& expected = valid.getEntry(name);
    const std::string expected_type = expected.getAny().typeName();
    if (!child.hasAttribute("type") || !child.hasAttribute("value"))
      throw ParameterError(file + ": parameter " + full + " needs a type and a value (type=\"" + expected_type +
                           "\")");
    const std::string& type = child.getAttribute("type");
    if (type != expected_type)
      throw ParameterError(file + ": parameter " + full + " has type " + type + ", expected " + expected_type);
    set_from_text(target, expected, name, child.getAttribute("value"), file + ": " + full);
  }
}

bool has_value(const ParameterList& list, const std::string& sublist, const std::string& name) {
  return list.isSublist(sublist) && list.sublist(sublist).isParameter(name);
}

// Teuchos's number validators try to read a string entry as a number and
// fail with a bare "stod": check every known entry's type ourselves first.
void check_types(const ParameterList& list, const ParameterList& valid, const std::string& path) {
  for (auto it = list.begin(); it != list.end(); ++it) {
    const std::string& name = list.name(it);
    if (!valid.isParameter(name)) continue;  // unknown names: Teuchos names them with the valid list
    const auto& entry = list.entry(it);
    const auto& expected = valid.getEntry(name);
    if (entry.isList() && expected.isList()) {
      check_types(list.sublist(name), valid.sublist(name), path + name + "/");
    } else if (entry.isList() != expected.isList() || entry.getAny().type() != expected.getAny().type()) {
      throw ParameterError("parameter " + path + name + " has type " +
                           (entry.isList() ? std::string("ParameterList") : entry.getAny().typeName()) +
                           ", expected " +
                           (expected.isList() ? std::string("ParameterList") : expected.getAny().typeName()));
    }
  }
}

// "at least 0", "between 1e-06 and 0.5": a validator's range in words; the
// largest numbers stand for no bound.
template <class T>
std::string range_text(T lo, T hi) {
  constexpr T most = std::numeric_limits<T>::max();
  std::ostringstream out;
  out << std::setprecision(10);
  const bool bounded_below = lo > -most, bounded_above = hi < most;
  if (bounded_below && bounded_above) out << "between " << lo << " and " << hi;
  else if (bounded_below) out << "at least " << lo;
  else if (bounded_above) out << "at most " << hi;
  return out.str();
}

// Each value against its validator's range or words, with a message in the
// scene's terms (Teuchos's own says the same after lines of its source
// paths). What Teuchos validates besides is left to it.
void check_ranges(const ParameterList& list, const ParameterList& valid, const std::string& path) {
  for (auto it = list.begin(); it != list.end(); ++it) {
    const std::string& name = list.name(it);
    if (!valid.isParameter(name)) continue;
    const std::string full = path + name;
    if (valid.isSublist(name)) {
      if (list.isSublist(name)) check_ranges(list.sublist(name), valid.sublist(name), full + "/");
      continue;
    }
    const auto validator = valid.getEntry(name).validator();
    if (validator.is_null()) continue;
    // what: "" for the value itself, "element 2" for one of an array.
    auto refuse = [&](const std::string& what, const std::string& value, const std::string& range) {
      throw ParameterError(full + (what.empty() ? "" : ": " + what) + " = " + value + " is out of range: it must be " +
                           range);
    };
    auto number = [](auto v) {
      std::ostringstream out;
      out << std::setprecision(10) << v;
      return out.str();
    };
    auto check = [&](auto value, const auto& numbers, const std::string& what) {
      if (value < numbers.getMin() || value > numbers.getMax())
        refuse(what, number(value), range_text(numbers.getMin(), numbers.getMax()));
    };
    using Teuchos::rcp_dynamic_cast;
    if (const auto v = rcp_dynamic_cast<const Teuchos::EnhancedNumberValidator<double>>(validator); !v.is_null()) {
      check(list.get<double>(name), *v, "");
    } else if (const auto i = rcp_dynamic_cast<const Teuchos::EnhancedNumberValidator<int>>(validator); !i.is_null()) {
      check(list.get<int>(name), *i, "");
    } else if (const auto a = rcp_dynamic_cast<const Teuchos::ArrayNumberValidator<double>>(validator); !a.is_null()) {
      const auto values = list.get<Array<double>>(name);
      for (Teuchos::Ordinal k = 0; k < values.size(); ++k)
        check(values[k], *a->getPrototype(), "element " + std::to_string(k + 1));
    } else if (const auto b = rcp_dynamic_cast<const Teuchos::ArrayNumberValidator<int>>(validator); !b.is_null()) {
      const auto values = list.get<Array<int>>(name);
      for (Teuchos::Ordinal k = 0; k < values.size(); ++k)
        check(values[k], *b->getPrototype(), "element " + std::to_string(k + 1));
    } else if (const auto w = rcp_dynamic_cast<const Teuchos::StringValidator>(validator); !w.is_null()) {
      const auto& words = *w->validStringValues();
      const std::string value = list.get<std::string>(name);
      if (std::find(words.begin(), words.end(), value) != words.end()) continue;
      std::string listed, nearest;
      size_t nearest_distance = 3;
      for (const auto& word : words) {
        listed += (listed.empty() ? "'" : ", '") + word + "'";
        if (const size_t d = edit_distance(value, word); d < nearest_distance) nearest_distance = d, nearest = word;
      }
      throw ParameterError(full + ": '" + value + "' is not one of its values, " + listed +
                           (nearest.empty() ? "" : "; did you mean '" + nearest + "'?"));
    }
  }
}

}  // namespace

RCP<const ParameterList> valid_parameters() {
  static const RCP<const ParameterList> list = make_valid_parameters();
  return list;
}

void print_valid_parameters(std::ostream& os) {
  os << "PoreSPH scene parameters (XML: <ParameterList name=\"...\"> with one sublist per group).\n"
        "Each line: name : type = default, then its documentation and valid values.\n\n";
  valid_parameters()->print(os, ParameterList::PrintOptions().showTypes(true).showDoc(true).indent(2));
}

std::string apply_override(ParameterList& list, const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw ParameterError("--set expects \"Sublist/Parameter Name=value\", got '" + assignment + "'");
  const std::string path = assignment.substr(0, eq), text = assignment.substr(eq + 1);
  const auto parts = split_path(path);
  const ParameterList* valid = valid_parameters().get();
  ParameterList* target = &list;
  for (size_t k = 0; k + 1 < parts.size(); ++k) {
    if (valid->isParameter(parts[k]) && !valid->isSublist(parts[k]))
      throw ParameterError("--set " + path + ": '" + parts[k] + "' is a parameter, not a group of them");
    if (!valid->isSublist(parts[k]))
      throw ParameterError("--set " + path + ": there is no parameter group '" + parts[k] + "'" +
                           suggestion(*valid, parts[k]) + " (see poresph --help-parameters)");
    valid = &valid->sublist(parts[k]);
    target = &target->sublist(parts[k]);
  }
  const std::string& name = parts.empty() ? path : parts.back();
  if (!parts.empty() && valid->isSublist(name))
    throw ParameterError("--set " + path + ": '" + name + "' is a group of parameters, not a value: give one of "
                         "them, as --set \"" + path + "/Parameter Name=value\" (see poresph --help-parameters)");
  if (parts.size() < 2 || !valid->isParameter(name))
    throw ParameterError("--set " + path + ": unknown parameter" + suggestion(*valid, name) +
                         " (see poresph --help-parameters)");
  // What is written back (parameters_used.xml, summary.json) is UTF-8, as the scene's XML is.
  for (size_t k = 0; k < text.size();) {
    const size_t n = xml_text_detail::utf8_length(text, k);
    if (n == 0)
      throw ParameterError("--set " + path + ": the value holds the byte " +
                           xml_text_detail::hex_byte(static_cast<unsigned char>(text[k])) +
                           ", which is not UTF-8: give it in UTF-8 (the terminal's encoding is another)");
    k += n;
  }
  set_from_text(*target, valid->getEntry(name), name, text, "--set " + path);
  return path;
}

void validate_parameters(ParameterList& list) {
  // Names, types and ranges first, so that a misspelt required parameter is
  // reported as the unknown name it is, with the valid names beside it.
  check_types(list, *valid_parameters(), "");
  check_ranges(list, *valid_parameters(), "");
  try {
    list.validateParameters(*valid_parameters());
  } catch (const std::exception& e) {
    throw ParameterError(std::string("invalid scene parameters: ") + teuchos_message(e.what()));
  }
  // Teuchos has no notion of a required parameter.
  const std::pair<const char*, const char*> required[] = {{"Domain", "Cell Size"},
                                                          {"Fluid", "Kinematic Viscosity"},
                                                          {"Run", "End Time"}};
  for (const auto& [group, name] : required)
    if (!has_value(list, group, name))
      throw ParameterError(std::string("missing required parameter ") + group + "/" + name +
                           " (see poresph --help-parameters)");
  // The spacing, given or from the narrowest throat: exactly one of them.
  const bool spacing = has_value(list, "Discretization", "Particle Spacing"),
             across = has_value(list, "Discretization", "Spacings Across Throat");
  if (!spacing && !across)
    throw ParameterError("missing required parameter Discretization/Particle Spacing (or Discretization/Spacings "
                         "Across Throat; see poresph --help-parameters)");
  list.validateParametersAndSetDefaults(*valid_parameters());
}

RCP<ParameterList> read_parameters(const std::string& xml_file, const std::vector<std::string>& overrides) {
  const std::string cannot = "cannot read scene file '" + xml_file + "': ";
  if (const std::string problem = regular_file_problem(xml_file, "an XML file"); !problem.empty())
    throw ParameterError(cannot + problem);
  std::ifstream in(xml_file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  if (!in) throw ParameterError(cannot + std::strerror(errno));
  if (trimmed(text.str()).empty()) throw ParameterError(cannot + "the file is empty");
  std::string xml_text;
  try {
    xml_text = xml_text_for_parser(text.str());
  } catch (const std::invalid_argument& e) {
    throw ParameterError(cannot + e.what());
  }
  Teuchos::XMLObject xml;
  try {
    xml = Teuchos::StringInputSource(xml_text).getObject();
  } catch (const std::exception& e) {
    throw ParameterError(cannot + "it is not well-formed XML: " + teuchos_message(e.what()));
  }
  if (xml.getTag() != "ParameterList")
    throw ParameterError(cannot + "its top element is <" + xml.getTag() + ">, not <ParameterList>");
  auto list = rcp(new ParameterList(xml.hasAttribute("name") ? xml.getAttribute("name") : "PoreSPH"));
  read_xml_list(xml, *valid_parameters(), *list, "", xml_file);
  // As in the XML, a parameter given twice is refused: which of them was meant is not for PoreSPH to guess.
  std::map<std::string, std::string> given;
  for (const auto& assignment : overrides) {
    const std::string path = apply_override(*list, assignment);
    const auto [earlier, first] = given.emplace(path, assignment);
    if (!first)
      throw ParameterError("--set " + path + " is given twice ('" + earlier->second + "' and '" + assignment +
                           "'); remove one (which of them should count is not for PoreSPH to guess)");
  }
  validate_parameters(*list);
  return list;
}

std::string parameters_to_xml(const ParameterList& list) {
  std::ostringstream out;
  Teuchos::writeParameterListToXmlOStream(list, out);
  return out.str();
}

void write_parameters_xml(const ParameterList& list, const std::string& file) {
  Teuchos::writeParameterListToXmlFile(list, file);
}

}  // namespace poresph
