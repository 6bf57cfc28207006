#pragma once
// The output directory of a run from the command line: decided before any
// work and claimed only once the set-up has succeeded, so that a refused run
// writes nothing; a directory holding another run's results is never mixed
// with a new one's (--overwrite removes the old run's files first), and a
// restart from the checkpoint in the directory continues that run there.
#include <string>
#include <vector>

namespace poresph {

// Whether a file name (no directory) is one a PoreSPH run writes:
// summary.json, parameters_used.xml, checkpoint.h5, fields_*.h5, *.xmf,
// permeability_history*.csv, profiles.csv, particles*.csv, and their
// temporary .tmp names. Other files are the user's and are left alone.
bool is_run_output(const std::string& name);

struct OutputDirectoryPlan {
  std::string path;
  bool continues = false;              // --restart of the checkpoint in this directory
  std::vector<std::string> old_files;  // another run's results (names), removed by prepare()
};

// Looks at `dir` and decides what the run may do with it; writes nothing.
// Throws ParameterError if `dir` exists but is not a directory, if it holds
// another run's results and `overwrite` is false, or if --overwrite would
// remove the checkpoint the run restarts from.
OutputDirectoryPlan plan_output_directory(const std::string& dir, const std::string& restart_file, bool overwrite);

// On one process: removes the old run's files, creates the directory.
void prepare_output_directory(const OutputDirectoryPlan& plan);

// A run continued from its checkpoint: removes the field files
// fields<suffix>_<step>.h5 whose step is not among the checkpoint's frames
// (written after it, or at the end of the run it continues past), and those
// of the later drive axes of a Permeability/Tensor run (suffix "_x": "_y"
// and "_z"), so that no frame of the first attempt stays beside the
// continued run's.
void remove_other_frames(const std::string& dir, const std::string& suffix, const std::vector<double>& frame_steps);

}  // namespace poresph
