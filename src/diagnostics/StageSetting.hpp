#pragma once
// What the observers of a stage are made from (diagnostics/Observer.hpp):
// the simulation, the scene, where the stage writes, the checkpoint it goes
// on from, and what the stage loop gives them (app/StageLoop.hpp).
#include <functional>
#include <memory>
#include <string>

#include "diagnostics/Observer.hpp"
#include "scene/SceneConfig.hpp"

namespace poresph {

template <class Sim>
struct StageSetting {
  Sim& sim;
  const SceneConfig& scene;            // the stage's (its spacing and force)
  std::string output_dir, suffix;      // the stage's files are output_dir/NAME + suffix + .EXT
  const RunState* restored;            // the checkpoint the stage goes on from, or null
  bool continuing;                     // a restart in the run's own directory
  bool finest;                         // the last level of a ladder (or the only one)
  bool warm_started;                   // starts from the stage before it
  int force_axis;                      // the one axis the body force points along, or -1
  int stage_axis;                      // the axis a tensor stage drives (Stage::drive_axis), -1: the scene's force
  long long check_interval;            // steps between the probes' checks
  double acoustic_time;                // L / c, over which a warm start is judged
  double porosity;                     // of the scene's solid
  HealthRecord earlier_health;         // what the run had seen before this stage
  std::function<void(bool)> write_checkpoint;  // checkpoint.h5 of the run now (rates valid?)
  bool show_progress;                  // a progress line on this process
  std::string progress_label;          // "[level 2/3] [F along x] "
  long long last_step;                 // of the time loop
  std::function<ProgressStatus()> progress_status;  // from every observer (Observer::status)
};

template <class Sim>
using ObserverMaker = std::unique_ptr<Observer<Sim>> (*)(const StageSetting<Sim>&);

}  // namespace poresph
