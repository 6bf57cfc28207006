#include "io/Checkpoint.hpp"

#include <charconv>
#include <cstdio>
#include <map>
#include <sstream>

namespace poresph {
namespace {

// The shortest text that reads back as the same double: exact, and 0.05 rather than 0.050000000000000003.
std::string number(double value) {
  char buffer[32];
  const auto end = std::to_chars(buffer, buffer + sizeof buffer, value).ptr;
  return std::string(buffer, end);
}

template <class T>
std::string list(const T* values, int n) {
  std::string text = "{";
  for (int k = 0; k < n; ++k) text += (k ? ", " : "") + number(static_cast<double>(values[k]));
  return text + "}";
}

// "name = value" lines into a map, in the order of the text.
std::vector<std::pair<std::string, std::string>> lines_of(const std::string& text) {
  std::vector<std::pair<std::string, std::string>> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    const auto eq = line.find(" = ");
    if (eq != std::string::npos) lines.emplace_back(line.substr(0, eq), line.substr(eq + 3));
  }
  return lines;
}

}  // namespace

std::string physics_fingerprint(const SceneConfig& scene, double time_step, double sound_speed) {
  const int D = scene.dimension;
  std::vector<std::pair<std::string, std::string>> entries;
  entries.emplace_back("dimension", std::to_string(D));
  entries.emplace_back("Domain/Cell Size", list(scene.cell_size.data(), D));
  entries.emplace_back("Domain/Periodic", list(scene.periodic.data(), D));
  entries.emplace_back("Discretization/Particle Spacing", number(scene.particle_spacing));
  entries.emplace_back("Discretization/Smoothing Length Ratio", number(scene.smoothing_length_ratio));
  entries.emplace_back("Discretization/Particle Motion",
                       scene.particle_motion == ParticleMotion::Fixed ? "fixed" : "lagrangian");
  entries.emplace_back("Discretization/Particle Shifting", number(scene.shifting_coefficient));
  entries.emplace_back("Discretization/Wall Pressure",
                       scene.wall_pressure == WallPressure::Extrapolated ? "extrapolated" : "continuity");
  entries.emplace_back("Fluid/Density", number(scene.density));
  entries.emplace_back("Fluid/Kinematic Viscosity", number(scene.kinematic_viscosity));
  entries.emplace_back("Fluid/Body Force", list(scene.body_force.data(), D));
  entries.emplace_back("Fluid/Background Pressure", number(scene.background_pressure));
  entries.emplace_back("Fluid/Convection", scene.convection ? "true" : "false");
  // Whatever set them (given, or from the flow scales): the time of a step
  // and the stiffness of the fluid must not change under a continued run.
  entries.emplace_back("speed of sound", number(sound_speed));
  entries.emplace_back("time step", number(time_step));
  entries.emplace_back("Walls/Type", scene.walls == WallType::Channel ? "channel" : "none");
  entries.emplace_back("Walls/Lower Velocity", number(scene.lower_wall_velocity));
  entries.emplace_back("Walls/Upper Velocity", number(scene.upper_wall_velocity));
  entries.emplace_back("Permeability/Tensor", scene.permeability_tensor ? "true" : "false");
  // The grains by their count and a checksum of centres and radii in order.
  std::vector<double> grains;
  for (const auto& g : scene.grains) {
    for (int d = 0; d < D; ++d) grains.push_back(g.centre[d]);
    grains.push_back(g.radius);
  }
  char checksum[20];
  std::snprintf(checksum, sizeof checksum, "%016llx",
                static_cast<unsigned long long>(row_checksum(grains.data(), static_cast<long long>(grains.size()),
                                                             1, 0)));
  entries.emplace_back("Grains", std::to_string(scene.grains.size()) + " grains, checksum " + checksum);
  // Grains that move: the centres above are where they started (the
  // checkpoint holds where they are); how they move is physics.
  if (scene.moving_grains()) {
    const ContactMaterial& c = scene.grain_contact;
    entries.emplace_back("Grains/Motion", scene.grain_motion == GrainMotion::Free ? "free" : "rotating");
    entries.emplace_back("Grains/Density", number(scene.grain_density));
    if (scene.grain_densities_given()) {  // (named only when given: the checkpoints of earlier runs still match)
      std::vector<double> densities;
      for (const auto& g : scene.grains) densities.push_back(g.density);
      char sum[20];
      std::snprintf(sum, sizeof sum, "%016llx",
                    static_cast<unsigned long long>(
                        row_checksum(densities.data(), static_cast<long long>(densities.size()), 1, 0)));
      entries.emplace_back("Grains/File densities", sum);
    }
    entries.emplace_back("Grains/Gravity", list(scene.gravity.data(), D));
    entries.emplace_back("Grains/Held", list(scene.held_grains.data(), static_cast<int>(scene.held_grains.size())));
    if (!scene.prescribed_grains.empty())  // (named only when given: the checkpoints of earlier runs still match)
      entries.emplace_back("Grains/Prescribed",
                           list(scene.prescribed_grains.data(), static_cast<int>(scene.prescribed_grains.size())));
    const double contact[] = {c.young_modulus, c.poisson_ratio, c.restitution, c.friction, c.cutoff_spacings};
    entries.emplace_back("Grains/Contact (Young Modulus, Poisson Ratio, Restitution, Friction, Cutoff Spacings)",
                         list(contact, 5));
  }
  // Two fluids: the second phase's viscosity and box (named only with
  // phases: the checkpoints of one-fluid runs still match).
  if (scene.has_phases()) {
    const PhaseConfig& second = scene.phases[1];
    entries.emplace_back("Phases/Count", std::to_string(scene.phases.size()));
    entries.emplace_back("Phases/Phase 1/Kinematic Viscosity", number(second.kinematic_viscosity));
    if (second.from_image()) {
      std::string values;
      for (int v : second.image_values) values += (values.empty() ? "" : " ") + std::to_string(v);
      entries.emplace_back("Phases/Phase 1/Image Values", values);
    } else if (second.drained()) {
      const auto& rule = second.drainage;
      entries.emplace_back("Phases/Phase 1/Drainage/Saturation", number(rule.saturation));
      entries.emplace_back("Phases/Phase 1/Drainage/Radius", number(rule.radius));  // or the capillary pressure's
      entries.emplace_back("Phases/Phase 1/Drainage/Inlet",
                           rule.inlet_anywhere ? std::string("anywhere") : std::string(1, "xyz"[rule.inlet_axis]));
      entries.emplace_back("Phases/Phase 1/Drainage/Trapping", rule.trapping ? "true" : "false");
    } else if (second.round()) {
      entries.emplace_back("Phases/Phase 1/Region Centre", list(second.region_centre.data(), D));
      entries.emplace_back("Phases/Phase 1/Region Radius", number(second.region_radius));
    } else {
      entries.emplace_back("Phases/Phase 1/Region Low", list(second.region_low.data(), D));
      entries.emplace_back("Phases/Phase 1/Region High", list(second.region_high.data(), D));
    }
    // The force's phase is in each particle's phase acceleration: a restart
    // that drove another phase (or both) would add it twice, or not at all.
    entries.emplace_back("Phases/Driven Phase", scene.driven_phase < 0 ? "both" : std::to_string(scene.driven_phase));
    if (scene.surface_tension > 0) {
      entries.emplace_back("Phases/Surface Tension", number(scene.surface_tension));
      entries.emplace_back("Phases/Colour", scene.colour == ColourFunction::Phase ? "phase" : "volume fraction");
    }
    // A moving interface's field is in the particles (colour); how it moves is the scene's.
    if (scene.moving_interface) {
      entries.emplace_back("Phases/Interface", "moving");
      entries.emplace_back("Phases/Interface Width", number(scene.interface_width));
      entries.emplace_back("Phases/Interface Mobility", number(scene.interface_mobility));
      entries.emplace_back("Phases/Contact Angle", number(scene.contact_angle));
      const auto& angles = scene.solid_contact_angles;
      if (!angles.empty())
        entries.emplace_back("Phases/Contact Angles", list(angles.data(), static_cast<int>(angles.size())));
      // The steps' spans are End Time's shares: a restart with another End Time would drive otherwise.
      const auto& steps = scene.force_steps;
      if (!steps.empty()) {
        entries.emplace_back("Phases/Force Steps", list(steps.data(), static_cast<int>(steps.size())));
        entries.emplace_back("Run/End Time", number(scene.end_time));
      }
    }
  }
  // The image by its shape, voxel size, solid values and a checksum of its
  // voxels (after Image/Mirror): another image, or the same read otherwise,
  // is another solid.
  // A process holding a piece knows the whole image's by the checksum made
  // over all the pieces (scene/ImageScene.cpp).
  if (scene.image.voxels) {
    auto whole_shape = scene.image.voxels->shape;
    std::uint64_t sum = scene.image.solid_checksum;
    if (scene.image.owned.empty()) {
      const auto& voxels = *scene.image.voxels;
      std::vector<std::uint16_t> solid(voxels.values.size());
      const auto is_solid = solid_value_table(scene.image.solid_values);
      for (size_t n = 0; n < solid.size(); ++n) solid[n] = is_solid[voxels.values[n]];
      sum = row_checksum(solid.data(), static_cast<long long>(solid.size()), 1, 0);
    } else {
      whole_shape = scene.image.cell_voxels;
    }
    std::snprintf(checksum, sizeof checksum, "%016llx", static_cast<unsigned long long>(sum));
    entries.emplace_back("Image", shape_text(whole_shape, scene.image.voxels->dimension) + " voxels of " +
                                      number(scene.image.voxel_size) + ", solid voxels checksum " + checksum);
  }
  std::string text;
  for (const auto& [name, value] : entries) text += name + " = " + value + "\n";
  return text;
}

std::uint64_t checkpoint_detail::scalars_checksum(const std::vector<double>& values) {
  return row_checksum(values.data(), static_cast<long long>(values.size()), 1, 0);
}

CheckpointInfo read_checkpoint_info(const std::string& path, MPI_Comm comm) {
  using namespace checkpoint_detail;
  Hdf5File file(path, Hdf5File::Mode::Read, comm);
  CheckpointInfo info;
  std::string format;
  try {
    format = file.string_attribute("format");
  } catch (const std::exception&) {
    throw std::invalid_argument(path + " is an HDF5 file but not a PoreSPH checkpoint");
  }
  if (format == "poresph checkpoint 1")
    throw std::invalid_argument(path + " was written by an earlier PoreSPH (" + format +
                                "), which recorded neither a fingerprint of its physics nor checksums of its data; "
                                "it cannot be checked, so it is not continued: start the run afresh");
  if (format.rfind("poresph checkpoint ", 0) == 0 && format != kCheckpointFormat)
    throw std::invalid_argument(path + " was written by another version of PoreSPH (" + format + "; this one reads " +
                                kCheckpointFormat + "): continue it with the version that wrote it, or start the "
                                "run afresh");
  if (format != kCheckpointFormat) throw std::invalid_argument(path + " is not a PoreSPH checkpoint (" + format + ")");
  std::vector<double> scalars;
  auto scalar = [&](const char* name, auto& value) {
    if constexpr (std::is_same_v<std::decay_t<decltype(value)>, double>) value = file.double_attribute(name);
    else value = static_cast<std::decay_t<decltype(value)>>(file.integer_attribute(name));
    scalars.push_back(static_cast<double>(value));
  };
  scalar("dimension", info.dimension);
  scalar("step", info.step);
  scalar("time", info.time);
  scalar("ranks", info.ranks);
  long long rates_valid = 0;
  scalar("rates_valid", rates_valid);
  info.rates_valid = rates_valid != 0;
  auto& st = info.state;
  scalar("drive_axis", st.drive_axis);
  RunState::for_each_value(st, [&](const char* name, auto& value) {
    if constexpr (std::is_same_v<std::decay_t<decltype(value)>, double>) scalar(name, value);
    else value = read_whole<double>(file, comm, std::string("run/") + name);
  });
  if (as_signed(scalars_checksum(scalars)) != file.integer_attribute("scalars_checksum"))
    throw std::invalid_argument(path + ": the step, time and run state do not match their checksum: the checkpoint "
                                "is damaged");
  const auto parameters = read_whole<char>(file, comm, "run/parameters");
  info.parameters.assign(parameters.begin(), parameters.end());
  const auto fingerprint = read_whole<char>(file, comm, "run/fingerprint");
  info.fingerprint.assign(fingerprint.begin(), fingerprint.end());
  info.boxes = read_whole<double>(file, comm, "run/boxes");
  if (info.ranks < 1 || info.boxes.size() != static_cast<size_t>(info.ranks) * info.dimension * 2)
    throw std::invalid_argument(path + ": its boxes do not match its " + std::to_string(info.ranks) + " processes");
  return info;
}

void check_checkpoint_matches(const CheckpointInfo& info, const std::string& path, const std::string& fingerprint) {
  std::map<std::string, std::string> saved;
  for (const auto& [name, value] : lines_of(info.fingerprint)) saved[name] = value;
  std::string differences;
  std::map<std::string, std::string> here;
  for (const auto& [name, value] : lines_of(fingerprint)) {
    here[name] = value;
    const auto it = saved.find(name);
    const std::string theirs = it == saved.end() ? "(not recorded)" : it->second;
    if (theirs != value) differences += "\n  " + name + ": " + theirs + " in the checkpoint, " + value + " here";
  }
  // What the checkpoint's physics had and this scene has not at all (a
  // second fluid, moving grains): that is other physics too.
  for (const auto& [name, value] : saved)
    if (here.find(name) == here.end())
      differences += "\n  " + name + ": " + value + " in the checkpoint, none here";
  if (!differences.empty())
    throw std::invalid_argument("--restart " + path +
                                ": the checkpoint is of other physics than this scene, so the run would not go on "
                                "but jump to another one:" +
                                differences);
}

}  // namespace poresph
