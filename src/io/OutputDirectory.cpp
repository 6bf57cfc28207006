#include "io/OutputDirectory.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <stdexcept>
#include <system_error>

#include "io/Parameters.hpp"

namespace poresph {
namespace fs = std::filesystem;

namespace {

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// "" or "_x", "_y", "_z": the drive axis of a Permeability/Tensor run.
bool axis_suffix(const std::string& s) { return s.empty() || (s.size() == 2 && s[0] == '_' && s[1] >= 'x' && s[1] <= 'z'); }

// NAME + axis suffix + EXTENSION.
bool named(const std::string& name, const std::string& stem, const std::string& extension) {
  if (name.rfind(stem, 0) != 0 || !ends_with(name, extension) || name.size() < stem.size() + extension.size())
    return false;
  return axis_suffix(name.substr(stem.size(), name.size() - stem.size() - extension.size()));
}

}  // namespace

bool is_run_output(const std::string& file) {
  const std::string name = ends_with(file, ".tmp") ? file.substr(0, file.size() - 4) : file;
  if (name == "summary.json" || name == "parameters_used.xml" || name == "checkpoint.h5" || name == "profiles.csv" ||
      name == "grains_used.txt")
    return true;
  if (named(name, "permeability_history", ".csv") || named(name, "particles", ".csv") ||
      named(name, "particles", ".xmf") || named(name, "grid", ".xmf"))
    return true;
  // fields[_x]_<step>.h5
  if (name.rfind("fields", 0) != 0 || !ends_with(name, ".h5")) return false;
  const std::string middle = name.substr(6, name.size() - 6 - 3);  // "[_x]_000000100"
  const size_t underscore = middle.rfind('_');
  if (underscore == std::string::npos || underscore + 1 == middle.size()) return false;
  const std::string digits = middle.substr(underscore + 1);
  return axis_suffix(middle.substr(0, underscore)) &&
         std::all_of(digits.begin(), digits.end(), [](unsigned char c) { return std::isdigit(c); });
}

OutputDirectoryPlan plan_output_directory(const std::string& dir, const std::string& restart_file, bool overwrite) {
  OutputDirectoryPlan plan;
  plan.path = dir;
  std::error_code error;
  const auto status = fs::status(dir, error);
  if (!fs::exists(status)) return plan;  // created when the run has set up
  if (!fs::is_directory(status))
    throw ParameterError("--output " + dir + ": it exists and is not a directory");
  for (const auto& entry : fs::directory_iterator(dir, error)) {
    const std::string name = entry.path().filename().string();
    if (is_run_output(name)) plan.old_files.push_back(name);
  }
  if (error) throw ParameterError("--output " + dir + ": cannot list it: " + error.message());
  std::sort(plan.old_files.begin(), plan.old_files.end());
  // The run saved in this directory's checkpoint goes on here: its files are this run's own.
  if (!restart_file.empty()) {
    const auto from = fs::absolute(restart_file).parent_path();
    plan.continues = fs::equivalent(from, dir, error);
  }
  if (plan.continues) {
    if (overwrite)
      throw ParameterError("--overwrite would remove " + restart_file +
                           ", the checkpoint --restart continues from; continue in " + dir +
                           " without --overwrite, or restart into another directory");
    plan.old_files.clear();
    return plan;
  }
  if (!plan.old_files.empty() && !overwrite) {
    std::string listed;
    const size_t shown = std::min<size_t>(plan.old_files.size(), 4);
    for (size_t k = 0; k < shown; ++k) listed += (k ? ", " : "") + plan.old_files[k];
    if (plan.old_files.size() > shown) listed += ", ... (" + std::to_string(plan.old_files.size()) + " files)";
    throw ParameterError("--output " + dir + " holds the results of another run (" + listed +
                         "); choose another directory, or add --overwrite to remove them first" +
                         (restart_file.empty() ? "" : " (a run continues in place only from the checkpoint.h5 "
                                                      "of its own directory)"));
  }
  return plan;
}

void remove_other_frames(const std::string& dir, const std::string& suffix, const std::vector<double>& frame_steps) {
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(dir, error)) {
    const std::string name = entry.path().filename().string();
    if (!is_run_output(name) || name.rfind("fields", 0) != 0 || !ends_with(name, ".h5")) continue;
    const std::string middle = name.substr(6, name.size() - 6 - 3);  // "[_x]_000000100"
    const size_t underscore = middle.rfind('_');
    const std::string axis = middle.substr(0, underscore);
    const double step = static_cast<double>(std::stoll(middle.substr(underscore + 1)));
    const bool listed = std::find(frame_steps.begin(), frame_steps.end(), step) != frame_steps.end();
    const bool later_axis = !suffix.empty() && !axis.empty() && axis > suffix;
    if ((axis == suffix && !listed) || later_axis) fs::remove(entry.path(), error);
  }
}

void prepare_output_directory(const OutputDirectoryPlan& plan) {
  for (const auto& name : plan.old_files) {
    std::error_code error;
    fs::remove(fs::path(plan.path) / name, error);
    if (error)
      throw std::runtime_error("--overwrite: cannot remove " + (fs::path(plan.path) / name).string() + ": " +
                               error.message());
  }
  std::error_code error;
  fs::create_directories(plan.path, error);
  if (error) throw std::runtime_error("cannot create the output directory " + plan.path + ": " + error.message());
}

}  // namespace poresph
