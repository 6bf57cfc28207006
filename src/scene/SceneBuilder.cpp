#include "scene/SceneBuilder.hpp"

#include <Teuchos_Array.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

#include "geometry/Grains.hpp"
#include "geometry/RandomPack.hpp"
#include "geometry/Solid.hpp"
#include "io/Parameters.hpp"
#include "scene/Drainage.hpp"
#include "scene/ImageScene.hpp"

namespace poresph {
namespace {

using Teuchos::Array;
using Teuchos::ParameterList;

// "a", "a and b", "a, b and c".
std::string list_of(const std::vector<std::string>& names) {
  std::string text;
  for (size_t k = 0; k < names.size(); ++k) text += (k ? (k + 1 == names.size() ? " and " : ", ") : "") + names[k];
  return text;
}

// What the scene asks to measure must be measurable: k needs a body force,
// along one axis unless Permeability/Tensor drives each axis in turn, and an
// axis the cell is open along. Asked of a scene that cannot give it, it used
// to be skipped without a word (no k, no history, a steady tolerance
// ignored, a ladder of nothing).
void check_measurement(const SceneConfig& scene) {
  int components = 0;
  double magnitude = 0;
  std::ostringstream force;
  force << std::setprecision(10) << "(";
  for (int d = 0; d < scene.dimension; ++d) {
    components += scene.body_force[d] != 0;
    magnitude += scene.body_force[d] * scene.body_force[d];
    force << (d ? ", " : "") << scene.body_force[d];
  }
  force << ")";
  magnitude = std::sqrt(magnitude);
  if (!std::isfinite(magnitude)) return;  // named as such by the scene check (app/SceneCheck.cpp)
  if (components > 1 && !scene.permeability_tensor) {
    std::ostringstream msg;
    msg << std::setprecision(10) << "Fluid/Body Force = " << force.str()
        << " does not lie along one axis: k is measured along the one axis the force drives. Put the force along "
           "an axis, or set Permeability/Tensor = true to drive each axis in turn with its magnitude "
        << magnitude << " and measure the whole tensor";
    throw ParameterError(msg.str());
  }
  std::vector<std::string> asked;
  if (components == 1 && !scene.permeability_tensor) {
    // Walls that close the cell along the driven axis pass no flow along it:
    // k there is zero by construction, and a run measuring it would chase a
    // relative change of nothing (a march never steady, a solve never settled).
    const int axis = force_axis(scene);
    if (scene.periodic[axis]) return;
    if (scene.steady_tolerance > 0) asked.push_back("Permeability/Steady Tolerance");
    if (scene.linearity_check) asked.push_back("Permeability/Linearity Check");
    if (scene.convergence_levels > 1) asked.push_back("Convergence/Levels");
    if (scene.steady_solver) asked.push_back("Solver/Method = steady");
    if (asked.empty()) return;
    throw ParameterError(std::string("Fluid/Body Force = ") + force.str() + " drives along " + "xyz"[axis] +
                         ", where the channel's walls close the cell: no flow crosses them, so k along " +
                         "xyz"[axis] + " is zero and " + list_of(asked) + " cannot measure it. Drive along an axis " +
                         "the cell is periodic in");
  }
  if (components > 0) return;
  if (scene.permeability_tensor) asked.push_back("Permeability/Tensor");
  if (scene.steady_tolerance > 0) asked.push_back("Permeability/Steady Tolerance");
  if (scene.steady_window > 0) asked.push_back("Permeability/Steady Window");
  if (scene.linearity_check) asked.push_back("Permeability/Linearity Check");
  if (scene.convergence_levels > 1) asked.push_back("Convergence/Levels");
  if (asked.empty()) return;
  throw ParameterError(list_of(asked) + (asked.size() > 1 ? " ask" : " asks") +
                       " for the permeability, which a body force measures, and Fluid/Body Force is zero here: give "
                       "one (along the axis to measure), or leave " +
                       (asked.size() > 1 ? "them" : "it") + " at the default");
}

// Discretization/Spacings Across Throat = n: the narrowest pore (an open
// throat between grains, an image's bottleneck) divided by n, rounded down
// to the largest spacing that fits every cell side a whole number of times
// (searched up to twice the count).
double spacing_across_throat(const SceneConfig& scene, double n) {
  const double gap = narrowest_pore(scene);
  if (!(gap > 0))
    throw ParameterError("Discretization/Spacings Across Throat needs a pore throat (between grains, or an image's "
                         "bottleneck), and this scene has none (no solid, or no open gap): give "
                         "Discretization/Particle Spacing");
  const long long first = static_cast<long long>(std::ceil(scene.cell_size[0] * n / gap - 1e-9));
  for (long long count = std::max(1LL, first); count <= 2 * first + 2; ++count) {
    const double dx = scene.cell_size[0] / count;
    bool fits = true;
    for (int d = 1; d < scene.dimension; ++d) {
      const double along = scene.cell_size[d] / dx;
      fits = fits && std::abs(along - std::round(along)) <= 1e-6 * along;
    }
    if (fits) return dx;
  }
  std::ostringstream msg;
  msg << "Discretization/Spacings Across Throat = " << n << ": no spacing near " << gap / n
      << " (the narrowest throat, " << gap << " wide, over " << n << ") fits every side of Domain/Cell Size a "
      << "whole number of times; give Discretization/Particle Spacing";
  throw ParameterError(msg.str());
}

// Grains/Motion, Density and Gravity: moving grains are rigid bodies in a
// moving fluid (physics/RigidGrains.hpp).
void read_grain_motion(const ParameterList& grains, SceneConfig& scene) {
  const auto motion = grains.get<std::string>("Motion");
  scene.grain_motion = motion == "free" ? GrainMotion::Free : motion == "rotating" ? GrainMotion::Rotating
                                                                                   : GrainMotion::Fixed;
  scene.grain_density = grains.get<double>("Density");
  const auto gravity = grains.get<Array<double>>("Gravity");
  const int dim = scene.dimension;
  if (!gravity.empty() && static_cast<int>(gravity.size()) != dim)
    throw ParameterError("Grains/Gravity must have one value per direction (" + std::to_string(dim) + ")");
  for (int d = 0; d < static_cast<int>(gravity.size()); ++d) scene.gravity[d] = gravity[d];
  const bool has_gravity = scene.gravity[0] != 0 || scene.gravity[1] != 0 || scene.gravity[2] != 0;
  const auto velocity = grains.get<Array<double>>("Initial Velocity");
  scene.grain_velocity.assign(velocity.begin(), velocity.end());
  const bool has_velocity = std::any_of(velocity.begin(), velocity.end(), [](double v) { return v != 0; });
  const auto spin = grains.get<Array<double>>("Initial Spin");
  scene.grain_spin.assign(spin.begin(), spin.end());
  const bool has_spin = std::any_of(spin.begin(), spin.end(), [](double w) { return w != 0; });
  const auto prescribed = grains.get<Array<int>>("Prescribed");
  const auto& contact = grains.sublist("Contact");
  scene.grain_contact.young_modulus = contact.get<double>("Young Modulus");
  scene.grain_contact.poisson_ratio = contact.get<double>("Poisson Ratio");
  scene.grain_contact.restitution = contact.get<double>("Restitution");
  scene.grain_contact.friction = contact.get<double>("Friction");
  scene.grain_contact.cutoff_spacings = contact.get<double>("Cutoff Spacings");
  if (scene.grain_motion == GrainMotion::Fixed) {
    if (has_gravity)
      throw ParameterError("Grains/Gravity acts on moving grains: with Grains/Motion = fixed it would do nothing; "
                           "drive the fluid with Fluid/Body Force");
    if (has_velocity || has_spin)
      throw ParameterError(std::string("Grains/Initial ") + (has_velocity ? "Velocity" : "Spin") +
                           " sets moving grains going: with Grains/Motion = fixed the grains hold still");
    if (!grains.get<Array<int>>("Held").empty())
      throw ParameterError("Grains/Held names grains that hold still while the others move: with Grains/Motion "
                           "= fixed they all hold still");
    if (!prescribed.empty())
      throw ParameterError("Grains/Prescribed names grains that keep their initial velocity and spin: with "
                           "Grains/Motion = fixed they all hold still (set Grains/Motion = free)");
    if (scene.grain_densities_given())
      scene.warnings.push_back("Grains/File gives each grain a density, which grains that hold still "
                               "(Grains/Motion = fixed) do not use");
    return;
  }
  if (has_velocity && scene.grain_motion != GrainMotion::Free)
    throw ParameterError("Grains/Initial Velocity moves the grains' centres: with Grains/Motion = " + motion +
                         " they are held (set Grains/Motion = free)");
  if (!prescribed.empty() && scene.grain_motion != GrainMotion::Free)
    throw ParameterError("Grains/Prescribed moves grains at their initial velocity: with Grains/Motion = " +
                         motion + " the centres are held (set Grains/Motion = free)");
  const size_t count = scene.grains.size();
  const auto held = grains.get<Array<int>>("Held");
  scene.held_grains.assign(held.begin(), held.end());
  scene.prescribed_grains.assign(prescribed.begin(), prescribed.end());
  for (const auto& [name, list] : {std::pair<const char*, const std::vector<int>*>{"Held", &scene.held_grains},
                                   {"Prescribed", &scene.prescribed_grains}})
    for (int g : *list)
      if (g >= static_cast<int>(count))
        throw ParameterError(std::string("Grains/") + name + " names grain " + std::to_string(g) +
                             ", and the scene has " + std::to_string(count) + " (indices from 0)");
  for (int g : scene.prescribed_grains)
    if (std::find(scene.held_grains.begin(), scene.held_grains.end(), g) != scene.held_grains.end())
      throw ParameterError("Grains/Held holds grain " + std::to_string(g) +
                           " still, and Grains/Prescribed moves it as set: name it in one of the two");
  std::vector<int> set(scene.held_grains);
  set.insert(set.end(), scene.prescribed_grains.begin(), scene.prescribed_grains.end());
  std::sort(set.begin(), set.end());
  if (!set.empty() && std::unique(set.begin(), set.end()) - set.begin() == static_cast<long>(count))
    throw ParameterError(scene.prescribed_grains.empty()
                             ? "Grains/Held holds every grain: nothing moves (set Grains/Motion = fixed)"
                             : "Grains/Held and Grains/Prescribed set the motion of every grain: the fluid moves "
                               "none of them");
  // Grains/Initial Velocity and Initial Spin: one set for every grain, or
  // one a grain; none for a held grain.
  const int spin_values = dim == 2 ? 1 : 3;
  auto check_start = [&](const std::vector<double>& values, const char* name, int per_grain, const char* unit) {
    const size_t given = values.size();
    if (given == per_grain * count)
      for (int g : scene.held_grains)
        for (int k = 0; k < per_grain; ++k)
          if (values[g * per_grain + k] != 0)
            throw ParameterError(std::string("Grains/Initial ") + name + " sets grain " + std::to_string(g) +
                                 " going, and Grains/Held holds it still");
    if (given != 0 && given != static_cast<size_t>(per_grain) && given != per_grain * count)
      throw ParameterError(std::string("Grains/Initial ") + name + " has " + std::to_string(given) +
                           " values: give " + std::to_string(per_grain) + " (every grain alike) or " +
                           std::to_string(per_grain * count) + " (" + std::to_string(per_grain) + " " + unit +
                           " for each of the " + std::to_string(count) + " grains)");
  };
  check_start(scene.grain_velocity, "Velocity", dim, "components");
  check_start(scene.grain_spin, "Spin", spin_values, dim == 2 ? "value, about z," : "components");
  if (scene.grains.empty())
    throw ParameterError("Grains/Motion = " + motion + " moves grains, and the scene has none (Grains/File, "
                         "Grains/Inline or Grains/Random Pack)");
  if (scene.particle_motion != ParticleMotion::Lagrangian)
    throw ParameterError("Grains/Motion = " + motion + " needs a fluid that moves with them: set "
                         "Discretization/Particle Motion = lagrangian (fixed particles stay on their lattice)");
  // The grains' density: Grains/Density for all, or each its own from the grain file.
  const bool own_densities = scene.grain_densities_given();
  if (own_densities && scene.grain_density != 0)
    throw ParameterError("Grains/Density and the grain file's density column both give the grains' density: give "
                         "it one way (leave Grains/Density out, or the file's fourth column in 2D, fifth in 3D)");
  if (!own_densities && !(scene.grain_density > 0))
    throw ParameterError("Grains/Motion = " + motion + " needs Grains/Density (kg/m^3) for the grains' mass and "
                         "moment of inertia (or each grain's density as a column of Grains/File)");
  // The fluid a grain pushes aside acts on it like mass of its own (added
  // mass), which the explicit step meets a step late: for grains far
  // lighter than the fluid that lag grows from step to step
  // (docs/method.md, 'Grains that move').
  const Grain* lightest = &scene.grains.front();
  for (const Grain& g : scene.grains)
    if (scene.density_of(g) < scene.density_of(*lightest)) lightest = &g;
  const double density = scene.density_of(*lightest);
  if (scene.grain_motion == GrainMotion::Free && density < 0.25 * scene.density) {
    std::ostringstream msg;
    if (own_densities)
      msg << "grain " << lightest->origin << ": its density " << density << " kg/m^3 is ";
    else
      msg << "Grains/Density = " << density << " kg/m^3 is ";
    msg << density / scene.density
        << " of the fluid's: grains much lighter than the fluid they displace move unstably under the explicit "
           "step (their added mass outweighs them); below about 0.2 of the fluid's density runs have failed";
    scene.warnings.push_back(msg.str());
  }
  if (scene.allow_overlapping_grains)
    throw ParameterError("Grains/Motion = " + motion + " takes grains that do not overlap: a grain's boundary "
                         "particles belong to it alone (set Grains/Allow Overlap = false)");
}

// The Image sublist: what it asks for, checked one by one; the image is
// then read in pieces and checked against the rest of the scene
// (scene/ImageScene.hpp). Parsed after Fluid, Run and Parallel, so that the
// driven axes, the memory limit and the process grid are known.
void read_scene_image(const ParameterList& list, const std::string& scene_directory, SceneConfig& scene) {
  const auto& image = list.sublist("Image");
  const auto shape_values = image.get<Array<int>>("Shape");
  const auto solid_values = image.get<Array<int>>("Solid Values");
  const double voxel_size = image.get<double>("Voxel Size");
  const bool mirror = image.get<bool>("Mirror");
  const std::string dataset = image.get<std::string>("Dataset");
  std::string file = image.get<std::string>("File");
  if (file.empty()) {
    // Said, not ignored: a scene that sets them meant to use an image.
    const char* given = !shape_values.empty()  ? "Shape"
                        : !solid_values.empty() ? "Solid Values"
                        : voxel_size > 0        ? "Voxel Size"
                        : mirror                ? "Mirror"
                        : !dataset.empty()      ? "Dataset"
                                                : nullptr;
    if (given) throw ParameterError(std::string("Image/") + given + " is given but Image/File is empty");
    return;
  }
  const auto& grains = list.sublist("Grains");
  if (!grains.get<std::string>("File").empty() || !grains.get<Array<double>>("Inline").empty() ||
      grains.sublist("Random Pack").get<double>("Porosity") > 0)
    throw ParameterError("Image/File and Grains describe the solid both: a scene uses one of them");
  if (solid_values.empty()) throw ParameterError("Image/Solid Values is required with Image/File");
  if (!(voxel_size > 0)) throw ParameterError("Image/Voxel Size is required with Image/File (a positive length)");
  if (file[0] != '/' && !scene_directory.empty()) file = scene_directory + "/" + file;

  ImageRequest request;
  request.source.path = file;
  request.source.dataset = dataset;
  request.source.raw.shape.assign(shape_values.begin(), shape_values.end());
  request.source.raw.bits = image.get<std::string>("Type") == "uint16" ? 16 : 8;
  std::string extension = std::filesystem::path(file).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (extension == ".raw" && shape_values.empty())
    throw ParameterError("Image/Shape is required for a .raw image ('" + file + "' says nothing of its own shape)");
  request.solid_values.assign(solid_values.begin(), solid_values.end());
  if (list.sublist("Phases").get<int>("Count") == 2) {
    const auto phase_values = list.sublist("Phases").sublist("Phase 1").get<Array<int>>("Image Values");
    request.phase_values.assign(phase_values.begin(), phase_values.end());
  }
  request.voxel_size = voxel_size;
  request.mirror = mirror;
  request.tensor = list.sublist("Permeability").get<bool>("Tensor");
  // The ladder's coarsest level has the deepest boundary layer, which the pieces' halo must hold.
  const auto& convergence = list.sublist("Convergence");
  request.coarsening = std::pow(convergence.get<double>("Refinement Ratio"), convergence.get<int>("Levels") - 1);
  request.coarsest_spacing = scene.particle_spacing * request.coarsening;
  request.spacings_across_throat = list.sublist("Discretization").get<double>("Spacings Across Throat");
  try {
    build_image_scene(request, scene);
  } catch (const std::invalid_argument& e) {
    throw ParameterError(e.what());
  }
}

// The smallest viscosity ratio of two phases taken, and its inverse the largest.
constexpr double kLeastViscosityRatio = 0.01;

// The Phases sublist, after everything else is read (it depends on the
// cell, the fluid, the particles' motion and what is measured). Two
// fluids on fixed particles, phase 1 in its box; what this slice of the
// feature does not handle is refused rather than run wrongly.
void read_phases(const ParameterList& list, SceneConfig& scene) {
  auto fail = [](const std::string& msg) { throw ParameterError(msg); };
  const auto& phases = list.sublist("Phases");
  const int count = phases.get<int>("Count");
  const auto& second = phases.sublist("Phase 1");
  const double nu = second.get<double>("Kinematic Viscosity"), density = second.get<double>("Density");
  const auto low = second.get<Array<double>>("Region Low"), high = second.get<Array<double>>("Region High");
  const auto centre = second.get<Array<double>>("Region Centre");
  const double radius = second.get<double>("Region Radius");
  const double k = phases.get<double>("Single Phase Permeability");
  const double sigma = phases.get<double>("Surface Tension");
  const std::string driven = phases.get<std::string>("Driven Phase");
  const auto& drainage = second.sublist("Drainage");
  const double drain_saturation = drainage.get<double>("Saturation"), drain_radius = drainage.get<double>("Radius");
  const double drain_pressure = drainage.get<double>("Capillary Pressure");
  const std::string inlet = drainage.get<std::string>("Inlet");
  const double contact_angle = drainage.get<double>("Contact Angle");
  const double drain_sigma = drainage.get<double>("Surface Tension");
  const bool trapping = drainage.get<bool>("Trapping");
  const bool drained = drain_saturation != 0 || drain_radius != 0 || drain_pressure != 0;
  // The rest of the Drainage sublist means nothing without Saturation, Radius or Capillary Pressure.
  const bool drainage_given =
      drained || trapping || contact_angle != 0 || drain_sigma != 0 || inlet != "x";
  const auto image_values = second.get<Array<int>>("Image Values");
  const bool labelled = !image_values.empty();
  const bool moving = phases.get<std::string>("Interface") == "moving";
  const double width = phases.get<double>("Interface Width"), mobility = phases.get<double>("Interface Mobility");
  const double wetting_angle = phases.get<double>("Contact Angle");
  const auto solid_angles = phases.get<Array<double>>("Contact Angles");
  const auto force_steps = phases.get<Array<double>>("Force Steps");
  // What only a moving interface reads, named when it would be ignored:
  // set to other than its default (the same in io/Parameters.cpp).
  const SceneConfig defaults;
  std::string moving_only;
  if (width != defaults.interface_width) moving_only = "Interface Width";
  if (mobility != defaults.interface_mobility) moving_only = "Interface Mobility";
  if (wetting_angle != defaults.contact_angle) moving_only = "Contact Angle";
  if (!solid_angles.empty()) moving_only = "Contact Angles";
  if (!force_steps.empty()) moving_only = "Force Steps";
  if (count == 1) {
    if (moving) fail("Phases/Interface = moving moves the interface between two phases, and Phases/Count = 1");
    if (nu != 0 || density != 0 || !low.empty() || !high.empty() || !centre.empty() || radius != 0 ||
        drainage_given || labelled ||
        second.get<std::string>("Name") != "phase 1")
      fail("Phases/Phase 1 is given, but Phases/Count = 1 (the Fluid sublist's fluid alone): set Phases/Count = 2, "
           "or leave Phases/Phase 1 out");
    if (k != 0)
      fail("Phases/Single Phase Permeability gives the relative permeabilities of two phases, and Phases/Count = 1");
    if (sigma != 0) fail("Phases/Surface Tension acts between two phases, and Phases/Count = 1");
    if (driven != "both") fail("Phases/Driven Phase = " + driven + " chooses between two phases, and Phases/Count = 1");
    if (!moving_only.empty())
      fail("Phases/" + moving_only + " is read with a moving interface between two phases, and Phases/Count = 1");
    return;
  }
  const int dim = scene.dimension;
  if (scene.particle_motion != ParticleMotion::Fixed)
    fail("Phases/Count = 2 needs Discretization/Particle Motion = fixed: a particle's phase is set once on the "
         "fixed lattice; phases on moving particles are not supported yet");
  if (!(scene.kinematic_viscosity > 0))
    fail("Fluid/Kinematic Viscosity must be positive with Phases/Count = 2 (it is phase 0's viscosity)");
  if (!(nu > 0)) fail("Phases/Phase 1/Kinematic Viscosity must be positive (m^2/s): it is required with Phases/Count = 2");
  // The viscosity ratios the layered channel validates (docs/validation.md,
  // section 8): to 100 either way within 0.25 % at 80 across; at 1000 the
  // steady solve stalls at 80 across, at 10,000 already at 20.
  // (To round-off: 1e-4 / 1e-6 is 100 and a last bit.)
  const double viscosity_ratio = nu / scene.kinematic_viscosity, slack = 1e-12;
  if (!(viscosity_ratio >= kLeastViscosityRatio * (1 - slack) &&
        viscosity_ratio <= (1 + slack) / kLeastViscosityRatio)) {
    std::ostringstream msg;
    msg << std::setprecision(6) << "Phases/Phase 1/Kinematic Viscosity = " << nu << " is " << viscosity_ratio
        << " times Fluid/Kinematic Viscosity: viscosity ratios from " << kLeastViscosityRatio << " to "
        << 1 / kLeastViscosityRatio << " are supported (docs/validation.md, section 8)";
    fail(msg.str());
  }
  if (density != 0 && density != scene.density) {
    std::ostringstream msg;
    msg << std::setprecision(10) << "Phases/Phase 1/Density = " << density << " differs from Fluid/Density = "
        << scene.density << ": only a density ratio of 1 is supported for now (leave it 0, or give Fluid/Density)";
    fail(msg.str());
  }
  const bool box = !low.empty() || !high.empty(), round = !centre.empty() || radius != 0;
  if (box + round + drained + labelled > 1)
    fail("Phases/Phase 1: give its region one way: a box (Region Low, Region High), a disc/sphere (Region "
         "Centre, Region Radius), the Drainage sublist's rule or Image Values, not two");
  if (drainage_given && !drained)
    fail("Phases/Phase 1/Drainage is given without Saturation, Radius or Capillary Pressure: its Inlet, Trapping, "
         "Contact Angle and Surface Tension mean nothing without them (give one, or leave the sublist out)");
  if (!box && !round && !drained && !labelled)
    fail("Phases/Phase 1 needs its region with Phases/Count = 2: a box (Region Low, Region High), a "
         "disc/sphere (Region Centre, Region Radius), Drainage/Saturation, Radius or Capillary Pressure, or Image "
         "Values");
  PhaseConfig outside, inside;
  outside.name = "fluid";
  outside.density = scene.density;
  outside.kinematic_viscosity = scene.kinematic_viscosity;
  inside.name = second.get<std::string>("Name");
  inside.density = scene.density;
  inside.kinematic_viscosity = nu;
  if (labelled) {
    if (!scene.image.voxels)
      fail("Phases/Phase 1/Image Values names voxels of an image, and the scene has none (Image/File)");
    for (int value : image_values)
      if (std::find(scene.image.solid_values.begin(), scene.image.solid_values.end(), value) !=
          scene.image.solid_values.end())
        fail("Phases/Phase 1/Image Values: " + std::to_string(value) +
             " is also in Image/Solid Values: a voxel is solid or fluid, not both");
    inside.image_values.assign(image_values.begin(), image_values.end());
  } else if (drained) {
    auto& rule = inside.drainage;
    std::ostringstream msg;
    msg << std::setprecision(10);
    if ((drain_saturation != 0) + (drain_radius != 0) + (drain_pressure != 0) > 1)
      msg << "Phases/Phase 1/Drainage: give Saturation, Radius or Capillary Pressure, one of them";
    else if (drain_saturation != 0 && !(drain_saturation > 0 && drain_saturation <= 1))
      msg << "Phases/Phase 1/Drainage/Saturation = " << drain_saturation << " must lie in (0, 1]";
    else if (drain_radius != 0 && !(drain_radius > 0))
      msg << "Phases/Phase 1/Drainage/Radius = " << drain_radius << " must be positive (m): the balls' radius";
    else if (drain_pressure != 0 && !(drain_pressure > 0))
      msg << "Phases/Phase 1/Drainage/Capillary Pressure = " << drain_pressure
          << " must be positive (Pa): phase 1's pressure over phase 0's";
    else if (drain_pressure != 0 && !(drain_sigma > 0))
      msg << "Phases/Phase 1/Drainage/Capillary Pressure needs Drainage/Surface Tension (N/m): the balls' radius "
             "is (dim - 1) sigma cos(theta) / Pc";
    else if (!(contact_angle >= 0 && contact_angle < 90))
      msg << "Phases/Phase 1/Drainage/Contact Angle = " << contact_angle
          << " must lie in [0, 90) degrees (measured through phase 0, the wetting fluid): at 90 or more, phase 1 "
             "wets the solid and pushing it in is imbibition, not drainage (swap the phases)";
    else if (!scene.has_solid() && scene.walls == WallType::None)
      msg << "Phases/Phase 1/Drainage needs a solid (Grains, an Image or Walls): in an open cell every ball fits "
             "and the phase would fill it all";
    else if (trapping && inlet == "anywhere")
      msg << "Phases/Phase 1/Drainage/Trapping needs an Inlet axis: the wetting phase is trapped when cut off "
             "from the outlet, the high side of the inlet's face, and Inlet = anywhere has none";
    else if (inlet != "anywhere" && inlet[0] - 'x' >= dim)
      msg << "Phases/Phase 1/Drainage/Inlet = '" << inlet << "' names an axis the " << dim << "D cell has not";
    else if (inlet != "anywhere" && !scene.periodic[inlet[0] - 'x'])
      msg << "Phases/Phase 1/Drainage/Inlet = '" << inlet << "': the cell is closed by walls across that axis "
          << "(Domain/Periodic), so no phase enters there; name a periodic axis";
    if (!msg.str().empty()) fail(msg.str());
    // A capillary pressure is a radius: the Young-Laplace law of the rule.
    const double radius_given =
        drain_pressure > 0 ? drainage_radius(dim, drain_sigma, contact_angle, drain_pressure) : drain_radius;
    if (radius_given > 0 && radius_given < 0.5 * scene.particle_spacing) {
      std::ostringstream note;
      note << std::setprecision(6) << "Phases/Phase 1/Drainage/";
      if (drain_pressure > 0)
        note << "Capillary Pressure = " << drain_pressure << " Pa gives balls of radius " << radius_given << ",";
      else
        note << "Radius = " << radius_given << " is";
      note << " below half a particle spacing (" << 0.5 * scene.particle_spacing
           << "), the smallest ball the lattice resolves: phase 1 is placed as at that radius (every fluid "
              "particle the inlet reaches), and the capillary pressure reported is that of the radius given";
      scene.warnings.push_back(note.str());
    }
    rule.saturation = drain_saturation;
    rule.radius = radius_given;
    rule.capillary_pressure = drain_pressure;
    rule.inlet_anywhere = inlet == "anywhere";
    rule.inlet_axis = rule.inlet_anywhere ? 0 : inlet[0] - 'x';
    rule.trapping = trapping;
    rule.contact_angle = contact_angle;
    rule.surface_tension = drain_sigma;
  } else if (box) {
    for (const auto& [corner, values] : {std::pair<const char*, const Array<double>&>{"Region Low", low},
                                         std::pair<const char*, const Array<double>&>{"Region High", high}})
      if (static_cast<int>(values.size()) != dim)
        fail(std::string("Phases/Phase 1/") + corner + " must have one value per direction (" + std::to_string(dim) +
             "), got " + std::to_string(values.size()) + ": the box needs both corners");
    for (int d = 0; d < dim; ++d) {
      const double L = scene.cell_size[d];
      if (!(low[d] < high[d]))
        fail("Phases/Phase 1/Region Low must lie below Region High in every direction (direction " +
             std::to_string(d) + " is empty)");
      if (low[d] < 0 || high[d] > L) {
        std::ostringstream msg;
        msg << std::setprecision(10) << "Phases/Phase 1/Region Low and Region High: the box [" << low[d] << ", "
            << high[d] << ") in direction " << d << " reaches outside the cell [0, " << L << ")";
        fail(msg.str());
      }
      inside.region_low[d] = low[d], inside.region_high[d] = high[d];
    }
  } else {
    if (static_cast<int>(centre.size()) != dim)
      fail("Phases/Phase 1/Region Centre must have one value per direction (" + std::to_string(dim) + "), got " +
           std::to_string(centre.size()));
    if (!(radius > 0)) {
      std::ostringstream msg;
      msg << std::setprecision(10) << "Phases/Phase 1/Region Radius = " << radius
          << " must be positive (m): it is the disc's (sphere's) radius";
      fail(msg.str());
    }
    for (int d = 0; d < dim; ++d) {
      if (centre[d] < 0 || centre[d] >= scene.cell_size[d]) {
        std::ostringstream msg;
        msg << std::setprecision(10) << "Phases/Phase 1/Region Centre: " << centre[d] << " in direction " << d
            << " lies outside the cell [0, " << scene.cell_size[d] << ")";
        fail(msg.str());
      }
      // Across a periodic face the nearest image is taken; it is unique only
      // while the region is narrower than the cell.
      if (2 * radius >= scene.cell_size[d]) {
        std::ostringstream msg;
        msg << std::setprecision(10) << "Phases/Phase 1/Region Radius = " << radius
            << ": the disc (sphere) must be narrower than the cell (" << scene.cell_size[d] << " in direction " << d
            << ")";
        fail(msg.str());
      }
      inside.region_centre[d] = centre[d];
    }
    inside.region_radius = radius;
  }
  if (!moving && !moving_only.empty())
    fail("Phases/" + moving_only + " is read with Phases/Interface = moving only (the phase field); with Interface "
         "= fixed the phases stay where they were put and nothing wets: set Interface = moving, or leave it out");
  if (moving && !force_steps.empty() && !(body_force_magnitude(scene) > 0))
    fail("Phases/Force Steps are factors of Fluid/Body Force, and Fluid/Body Force is zero");
  if (moving && !solid_angles.empty()) {
    // One angle per solid the scene names: its image's solid values, or its grains.
    const bool image = scene.image.voxels != nullptr;
    const std::size_t solids = image ? scene.image.solid_values.size() : scene.grains.size();
    if (!image && scene.grains.empty())
      fail("Phases/Contact Angles gives an angle per solid value of an image or per grain, and the scene has neither "
           "(plane walls take Phases/Contact Angle)");
    if (static_cast<std::size_t>(solid_angles.size()) != solids)
      fail("Phases/Contact Angles has " + std::to_string(solid_angles.size()) + " angles for " +
           std::to_string(solids) + (image ? " Image/Solid Values" : " grains") + ": give one for each, in order");
  }
  if (moving) {
    if (scene.steady_solver)
      fail("Phases/Interface = moving follows the interface in time; Solver/Method = steady solves for a flow whose "
           "phases stay put: use Solver/Method = explicit");
    if (scene.convergence_levels > 1)
      fail("Phases/Interface = moving with Convergence/Levels > 1 is not supported: a level would start from the "
           "coarser level's flow but not from its interface");
  }
  if (sigma > 0 && !moving) {
    bool all_periodic = true;
    for (int d = 0; d < dim; ++d) all_periodic = all_periodic && scene.periodic[d];
    if (scene.has_solid() || scene.walls != WallType::None || !all_periodic)
      fail("Phases/Surface Tension with Phases/Interface = fixed needs a cell periodic in every direction without "
           "grains, an image or walls: boundary particles carry no colour there (Interface = moving wets them)");
  }
  if (scene.permeability_tensor)
    fail("Permeability/Tensor with Phases/Count = 2 is not supported: the phases report their flux along the one "
         "driven axis");
  if (scene.convergence_levels > 1 && drain_saturation != 0)
    fail("Convergence/Levels > 1 with Phases/Phase 1/Drainage/Saturation: each level's drainage would reach "
         "another saturation at another capillary pressure; give Drainage/Capillary Pressure or Radius, the same "
         "on every level");
  if (scene.linearity_check)
    fail("Permeability/Linearity Check with Phases/Count = 2 is not supported yet: the phases are reported for one "
         "force");
  if (!scene.profile_sample_times.empty())
    fail("Diagnostics/Profile Sample Times compares a channel with the series solution of one fluid: leave it empty "
         "with Phases/Count = 2");
  if (k > 0 && !(body_force_magnitude(scene) > 0))
    fail("Phases/Single Phase Permeability gives relative permeabilities, which need the driving force: "
         "Fluid/Body Force is zero");
  if (driven != "both" && !(body_force_magnitude(scene) > 0))
    fail("Phases/Driven Phase = " + driven + " names the phase Fluid/Body Force acts on, and Fluid/Body Force is "
         "zero");
  scene.phases = {outside, inside};
  scene.driven_phase = driven == "both" ? -1 : std::stoi(driven);
  scene.single_phase_permeability = k;
  scene.surface_tension = sigma;
  scene.moving_interface = moving;
  scene.interface_width = width;
  scene.interface_mobility = mobility;
  scene.contact_angle = wetting_angle;
  scene.solid_contact_angles.assign(solid_angles.begin(), solid_angles.end());
  scene.force_steps.assign(force_steps.begin(), force_steps.end());
  scene.colour = phases.get<std::string>("Colour") == "phase" ? ColourFunction::Phase : ColourFunction::VolumeFraction;
}

}  // namespace

SceneConfig scene_from_parameters(const ParameterList& list, const std::string& scene_directory) {
  SceneConfig scene;
  auto fail = [](const std::string& msg) { throw ParameterError(msg); };
  scene.name = list.sublist("Scene").get<std::string>("Name");
  // The name makes the default output directory, poresph-NAME: it must not
  // lead anywhere else, nor be missing.
  if (scene.name.empty()) fail("Scene/Name is empty: give the scene a name (summary.json's scene, poresph-NAME)");
  if (scene.name.find_first_of("/\\") != std::string::npos)
    fail("Scene/Name '" + scene.name + "' contains a path separator; name the output directory with --output");
  // It names a directory and is written into XML and JSON: a control
  // character (a tab, a newline) would not come back as it was written.
  for (unsigned char c : scene.name)
    if (c < 0x20 || c == 0x7F)
      fail("Scene/Name contains a control character (code " + std::to_string(c) +
           "): a name is written on one line, without tabs or other control characters");

  const auto& domain = list.sublist("Domain");
  const auto cell = domain.get<Array<double>>("Cell Size");
  if (cell.size() != 2 && cell.size() != 3)
    fail("Domain/Cell Size must have 2 (2D) or 3 (3D) values, got " + std::to_string(cell.size()));
  scene.dimension = static_cast<int>(cell.size());
  const int dim = scene.dimension;
  for (int d = 0; d < dim; ++d) {
    if (!(cell[d] > 0)) fail("Domain/Cell Size: every side must be positive");
    scene.cell_size[d] = cell[d];
  }
  const auto periodic = domain.get<Array<int>>("Periodic");
  if (!periodic.empty() && static_cast<int>(periodic.size()) != dim)
    fail("Domain/Periodic must have one value per direction (" + std::to_string(dim) + ")");
  for (int d = 0; d < dim; ++d) scene.periodic[d] = periodic.empty() ? true : periodic[d] != 0;

  const auto& fluid = list.sublist("Fluid");
  scene.density = fluid.get<double>("Density");
  if (!(scene.density > 0)) fail("Fluid/Density must be positive");
  scene.kinematic_viscosity = fluid.get<double>("Kinematic Viscosity");
  const auto force = fluid.get<Array<double>>("Body Force");
  if (!force.empty() && static_cast<int>(force.size()) != dim)
    fail("Fluid/Body Force must have one value per direction (" + std::to_string(dim) + ")");
  for (int d = 0; d < static_cast<int>(force.size()); ++d) scene.body_force[d] = force[d];
  scene.sound_speed = fluid.get<double>("Sound Speed");
  scene.density_variation = fluid.get<double>("Density Variation");
  scene.raise_sound_speed = fluid.get<bool>("Raise Sound Speed");
  if (scene.raise_sound_speed && scene.sound_speed > 0)
    fail("Fluid/Raise Sound Speed and Fluid/Sound Speed exclude each other: the sound speed is either given or chosen");
  scene.velocity_scale = fluid.get<double>("Velocity Scale");
  scene.length_scale = fluid.get<double>("Length Scale");
  scene.background_pressure = fluid.get<double>("Background Pressure");

  const auto& disc = list.sublist("Discretization");
  scene.particle_spacing = disc.get<double>("Particle Spacing");
  const double across_throat = disc.get<double>("Spacings Across Throat");
  if (scene.particle_spacing > 0 && across_throat > 0)
    fail("Discretization/Particle Spacing and Discretization/Spacings Across Throat exclude each other: give one");
  if (!(scene.particle_spacing > 0) && !(across_throat > 0))
    fail("Discretization/Particle Spacing (or Spacings Across Throat) must be positive");
  if (across_throat > 0 && across_throat < 1) {
    std::ostringstream msg;
    msg << "Discretization/Spacings Across Throat = " << across_throat
        << " puts less than one spacing across the narrowest throat, which then holds no fluid particle: give 1 or "
           "more (3 or more resolve the flow there)";
    fail(msg.str());
  }
  scene.smoothing_length_ratio = disc.get<double>("Smoothing Length Ratio");
  scene.resummation_interval = disc.get<int>("Density Resummation Interval");
  scene.time_step = disc.get<double>("Time Step");
  scene.shifting_coefficient = disc.get<double>("Particle Shifting");
  scene.neighbour_skin = disc.get<double>("Neighbour Skin");
  scene.particle_motion =
      disc.get<std::string>("Particle Motion") == "lagrangian" ? ParticleMotion::Lagrangian : ParticleMotion::Fixed;
  scene.convection = fluid.get<bool>("Convection");
  scene.wall_pressure =
      disc.get<std::string>("Wall Pressure") == "continuity" ? WallPressure::Continuity : WallPressure::Extrapolated;
  if (scene.particle_motion == ParticleMotion::Fixed) {
    // What only moving particles need: said, not silently dropped, since
    // older scene files switch them on.
    auto unused = [&](const char* name, bool given) {
      if (given)
        scene.warnings.push_back(std::string("Discretization/") + name +
                                 " has no effect: Discretization/Particle Motion = fixed keeps the particles on "
                                 "their lattice");
    };
    unused("Particle Shifting", scene.shifting_coefficient > 0);
    unused("Density Resummation Interval", scene.resummation_interval > 0);
    scene.shifting_coefficient = 0;
    scene.resummation_interval = 0;
    scene.neighbour_skin = 0;  // the lists are built once
  }

  const auto& walls = list.sublist("Walls");
  const auto wall_type = walls.get<std::string>("Type");
  scene.walls = wall_type == "channel" ? WallType::Channel : WallType::None;
  scene.lower_wall_velocity = walls.get<double>("Lower Velocity");
  scene.upper_wall_velocity = walls.get<double>("Upper Velocity");
  for (int d = 0; d < dim; ++d) {
    const bool walled = scene.walls == WallType::Channel && d == 1;
    if (walled && scene.periodic[d])
      fail("Walls/Type = channel puts walls at y = 0 and y = L_y: set Domain/Periodic to 0 in y");
    if (!walled && !scene.periodic[d])
      fail("Domain/Periodic is 0 in direction " + std::to_string(d) +
           " but no wall bounds it (only Walls/Type = channel, in y, is available)");
  }
  if (scene.walls == WallType::None && (scene.lower_wall_velocity != 0 || scene.upper_wall_velocity != 0))
    fail("Walls/Lower Velocity and Walls/Upper Velocity need Walls/Type = channel");

  const auto& run = list.sublist("Run");
  scene.end_time = run.get<double>("End Time");
  if (!(scene.end_time > 0)) fail("Run/End Time must be positive");
  scene.max_steps = run.get<int>("Max Steps");
  const auto backend = run.get<std::string>("Backend");
  scene.backend = backend == "serial" ? Backend::Serial : backend == "openmp" ? Backend::OpenMP : Backend::Default;
  scene.threads = run.get<int>("Threads");
  scene.memory_limit_bytes = run.get<double>("Memory Limit") * 1e9;
  const auto progress = run.get<std::string>("Progress");
  scene.progress = progress == "always" ? ProgressMode::Always
                   : progress == "never" ? ProgressMode::Never
                                         : ProgressMode::Auto;

  const auto& parallel = list.sublist("Parallel");
  scene.grid_decomposition = parallel.get<std::string>("Decomposition") == "grid";
  const auto grid = parallel.get<Array<int>>("Process Grid");
  scene.process_grid.assign(grid.begin(), grid.end());
  const char* cut_names[3] = {"X Cuts", "Y Cuts", "Z Cuts"};
  for (int d = 0; d < 3; ++d) {
    const auto cuts = parallel.get<Array<double>>(cut_names[d]);
    scene.cuts[d].assign(cuts.begin(), cuts.end());
  }
  if (!scene.grid_decomposition && (!scene.process_grid.empty() || !scene.cuts[0].empty() || !scene.cuts[1].empty() ||
                                    !scene.cuts[2].empty()))
    fail("Parallel/Process Grid and the cuts apply to Parallel/Decomposition = grid");
  scene.rebalance_threshold = parallel.get<double>("Rebalance Threshold");
  scene.rebalance_interval = parallel.get<int>("Rebalance Interval");
  if (scene.rebalance_threshold > 0 && scene.rebalance_threshold < 1)
    fail("Parallel/Rebalance Threshold = " + std::to_string(scene.rebalance_threshold) +
         ": the slowest process's time over the mean is at least 1; give a threshold of at least 1 (or 0: never)");
  if (scene.rebalance_threshold > 0 && scene.grid_decomposition)
    fail("Parallel/Rebalance Threshold divides the cell anew by Zoltan2's RCB: not with Parallel/Decomposition = grid");
  if (scene.rebalance_threshold > 0 && scene.particle_motion == ParticleMotion::Fixed)
    fail("Parallel/Rebalance Threshold follows a load that moves: fixed particles (Discretization/Particle Motion) "
         "keep the load they start with, which the first division already balances");

  // Before the solid is read: the pore checks trace every axis the tensor drives.
  scene.permeability_tensor = list.sublist("Permeability").get<bool>("Tensor");
  read_scene_image(list, scene_directory, scene);
  const auto& grains = list.sublist("Grains");
  try {
    std::string file = grains.get<std::string>("File");
    if (!file.empty()) {
      if (file[0] != '/' && !scene_directory.empty()) file = scene_directory + "/" + file;
      scene.grains = read_grain_file(file, dim);
    }
    const auto inline_values = grains.get<Array<double>>("Inline");
    const auto listed = grains_from_list(std::vector<double>(inline_values.begin(), inline_values.end()), dim);
    if (!listed.empty() && !scene.grains.empty() && scene.grains.front().density > 0)
      fail("Grains/File gives each grain a density and Grains/Inline gives grains without one: give every grain "
           "its density (all in the file) or none");
    scene.grains.insert(scene.grains.end(), listed.begin(), listed.end());
    scene.allow_overlapping_grains = grains.get<bool>("Allow Overlap");
    const auto& pack = grains.sublist("Random Pack");
    if (pack.get<double>("Porosity") > 0) {
      if (!scene.grains.empty())
        fail("Grains/Random Pack makes all the grains of the scene: leave Grains/File and Grains/Inline empty");
      RandomPackSpec spec;
      spec.porosity = pack.get<double>("Porosity");
      spec.distribution = pack.get<std::string>("Radius Distribution") == "lognormal"
                              ? RandomPackSpec::Distribution::Lognormal
                              : RandomPackSpec::Distribution::Uniform;
      spec.min_radius = pack.get<double>("Min Radius");
      spec.max_radius = pack.get<double>("Max Radius");
      spec.median_radius = pack.get<double>("Median Radius");
      spec.log_deviation = pack.get<double>("Log Standard Deviation");
      spec.minimum_gap = pack.get<double>("Minimum Gap");
      spec.contacts = pack.get<bool>("Contacts");
      spec.seed = static_cast<unsigned long long>(pack.get<int>("Seed"));
      auto made = make_random_pack(spec, scene);
      scene.grains = std::move(made.grains);
      scene.grains_note = made.description;
      // Contacts are overlaps by construction; the pack's own rule bounds them.
      scene.allow_overlapping_grains = scene.allow_overlapping_grains || spec.contacts;
    }
    check_grains(scene.grains, scene);
    read_grain_motion(grains, scene);
    if (across_throat > 0) scene.particle_spacing = spacing_across_throat(scene, across_throat);
    const auto throats = check_pores(scene);
    scene.warnings.insert(scene.warnings.end(), throats.begin(), throats.end());
  } catch (const std::invalid_argument& e) {
    throw ParameterError(e.what());
  }
  // A channel as narrow as a throat resolves as badly: its k comes out about
  // 1 + 2.3 (dx / H)^2 times L_y^2 / 12 (+2.3 % at 10 spacings, +9.5 % at 5,
  // +26 % at 3; docs/validation.md).
  if (scene.walls == WallType::Channel && scene.particle_spacing > 0) {
    const double across = scene.cell_size[1] / scene.particle_spacing;
    if (across < 5 - 1e-9) {
      std::ostringstream msg;
      msg.precision(3);
      msg << "the channel is " << across << " particle spacings high (Domain/Cell Size[1] over Discretization/"
          << "Particle Spacing): fewer than 5, so k and the flow are off by " << 100 * 2.3 / (across * across)
          << " % or so (+26 % at 3 spacings, +9.5 % at 5); a finer spacing resolves it";
      scene.warnings.push_back(msg.str());
    }
  }

  const auto& permeability = list.sublist("Permeability");
  scene.linearity_check = permeability.get<bool>("Linearity Check");
  const auto& convergence = list.sublist("Convergence");
  scene.convergence_levels = convergence.get<int>("Levels");
  scene.refinement_ratio = convergence.get<double>("Refinement Ratio");
  scene.steady_tolerance = permeability.get<double>("Steady Tolerance");
  scene.steady_window = permeability.get<double>("Steady Window");
  const auto& solver = list.sublist("Solver");
  scene.steady_solver = solver.get<std::string>("Method") == "steady";

  check_measurement(scene);
  // What is not refused but measures no k, said so rather than left out of summary.json unexplained.
  const int driven_axis = force_axis(scene);
  const bool forced = body_force_magnitude(scene) > 0;
  if (driven_axis >= 0 && !scene.permeability_tensor && !scene.periodic[driven_axis])
    scene.warnings.push_back(std::string("Fluid/Body Force drives along ") + "xyz"[driven_axis] +
                             ", across the channel's walls: no flow crosses them, so no k is measured (the fluid "
                             "comes to rest with a hydrostatic pressure)");
  if (forced && scene.moving_grains())
    scene.warnings.push_back("Grains/Motion moves grains while Fluid/Body Force drives the fluid: k = nu <u> / F is "
                             "then measured on a flow whose solid moves, not the Darcy permeability of a fixed pack "
                             "(hold the grains, Grains/Motion = fixed, to measure that)");
  if (forced && !(scene.kinematic_viscosity > 0))
    scene.warnings.push_back("Fluid/Kinematic Viscosity = 0: nothing resists the body force, so the fluid speeds up "
                             "without end and no k is measured");

  scene.solver.tolerance = solver.get<double>("Tolerance");
  scene.solver.permeability_tolerance = solver.get<double>("Permeability Tolerance");
  scene.solver.linear_tolerance = solver.get<double>("Linear Tolerance");
  scene.solver.max_nonlinear_iterations = solver.get<int>("Max Nonlinear Iterations");
  scene.solver.max_linear_iterations = solver.get<int>("Max Linear Iterations");
  scene.solver.restart = solver.get<int>("Krylov Restart");
  scene.solver.inner_restart = solver.get<int>("Inner Krylov Restart");
  scene.solver.inner_tolerance = solver.get<double>("Inner Tolerance");
  scene.solver.max_inner_iterations = solver.get<int>("Max Inner Iterations");
  scene.solver.raised_inner_iterations = solver.get<int>("Raised Inner Iterations");
  const std::string dg_preconditioner = solver.get<std::string>("DG Preconditioner");
  scene.solver.dg_preconditioner = dg_preconditioner == "schwarz" ? DgPreconditioner::Schwarz
                                   : dg_preconditioner == "auto"  ? DgPreconditioner::Auto
                                                                  : DgPreconditioner::Lattice;
  if (scene.steady_solver) {
    // What the steady equations are: those of particles that stay where they are.
    if (scene.particle_motion != ParticleMotion::Fixed)
      fail("Solver/Method = steady solves for the steady state of fixed particles; Discretization/Particle "
           "Motion = lagrangian particles move, so their flow has no steady state to solve for: march it with "
           "Solver/Method = explicit");
    if (!(scene.kinematic_viscosity > 0))
      fail("Solver/Method = steady needs Fluid/Kinematic Viscosity > 0: without viscosity nothing balances the "
           "driving force, so the flow has no steady state to solve for");
    if (scene.has_solid() || scene.walls != WallType::None)
      if (scene.wall_pressure != WallPressure::Extrapolated)
        fail("Solver/Method = steady needs Discretization/Wall Pressure = extrapolated: with 'continuity' the "
             "boundary particles' densities are unknowns of their own that keep changing while the fluid flows");
    if (scene.solver.dg_preconditioner == DgPreconditioner::Schwarz && scene.dimension != 2)
      fail("Solver/DG Preconditioner = schwarz is for 2D scenes: in 3D its set-up would take 19,683 products of "
           "DG at h = dx (one per colour, 27 lattice points apart along each axis) and its factors up to 47 kB a "
           "fluid particle; use 'lattice'");
  }

  const auto& output = list.sublist("Output");
  scene.write_final_particles = output.get<bool>("Final Particles CSV");
  scene.field_interval = output.get<double>("Field Interval");
  {
    std::string words = output.get<std::string>("Fields");
    for (auto& c : words)
      if (c == ',') c = ' ';
    std::istringstream in(words);
    for (std::string word; in >> word;) {
      static const char* const known[] = {"velocity", "density", "pressure", "kind", "grain", "id", "phase",
                                          "colour"};
      if (std::find(std::begin(known), std::end(known), word) == std::end(known))
        fail("Output/Fields: unknown field '" + word +
             "' (known: velocity density pressure kind grain id phase colour)");
      if (std::find(scene.fields.begin(), scene.fields.end(), word) == scene.fields.end())
        scene.fields.push_back(word);
    }
  }
  const auto grid_points = output.get<Array<int>>("Grid Points");
  scene.grid_points.assign(grid_points.begin(), grid_points.end());
  if (!scene.grid_points.empty() && static_cast<int>(scene.grid_points.size()) != scene.dimension)
    fail("Output/Grid Points needs one count per direction (" + std::to_string(scene.dimension) + ")");
  if (!scene.grid_points.empty() && !(scene.field_interval > 0))
    fail("Output/Grid Points is given, but the grid is written with the field files and Output/Field Interval is 0 "
         "(none are written): set Output/Field Interval, or leave Output/Grid Points empty");
  scene.checkpoint_interval = output.get<int>("Checkpoint Interval");
  scene.final_checkpoint = output.get<bool>("Final Checkpoint");
  scene.density_variation_limit = list.sublist("Checks").get<double>("Density Variation Limit");

  const auto samples = list.sublist("Diagnostics").get<Array<double>>("Profile Sample Times");
  scene.profile_sample_times.assign(samples.begin(), samples.end());
  if (!scene.profile_sample_times.empty() && scene.walls != WallType::Channel)
    fail("Diagnostics/Profile Sample Times compares a channel's velocity profile with its series solution, and this "
         "scene has no channel (Walls/Type = channel): leave it empty");
  if (!scene.profile_sample_times.empty() && scene.walls == WallType::Channel && !scene.empty_channel())
    fail("Diagnostics/Profile Sample Times compares the velocity profile of an empty channel driven along x with its "
         "series solution, and this channel holds grains or an image or is driven across its walls: leave it "
         "empty");
  read_phases(list, scene);
  if (!scene.has_phases() && std::find(scene.fields.begin(), scene.fields.end(), "phase") != scene.fields.end())
    fail("Output/Fields names 'phase', and the scene has one fluid (set Phases/Count = 2, or leave it out)");
  if (!scene.moving_interface &&
      std::find(scene.fields.begin(), scene.fields.end(), "colour") != scene.fields.end())
    fail("Output/Fields names 'colour', the phase field of Phases/Interface = moving, and this scene has none");
  // Fields other than the default, with no field file to write them to, would do nothing.
  const auto default_fields = valid_parameters()->sublist("Output").get<std::string>("Fields");
  if (list.sublist("Output").get<std::string>("Fields") != default_fields && !(scene.field_interval > 0))
    fail("Output/Fields is given, but the fields are written to the field files and Output/Field Interval is 0: "
         "set an interval, or leave Output/Fields out");
  return scene;
}

}  // namespace poresph
