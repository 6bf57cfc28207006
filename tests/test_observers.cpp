// The observers a stage's loop is given (app/StageObservers.hpp): which of
// them a scene gets, probes before writers, and what they report into the
// stage's observations.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "Scenes.hpp"
#include "TestSpaces.hpp"
#include "app/Simulation.hpp"
#include "app/StageObservers.hpp"
#include "io/ProgressLine.hpp"

namespace poresph {
namespace {

template <class Space>
class ObserverFactoryTest : public ::testing::Test {};
TYPED_TEST_SUITE(ObserverFactoryTest, testing::ExecutionSpaces);

template <class Sim>
struct Made {
  std::vector<std::unique_ptr<Observer<Sim>>> observers;
  int probes = 0, writers = 0;
  bool writer_before_probe = false;
};

// Every maker of the list on one setting, as StageLoop calls them.
template <class Sim>
Made<Sim> make_all(const StageSetting<Sim>& setting) {
  Made<Sim> made;
  for (const auto make : stage_observers<2, Sim>()) {
    auto observer = make(setting);
    if (!observer) continue;
    if (observer->writes()) ++made.writers;
    else made.writer_before_probe = made.writer_before_probe || made.writers > 0, ++made.probes;
    made.observers.push_back(std::move(observer));
  }
  return made;
}

template <class Sim>
StageSetting<Sim> setting_of(Sim& sim, const SceneConfig& scene, const std::string& dir) {
  int axis = -1;
  for (int d = 0; d < 2; ++d)
    if (scene.body_force[d] != 0) axis = d;
  return StageSetting<Sim>{sim,  scene, dir,   "",  nullptr, false, true, false, axis, -1, 10, 1.0, 1.0,
                           HealthRecord{}, [](bool) {}, false, "", 1000, []() { return ProgressStatus{}; }};
}

// A channel marched: the profile probe, the health watch and the
// permeability probe, then four writers (the field frames, checkpoints, the
// progress line and, the channel having walls, the forces on them); a
// channel solved for its steady state: no profile probe (it has no
// start-up flow to compare).
TYPED_TEST(ObserverFactoryTest, AChannelGetsItsProbesAndWriters) {
  using Sim = Simulation<2, TypeParam>;
  const std::string dir = ::testing::TempDir() + "/poresph_observers";
  std::filesystem::create_directories(dir);
  SceneConfig scene = testing::channel(10);
  scene.body_force = {1e-4, 0, 0};
  scene.profile_sample_times = {0.5};
  Sim sim(scene);
  const auto marched = make_all(setting_of(sim, scene, dir));
  EXPECT_EQ(marched.probes, 3);
  EXPECT_EQ(marched.writers, 4);
  EXPECT_FALSE(marched.writer_before_probe) << "probes run before writers";
  SceneConfig solved_scene = scene;
  solved_scene.steady_solver = true;
  const auto solved = make_all(setting_of(sim, solved_scene, dir));
  EXPECT_EQ(solved.probes, 2);

  // What they report: the channel's profiles and k once sampled.
  for (auto& o : marched.observers) o->at_end(sim);
  StageObservations observed;
  for (const auto& o : marched.observers) o->report(observed);
  EXPECT_TRUE(observed.channel);
  EXPECT_EQ(observed.profile_samples.size(), 1u) << "the end's sample";
  EXPECT_TRUE(observed.has_permeability);
  ProgressStatus status;
  for (const auto& o : marched.observers) o->status(status);
  EXPECT_TRUE(status.has_permeability);
  std::filesystem::remove_all(dir);
}

// A scene without a single driven axis measures no k: no permeability probe.
TYPED_TEST(ObserverFactoryTest, NoForceNoPermeabilityProbe) {
  using Sim = Simulation<2, TypeParam>;
  const std::string dir = ::testing::TempDir() + "/poresph_observers_box";
  std::filesystem::create_directories(dir);
  SceneConfig scene = testing::periodic_box(2, 10);
  Sim sim(scene);
  const auto made = make_all(setting_of(sim, scene, dir));
  EXPECT_EQ(made.probes, 1) << "the health watch only";
  StageObservations observed;
  for (const auto& o : made.observers) o->report(observed);
  EXPECT_FALSE(observed.has_permeability);
  EXPECT_FALSE(observed.channel);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace poresph

// The progress line's ETA of a steady solve's Newton step: the time to its
// end at the rate the step has gone so far, 0 once there, none before the
// residual has fallen.
TEST(ProgressLine, GeometricEtaFollowsTheStepsOwnRate) {
  using poresph::geometric_eta;
  // A decade in 10 s; a decade to go: 10 s more.
  EXPECT_NEAR(geometric_eta(1e-3, 0.0, 1e-4, 10.0, 1e-5), 10.0, 1e-9);
  // The same fall taking 100 s (a step that crawls): 100 s more.
  EXPECT_NEAR(geometric_eta(1e-3, 0.0, 1e-4, 100.0, 1e-5), 100.0, 1e-9);
  // Below the step's end: done, whatever the rate.
  EXPECT_EQ(geometric_eta(1e-3, 0.0, 1e-6, 10.0, 1e-5), 0.0);
  // Not yet fallen, or no time passed: no rate, no ETA.
  EXPECT_TRUE(std::isnan(geometric_eta(1e-3, 0.0, 1e-3, 10.0, 1e-5)));
  EXPECT_TRUE(std::isnan(geometric_eta(1e-3, 5.0, 1e-4, 5.0, 1e-5)));
}

// The anchor of the ETA's rate moves on with the window: after a fall of a
// decade in the first 20 s and none in the next 40, the rate is taken over
// the last 20 to 40 s, where nothing fell (no ETA), not over the whole step.
TEST(ProgressLine, RecentAnchorTakesTheRateOfTheLastWindows) {
  poresph::RecentAnchor anchor;
  anchor.restart(1e-3, 0.0);
  anchor.update(1e-4, 20.0);  // a window passed: the anchor is still the start
  EXPECT_EQ(anchor.value, 1e-3);
  EXPECT_EQ(anchor.seconds, 0.0);
  anchor.update(1e-4, 30.0);  // within the window: nothing moves
  EXPECT_EQ(anchor.seconds, 0.0);
  anchor.update(1e-4, 40.0);  // the next: the anchor is where it stood at 20 s
  EXPECT_EQ(anchor.value, 1e-4);
  EXPECT_EQ(anchor.seconds, 20.0);
  EXPECT_TRUE(std::isnan(poresph::geometric_eta(anchor.value, anchor.seconds, 1e-4, 60.0, 1e-5)));
  anchor.restart(2e-5, 60.0);  // a new step starts afresh
  EXPECT_EQ(anchor.seconds, 60.0);
}
