// poresph SCENE.xml [--set "Sublist/Parameter Name=value" ...] [--output DIR]
#include <Kokkos_Core.hpp>
#include <mpi.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "app/Run.hpp"
#include "app/SceneCheck.hpp"
#include "app/Simulation.hpp"
#include "io/Summary.hpp"
#include "io/Parameters.hpp"

namespace {

constexpr const char* kUsage =
    "usage: poresph SCENE.xml [--set \"Sublist/Parameter Name=value\"]... [--output DIR] [--restart CHECKPOINT.h5]\n"
    "       poresph --help-parameters    every scene parameter with its default and documentation\n"
    "--restart continues the run saved in a checkpoint (Output/Checkpoint Interval, Output/Final Checkpoint)\n"
    "with the scene's parameters; on as many processes as wrote it, bit for bit.\n"
    "--inject-nan STEP makes step STEP end with a NaN velocity, to test the failure path.\n"
    "Exit status: 0 done, 1 error, 2 bad input, 3 the run failed (a checkpoint of the last good state\n"
    "was written), 128 + signal after SIGINT/SIGTERM (a checkpoint was written).\n"
    "Kokkos options (--kokkos-threads=N, ...) are passed on to Kokkos.\n";

struct CommandLine {
  std::string scene_file;
  std::vector<std::string> overrides;
  std::string output_dir;
  std::string restart_file;
  long long inject_nan_at_step = -1;
  bool help = false, help_parameters = false;
  std::vector<char*> kokkos_args;  // argv[0] and every --kokkos-* option
};

// Our options are read before Kokkos sees argv: Kokkos 3.4 would take a bare
// --help (or --threads=) as its own.
CommandLine parse_command_line(int argc, char** argv) {
  CommandLine cl;
  cl.kokkos_args.push_back(argv[0]);
  auto value_of = [&](int& i, const std::string& option) -> std::string {
    const std::string arg = argv[i];
    if (arg.size() > option.size() && arg[option.size()] == '=') return arg.substr(option.size() + 1);
    if (i + 1 >= argc) throw poresph::ParameterError(option + " needs a value");
    return argv[++i];
  };
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") cl.help = true;
    else if (arg == "--help-parameters") cl.help_parameters = true;
    else if (arg.rfind("--set", 0) == 0 && (arg.size() == 5 || arg[5] == '=')) cl.overrides.push_back(value_of(i, "--set"));
    else if (arg.rfind("--output", 0) == 0 && (arg.size() == 8 || arg[8] == '=')) cl.output_dir = value_of(i, "--output");
    else if (arg.rfind("--restart", 0) == 0 && (arg.size() == 9 || arg[9] == '=')) cl.restart_file = value_of(i, "--restart");
    else if (arg.rfind("--inject-nan", 0) == 0 && (arg.size() == 12 || arg[12] == '=')) {
      const std::string step = value_of(i, "--inject-nan");
      size_t used = 0;
      try {
        cl.inject_nan_at_step = std::stoll(step, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used == 0 || used != step.size() || cl.inject_nan_at_step < 1)
        throw poresph::ParameterError("--inject-nan needs a step number >= 1, not '" + step + "'");
    }
    else if (arg.rfind("--kokkos-", 0) == 0) cl.kokkos_args.push_back(argv[i]);
    else if (arg.rfind("-", 0) == 0) throw poresph::ParameterError("unknown option " + arg);
    else if (cl.scene_file.empty()) cl.scene_file = arg;
    else throw poresph::ParameterError("more than one scene file given: " + cl.scene_file + ", " + arg);
  }
  return cl;
}

// Processes of this run on this machine, for the memory check.
int processes_on_this_machine() {
  MPI_Comm machine;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &machine);
  int n = 1;
  MPI_Comm_size(machine, &n);
  MPI_Comm_free(&machine);
  return n;
}

int run(const CommandLine& cl, const Teuchos::ParameterList& parameters, const poresph::SceneConfig& scene,
        int rank) {

  poresph::RunOptions options;
  options.output_dir = cl.output_dir.empty() ? "poresph-" + scene.name : cl.output_dir;
  // Under mpiexec a rank's stdout is a pseudo-terminal even when the
  // launcher's output goes to a log: stay quiet there unless asked.
  const bool under_mpiexec = std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE");
  options.progress_on_terminal = isatty(fileno(stdout)) && !under_mpiexec;
  options.restart_file = cl.restart_file;
  options.inject_nan_at_step = cl.inject_nan_at_step;
  options.parameters_xml = poresph::parameters_to_xml(parameters);
  int ranks = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  if (rank == 0) {
    std::filesystem::create_directories(options.output_dir);
    // The list after defaults, and what ran it: enough to reproduce any output.
    poresph::write_file_atomically(
        options.output_dir + "/parameters_used.xml",
        "<!-- poresph " + std::string(PORESPH_VERSION) + "; backend " + poresph::backend_for(scene) + "; ranks " +
            std::to_string(ranks) + "; threads per rank " + std::to_string(poresph::threads_for(scene)) +
            (cl.restart_file.empty() ? "" : "; restarted from " + cl.restart_file) + " -->\n" +
            options.parameters_xml);
  }
  if (rank == 0)
    for (const auto& warning : scene.warnings) std::cerr << "poresph: warning: " << warning << "\n";
  MPI_Barrier(MPI_COMM_WORLD);  // the directory exists before any process writes into it
  poresph::install_stop_signal_handlers();
  const auto report = poresph::run_scene(scene, options);
  if (rank == 0)
    std::cout << "poresph: " << scene.name << ": " << report.steps << " steps to t = " << report.simulated_time
            << " s in " << report.wall_seconds << " s; summary in " << options.output_dir << "/summary.json\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  int status = 0;
  CommandLine cl;
  try {
    cl = parse_command_line(argc, argv);
  } catch (const std::exception& e) {
    if (rank == 0) std::cerr << "poresph: error: " << e.what() << "\n" << kUsage;
    MPI_Finalize();
    return 2;
  }
  // The scene is read and checked before Kokkos starts: Run/Threads configures it.
  Teuchos::RCP<Teuchos::ParameterList> parameters;
  poresph::SceneConfig scene;
  try {
    if (cl.help || cl.help_parameters) {
      if (rank == 0) {
        if (cl.help) std::cout << kUsage;
        else poresph::print_valid_parameters(std::cout);
      }
      MPI_Finalize();
      return 0;
    }
    if (cl.scene_file.empty()) throw poresph::ParameterError(std::string("no scene file given\n") + kUsage);
    parameters = poresph::read_parameters(cl.scene_file, cl.overrides);
    scene = poresph::scene_from_parameters(*parameters,
                                           std::filesystem::absolute(cl.scene_file).parent_path().string());
    int ranks = 1;
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    // What the run needs, before it allocates anything.
    poresph::check_scene(scene, ranks, poresph::memory_budget(scene, processes_on_this_machine()));
  } catch (const std::exception& e) {
    if (rank == 0) std::cerr << "poresph: error: " << e.what() << "\n";
    MPI_Finalize();
    return 2;
  }
  std::vector<char*> kokkos_args = cl.kokkos_args;
  std::string threads_arg = "--kokkos-threads=" + std::to_string(scene.threads);
  if (scene.threads > 0) kokkos_args.push_back(threads_arg.data());
  int kokkos_argc = static_cast<int>(kokkos_args.size());
  Kokkos::initialize(kokkos_argc, kokkos_args.data());
  try {
    status = run(cl, *parameters, scene, rank);
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
  MPI_Finalize();
  return status;
}
