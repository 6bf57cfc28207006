#pragma once
// The observers a stage's loop may have (diagnostics/Observer.hpp), in the
// order they run: probes measure (and may stop the loop), writers write
// after them. Each is made by its own make(setting), which gives none when
// the stage does not need it. A new observer is its file and one line here.
#include <vector>

#include "diagnostics/ChannelProbe.hpp"
#include "diagnostics/HealthWatch.hpp"
#include "diagnostics/PermeabilityProbe.hpp"
#include "diagnostics/PhaseProbe.hpp"
#include "diagnostics/StageSetting.hpp"
#include "io/BalanceHistory.hpp"
#include "io/Checkpoints.hpp"
#include "io/FieldFrames.hpp"
#include "io/GrainsHistory.hpp"
#include "io/PhasesHistory.hpp"
#include "io/ProgressLine.hpp"
#include "io/SurfaceForcesFile.hpp"

namespace poresph {

template <int Dim, class Sim>
const std::vector<ObserverMaker<Sim>>& stage_observers() {
  static const std::vector<ObserverMaker<Sim>> makers = {
      &ChannelProbe<Sim>::make,  &HealthWatch<Sim>::make, &PermeabilityProbe<Dim, Sim>::make, &PhaseProbe<Sim>::make,
      &FieldFrames<Dim, Sim>::make, &Checkpoints<Sim>::make, &ProgressObserver<Sim>::make,
      &SurfaceForcesFile<Dim, Sim>::make, &GrainsHistory<Dim, Sim>::make, &BalanceHistory<Sim>::make,
      &PhasesHistory<Sim>::make,
  };
  return makers;
}

}  // namespace poresph
