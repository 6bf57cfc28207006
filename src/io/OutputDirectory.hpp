#pragma once
// The output directory of a run from the command line. It is claimed for
// the run before any work (an exclusive lock that the system releases when
// the process ends, however it ends), so that two runs never write into one
// directory; a run refused on the way gives it back as it found it. Another
// run's results in it are never mixed with a new one's (--overwrite removes
// them first), and a restart from the checkpoint in the directory continues
// that run there.
#include <optional>
#include <string>
#include <vector>

namespace poresph {

// The suffix of the files of one stage of a run (app/RunPlan.hpp): "_x",
// "_y" or "_z" for the drive axis of a Permeability/Tensor run, then
// "_level<N>" for a level of a resolution ladder other than the finest, or
// "_half_force" for the repeat at half the body force. The one place the
// names are made and read back (is_run_output), so that they cannot drift
// apart.
std::string stage_suffix(int drive_axis, int level, int levels, bool half_force);

// A file name (no directory) a PoreSPH run writes, taken apart.
struct RunFile {
  std::string stem;    // "fields", "permeability_history", "summary", ...
  std::string suffix;  // the stage's suffix (stage_suffix), "" for the run's own files
  std::string extension;  // ".csv", ".xmf", ".h5", ...
  long long step = -1;  // of a field file
  bool temporary = false;  // NAME.tmp, a file being written
};

// Whether `name` is one a run writes: summary.json, parameters_used.xml,
// checkpoint.h5, grains_used.txt, and per stage (any stage_suffix S)
// fieldsS_<step>.h5, particlesS.xmf, gridS.xmf, permeability_historyS.csv,
// profilesS.csv and particlesS.csv; each also with .tmp appended (written
// but not yet renamed). Other files are the user's and are left alone.
std::optional<RunFile> parse_run_output(const std::string& name);
bool is_run_output(const std::string& name);

// The lock file by which a run holds its output directory.
constexpr const char* kOutputLockName = ".poresph.lock";

struct OutputDirectoryPlan {
  std::string path;
  bool continues = false;              // --restart of the checkpoint in this directory
  std::vector<std::string> old_files;  // another run's results (names), removed by prepare()
};

// Why `path` cannot be used as an output directory, in words that say what
// to fix, or "": a symbolic link that leads nowhere or in a loop, something
// that is not a directory, a parent that is a file, a path that cannot be
// created (no permission, a read-only file system, a name too long). Looks
// only; writes nothing.
std::string output_path_problem(const std::string& dir);

// Looks at `dir` and decides what the run may do with it; writes nothing.
// Throws ParameterError if `dir` exists but is not a directory, if it holds
// another run's results and `overwrite` is false, or if --overwrite would
// remove the checkpoint the run restarts from.
OutputDirectoryPlan plan_output_directory(const std::string& dir, const std::string& restart_file, bool overwrite);

// The exclusive claim of a run on its output directory: the directory (and
// any missing parent) is created, and kOutputLockName in it is locked with
// flock(2), which the system releases when the process ends, a kill
// included. A second run that finds the lock held is refused. The lock
// file names the holder (process, machine, start) for the message.
class OutputClaim {
 public:
  OutputClaim() = default;
  OutputClaim(const OutputClaim&) = delete;
  OutputClaim& operator=(const OutputClaim&) = delete;
  ~OutputClaim();

  // Claims `dir`; throws ParameterError saying why it cannot (in use by
  // another run, or a path that cannot be created), having left the file
  // system as it found it.
  void claim(const std::string& dir);
  bool held() const { return fd_ >= 0; }
  // The run has written into the directory: it stays, whatever follows.
  void written() { written_ = true; }
  // Gives the directory back: removes the lock file, and if the run wrote
  // nothing, the directories the claim created.
  void release();

 private:
  std::string dir_, lock_path_;
  std::vector<std::string> created_;  // directories made by claim(), outermost first
  int fd_ = -1;
  bool written_ = false;
};

// On one process, once the run has set up: removes the old run's files, and
// creates the directory if it does not exist yet.
void prepare_output_directory(const OutputDirectoryPlan& plan);

// A run continued from its checkpoint in its own directory: removes what
// the first attempt wrote after that checkpoint, so that nothing of it stays
// beside the continued run's files: the field files of the checkpoint's
// stage (suffix `suffix`) whose step is not among `frame_steps`, and every
// file of the stages after it (`later_suffixes`: their histories, frames,
// descriptions and particle files), which the continued run writes anew.
void remove_files_after_checkpoint(const std::string& dir, const std::string& suffix,
                                   const std::vector<double>& frame_steps,
                                   const std::vector<std::string>& later_suffixes);

}  // namespace poresph
