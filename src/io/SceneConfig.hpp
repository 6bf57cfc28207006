#pragma once
// A scene as the solver sees it: plain values, already validated. Only the
// io layer knows about Teuchos; everything else reads this struct.
#include <array>
#include <string>
#include <vector>

namespace poresph {

enum class WallType { None, Channel };
enum class ProgressMode { Auto, Always, Never };

struct SceneConfig {
  std::string name = "scene";
  int dimension = 2;
  std::array<double, 3> cell_size{};  // periodic cell [0, L_d)
  std::array<bool, 3> periodic{{true, true, true}};

  double density = 1000.0;
  double kinematic_viscosity = 1e-6;
  std::array<double, 3> body_force{};
  double sound_speed = 0.0;  // 0: from the scales below
  double density_variation = 0.01;
  double velocity_scale = 0.0;  // 0: estimated (see Parameters.cpp)
  double length_scale = 0.0;    // 0: largest cell side
  bool absolute_pressure_gradient = false;  // true: momentum equation uses p = c^2 rho itself

  double particle_spacing = 0.0;
  double smoothing_length_ratio = 1.0;  // h / dx
  int resummation_interval = 0;         // steps; 0 = never
  double time_step = 0.0;               // 0: from the stability limits

  WallType walls = WallType::None;
  double lower_wall_velocity = 0.0;  // along x
  double upper_wall_velocity = 0.0;

  double end_time = 0.0;
  long long max_steps = 0;  // 0: no limit
  std::vector<double> profile_sample_times;

  ProgressMode progress = ProgressMode::Auto;
};

}  // namespace poresph
