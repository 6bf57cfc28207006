// poresph SCENE.xml [--set "Sublist/Parameter Name=value" ...] [--output DIR] [--restart FILE] [--overwrite]
#include <Kokkos_Core.hpp>
#include <mpi.h>
#include <unistd.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "app/Run.hpp"
#include "app/RunPlan.hpp"
#include "app/SceneCheck.hpp"
#include "core/StopRequest.hpp"
#include "geometry/Grains.hpp"
#include "app/Simulation.hpp"
#include "io/Checkpoint.hpp"
#include "io/Hdf5File.hpp"
#include "io/OutputDirectory.hpp"
#include "io/Parameters.hpp"
#include "scene/SceneBuilder.hpp"
#include "parallel/Communicator.hpp"
#include "io/Summary.hpp"
#include "io/TextValues.hpp"

namespace {

constexpr const char* kUsage =
    "usage: poresph SCENE.xml [--set \"Sublist/Parameter Name=value\"]... [--output DIR] [--restart CHECKPOINT.h5]\n"
    "                         [--overwrite]\n"
    "       poresph --help-parameters    every scene parameter with its default and documentation\n"
    "--output DIR (default poresph-NAME) must not hold another run's results (--overwrite removes them first),\n"
    "nor be in use by a run going on.\n"
    "--restart continues the run saved in a checkpoint (Output/Checkpoint Interval, Output/Final Checkpoint)\n"
    "with the scene's parameters; on as many processes as wrote it, bit for bit. Into the checkpoint's own\n"
    "directory it continues that run's files. The checkpoint must be of the same physics (cell, spacing, fluid,\n"
    "grains); a mismatch is refused, naming what differs.\n"
    "--inject-nan STEP makes step STEP end with a NaN velocity, to test the failure path.\n"
    "Exit status: 0 done, 1 error (I/O, MPI), 2 bad input or a refused run (nothing written), 3 the run failed\n"
    "(a checkpoint of the last good state was written), 4 a steady solve (Solver/Method) did not converge\n"
    "(its last state is in checkpoint.h5, summary.json says so), 128 + signal after SIGHUP (129), SIGINT (130), SIGPIPE\n"
    "(141) or SIGTERM (143), each with a checkpoint and summary.json.\n"
    "Kokkos options (--kokkos-threads=N, ...) are passed on to Kokkos. See docs/reliability.md.\n";

struct CommandLine {
  std::string scene_file;
  std::vector<std::string> overrides;
  std::string output_dir;
  std::string restart_file;
  bool overwrite = false;
  long long inject_nan_at_step = -1;
  bool help = false, help_parameters = false;
  std::vector<char*> kokkos_args;  // argv[0] and every --kokkos-* option
};

// Our options are read before Kokkos sees argv: Kokkos 3.4 would take a bare
// --help (or --threads=) as its own. Teuchos::CommandLineProcessor does not
// fit this interface (docs/building.md): it reads only --name=value, keeps
// the last of a repeated --set, and has no place for the scene file.
CommandLine parse_command_line(int argc, char** argv) {
  CommandLine cl;
  cl.kokkos_args.push_back(argv[0]);
  // --option VALUE or --option=VALUE; true if argv[i] is `option`.
  auto is = [&](int i, const std::string& option) {
    const std::string arg = argv[i];
    return arg.rfind(option, 0) == 0 && (arg.size() == option.size() || arg[option.size()] == '=');
  };
  auto value_of = [&](int& i, const std::string& option) -> std::string {
    const std::string arg = argv[i];
    if (arg.size() > option.size() && arg[option.size()] == '=') return arg.substr(option.size() + 1);
    if (i + 1 >= argc) throw poresph::ParameterError(option + " needs a value");
    return argv[++i];
  };
  auto once = [](std::string& slot, const std::string& option, const std::string& value) {
    if (!slot.empty()) throw poresph::ParameterError(option + " given twice: '" + slot + "' and '" + value + "'");
    if (value.empty()) throw poresph::ParameterError(option + " needs a non-empty value");
    slot = value;
  };
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") cl.help = true;
    else if (arg == "--help-parameters") cl.help_parameters = true;
    else if (arg == "--overwrite") cl.overwrite = true;
    else if (is(i, "--overwrite")) throw poresph::ParameterError("--overwrite takes no value");
    else if (is(i, "--set")) cl.overrides.push_back(value_of(i, "--set"));
    else if (is(i, "--output")) once(cl.output_dir, "--output", value_of(i, "--output"));
    else if (is(i, "--restart")) once(cl.restart_file, "--restart", value_of(i, "--restart"));
    else if (is(i, "--inject-nan")) {
      const std::string step = value_of(i, "--inject-nan");
      if (cl.inject_nan_at_step >= 0)
        throw poresph::ParameterError("--inject-nan given twice: '" + std::to_string(cl.inject_nan_at_step) +
                                      "' and '" + step + "'");
      const auto parsed = poresph::parse_number<long long>(step);
      if (!parsed.value || *parsed.value < 1)
        throw poresph::ParameterError("--inject-nan needs a step number >= 1, not '" + step + "'");
      cl.inject_nan_at_step = *parsed.value;
    }
    else if (arg.rfind("--kokkos-", 0) == 0) cl.kokkos_args.push_back(argv[i]);
    else if (arg.rfind("-", 0) == 0) throw poresph::ParameterError("unknown option " + arg);
    else if (cl.scene_file.empty()) cl.scene_file = arg;
    else throw poresph::ParameterError("more than one scene file given: " + cl.scene_file + ", " + arg);
  }
  return cl;
}

// Every process reaches the same verdict on a check some of them may see
// differently (the file system, a signal): the first failing process's
// message is everyone's, so that no process runs on alone into a collective.
std::string agree(const std::string& problem) { return poresph::Communicator().first_problem(problem); }

// Processes of this run on this machine, for the memory check.
int processes_on_this_machine() { return poresph::Communicator().on_this_machine(); }

int run(const CommandLine& cl, const Teuchos::ParameterList& parameters, const poresph::SceneConfig& scene,
        const poresph::OutputDirectoryPlan& plan, poresph::OutputClaim& claim, double seconds_before, int rank) {
  poresph::RunOptions options;
  options.output_dir = plan.path;
  // Under mpiexec a rank's stdout is a pseudo-terminal even when the
  // launcher's output goes to a log: stay quiet there unless asked.
  const bool under_mpiexec = std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE");
  options.progress_on_terminal = isatty(fileno(stdout)) && !under_mpiexec;
  options.restart_file = cl.restart_file;
  options.inject_nan_at_step = cl.inject_nan_at_step;
  options.parameters_xml = poresph::parameters_to_xml(parameters);
  options.setup_seconds_before = seconds_before;
  int ranks = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  // Claimed once the run has set up, so that a run refused on the way writes nothing.
  options.prepare_output = [&]() {
    if (rank == 0) {
      claim.written();  // from here on the directory holds this run, whatever follows
      poresph::prepare_output_directory(plan);
      // The list after defaults, and what ran it: enough to reproduce any output.
      poresph::write_file_atomically(
          plan.path + "/parameters_used.xml",
          "<!-- poresph " + std::string(PORESPH_VERSION) + "; backend " + poresph::backend_for(scene) + "; ranks " +
              std::to_string(ranks) + "; threads per rank " + std::to_string(poresph::threads_for(scene)) +
              (cl.restart_file.empty() ? "" : "; restarted from " + cl.restart_file) + " -->\n" +
              options.parameters_xml);
      // The grains as a grain file: a random pack is repeated from it with Grains/File.
      if (!scene.grains.empty())
        poresph::write_file_atomically(plan.path + "/grains_used.txt", poresph::grains_used_text(scene));
    }
    MPI_Barrier(MPI_COMM_WORLD);  // the directory exists before any process writes into it
  };
  if (rank == 0) {
    if (!scene.grains_note.empty()) std::cout << "poresph: " << scene.grains_note << "\n";
    for (const auto& warning : scene.warnings) std::cerr << "poresph: warning: " << warning << "\n";
  }
  const auto report = poresph::run_scene(scene, options);
  if (rank == 0) {
    // What the run itself found (an unsteady k, levels outside the asymptotic range, inertia),
    // after the scene's own warnings, which were said above.
    for (size_t w = scene.warnings.size(); w < report.warnings.size(); ++w)
      std::cerr << "poresph: warning: " << report.warnings[w] << "\n";
    if (report.solver.method == "steady")
      std::cout << "poresph: " << scene.name << ": steady solve " << (report.solver.converged ? "converged" : "NOT converged")
                << " (" << report.solver.nonlinear_iterations << " Newton, " << report.solver.linear_iterations
                << " linear iterations, relative residual " << report.solver.residual << ") in " << report.wall_seconds
                << " s; summary in " << options.output_dir << "/summary.json\n";
    else
      std::cout << "poresph: " << scene.name << ": " << report.steps << " steps to t = " << report.simulated_time
                << " s in " << report.wall_seconds << " s; summary in " << options.output_dir << "/summary.json\n";
  }
  // A steady solve short of its tolerance wrote its state and summary, and says so.
  return report.solver.method == "steady" && !report.solver.converged ? 4 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  const auto start = std::chrono::steady_clock::now();
#ifdef __GLIBC__
  // Arrays of a MiB and more (the particles' Views) in mappings of their
  // own, unmapped when freed. glibc otherwise raises this threshold to the
  // size of the largest mapped block freed (the lattice seeds' growth takes
  // it to 32 MiB), after which the Views come from the heap, and those freed
  // in set-up (each field's copy before the ghosts) stay resident as holes:
  // 11 MB at the peak of the simple cubic array at 80 a side
  // (docs/performance.md, "Memory per particle").
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
#endif
  MPI_Init(&argc, &argv);
  // At once: a signal during set-up (reading a large scene) must stop the run, not be lost or end it unsaved.
  poresph::install_stop_signal_handlers();
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  CommandLine cl;
  try {
    cl = parse_command_line(argc, argv);
  } catch (const std::exception& e) {
    if (rank == 0) std::cerr << "poresph: error: " << e.what() << "\n" << kUsage;
    MPI_Finalize();
    return 2;
  }
  if (cl.help || cl.help_parameters) {
    if (rank == 0) {
      if (cl.help) std::cout << kUsage;
      else poresph::print_valid_parameters(std::cout);
    }
    MPI_Finalize();
    return 0;
  }
  // Everything that can refuse the run is checked before Kokkos starts (Run/Threads configures it) and
  // before anything is written: the scene, what it needs, the checkpoint, the output directory.
  Teuchos::RCP<Teuchos::ParameterList> parameters;
  poresph::SceneConfig scene;
  poresph::OutputDirectoryPlan plan;
  std::string problem;
  int interrupted = 0;  // a signal that stopped the reading of the scene (a random pack being grown)
  try {
    if (cl.scene_file.empty()) throw poresph::ParameterError(std::string("no scene file given\n") + kUsage);
    parameters = poresph::read_parameters(cl.scene_file, cl.overrides);
    scene = poresph::scene_from_parameters(*parameters,
                                           std::filesystem::absolute(cl.scene_file).parent_path().string());
    const int on_machine = processes_on_this_machine();
    poresph::check_scene(scene, size, poresph::memory_budget(scene, on_machine));
  } catch (const poresph::SetupInterrupted& e) {
    problem = "stopped by " + poresph::signal_name(e.signal_number) + " " + e.what();
    interrupted = e.signal_number;
  } catch (const std::exception& e) {
    problem = e.what();
  }
  problem = agree(problem);
  interrupted = poresph::Communicator().max(interrupted);
  if (problem.empty() && !cl.restart_file.empty()) {
    // Every process opens the checkpoint, and they agree on what they found.
    std::string why = poresph::hdf5_file_problem(cl.restart_file);
    if (!why.empty()) why = "--restart " + cl.restart_file + ": " + why;
    problem = agree(why);
    if (problem.empty()) {
      // The checkpoint must be of this physics, and undamaged in what it says of itself.
      try {
        const auto info = poresph::read_checkpoint_info(cl.restart_file, MPI_COMM_WORLD);
        // Against the stage it is of: a ladder's coarser level has its own spacing, an axis of a tensor
        // run or the Darcy check its own force.
        const auto stages = poresph::plan_run(scene);
        const auto stage = static_cast<long long>(info.state.stage);
        if (stage < 0 || stage >= static_cast<long long>(stages.size()))
          throw poresph::ParameterError(
              "--restart " + cl.restart_file + ": the checkpoint is of stage " + std::to_string(stage + 1) +
              " of a run, this scene's run has " + std::to_string(stages.size()) +
              " (Convergence/Levels, Permeability/Tensor, Permeability/Linearity Check differ)");
        const auto stage_scene = poresph::stage_scene(scene, stages[static_cast<size_t>(stage)]);
        const auto derived = poresph::derive_parameters(stage_scene);
        poresph::check_checkpoint_matches(
            info, cl.restart_file,
            poresph::physics_fingerprint(stage_scene, derived.time_step, derived.sound_speed));
      } catch (const std::exception& e) {
        problem = e.what();
      }
      problem = agree(problem);
    }
  }
  // The output directory: claimed for this run alone (rank 0 holds the
  // lock), then looked at: under the claim, no other run writes into it.
  poresph::OutputClaim claim;
  if (problem.empty()) {
    const std::string dir = cl.output_dir.empty() ? "poresph-" + scene.name : cl.output_dir;
    try {
      if (rank == 0) claim.claim(dir);
    } catch (const std::exception& e) {
      problem = e.what();
    }
    problem = agree(problem);
    if (problem.empty()) {
      try {
        plan = poresph::plan_output_directory(dir, cl.restart_file, cl.overwrite);
      } catch (const std::exception& e) {
        problem = e.what();
      }
      problem = agree(problem);
    }
  }
  if (!problem.empty()) {
    if (rank == 0) std::cerr << (interrupted ? "poresph: " : "poresph: error: ") << problem << "\n";
    claim.release();
    MPI_Finalize();
    return interrupted ? 128 + interrupted : 2;
  }
  std::vector<char*> kokkos_args = cl.kokkos_args;
  std::string threads_arg = "--kokkos-threads=" + std::to_string(scene.threads);
  if (scene.threads > 0) kokkos_args.push_back(threads_arg.data());
  int kokkos_argc = static_cast<int>(kokkos_args.size());
  Kokkos::initialize(kokkos_argc, kokkos_args.data());
  int status = 0;
  try {
    status = run(cl, *parameters, scene, plan, claim,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), rank);
  } catch (const poresph::ParameterError& e) {
    if (rank == 0) std::cerr << "poresph: error: " << e.what() << "\n";
    status = 2;
  } catch (const poresph::SimulationFailure& e) {
    if (rank == 0) std::cerr << "poresph: the run failed: " << e.what() << "\n";
    status = 3;
  } catch (const poresph::RunInterrupted& e) {
    if (rank == 0) std::cerr << "poresph: " << e.what() << "\n";
    status = 128 + e.signal_number;
  } catch (const std::invalid_argument& e) {  // a scene the solver refuses before any work
    if (rank == 0) std::cerr << "poresph: error: " << e.what() << "\n";
    status = 2;
  } catch (const std::exception& e) {
    if (rank == 0) std::cerr << "poresph: error: " << e.what() << "\n";
    status = 1;
  }
  Kokkos::finalize();
  // A run refused during its set-up (status 2) wrote nothing: the directories its claim made go too.
  claim.release();
  if (poresph::hdf5_left_broken()) {
    // HDF5 would crash closing the file that failed to close (see Hdf5File.hpp) and turn exit status 1 into a
    // segmentation fault; everything there was to write has been written or reported.
    std::fflush(nullptr);
    std::_Exit(status);
  }
  MPI_Finalize();
  return status;
}
