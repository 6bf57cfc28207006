#include "io/OutputDirectory.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <stdexcept>
#include <system_error>

#include "io/Parameters.hpp"
#include "io/PathCheck.hpp"

namespace poresph {
namespace fs = std::filesystem;

namespace {

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

bool all_digits(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c); });
}

// Whether `s` is a suffix stage_suffix makes: [_x|_y|_z][_level<N>|_half_force].
bool is_stage_suffix(std::string s) {
  if (s.size() >= 2 && s[0] == '_' && s[1] >= 'x' && s[1] <= 'z' && (s.size() == 2 || s[2] == '_')) s.erase(0, 2);
  if (s.empty() || s == "_half_force") return true;
  return s.rfind("_level", 0) == 0 && all_digits(s.substr(6));
}

// The files of one stage: STEM + suffix + EXTENSION.
struct StageFile {
  const char* stem;
  const char* extension;
};
constexpr StageFile kStageFiles[] = {{"permeability_history", ".csv"}, {"profiles", ".csv"}, {"particles", ".csv"},
                                     {"particles", ".xmf"},           {"grid", ".xmf"},       {"surface_forces", ".csv"},
                                     {"grains_history", ".csv"},     {"balance_history", ".csv"},
                                     {"phases_history", ".csv"}};
// The run's own files, one of each.
constexpr const char* kRunFiles[] = {"summary.json", "parameters_used.xml", "checkpoint.h5", "grains_used.txt",
                                     "drainage.csv"};

}  // namespace

std::string stage_suffix(int drive_axis, int level, int levels, bool half_force) {
  std::string suffix = drive_axis >= 0 ? std::string("_") + "xyz"[drive_axis] : "";
  if (half_force) return suffix + "_half_force";
  if (level < levels - 1) suffix += "_level" + std::to_string(level);
  return suffix;
}

std::optional<RunFile> parse_run_output(const std::string& file) {
  RunFile parsed;
  parsed.temporary = ends_with(file, ".tmp");
  const std::string name = parsed.temporary ? file.substr(0, file.size() - 4) : file;
  for (const char* own : kRunFiles)
    if (name == own) {
      parsed.stem = name.substr(0, name.find('.'));
      parsed.extension = name.substr(name.find('.'));
      return parsed;
    }
  for (const auto& kind : kStageFiles) {
    const std::string stem = kind.stem, extension = kind.extension;
    if (name.rfind(stem, 0) != 0 || !ends_with(name, extension) || name.size() < stem.size() + extension.size())
      continue;
    const std::string suffix = name.substr(stem.size(), name.size() - stem.size() - extension.size());
    if (!is_stage_suffix(suffix)) continue;
    parsed.stem = stem, parsed.suffix = suffix, parsed.extension = extension;
    return parsed;
  }
  // fields<suffix>_<step>.h5
  if (name.rfind("fields", 0) != 0 || !ends_with(name, ".h5")) return std::nullopt;
  const std::string middle = name.substr(6, name.size() - 6 - 3);  // "<suffix>_000000100"
  const size_t underscore = middle.rfind('_');
  if (underscore == std::string::npos) return std::nullopt;
  const std::string digits = middle.substr(underscore + 1), suffix = middle.substr(0, underscore);
  if (!all_digits(digits) || digits.size() > 18 || !is_stage_suffix(suffix)) return std::nullopt;
  parsed.stem = "fields", parsed.suffix = suffix, parsed.extension = ".h5", parsed.step = std::stoll(digits);
  return parsed;
}

bool is_run_output(const std::string& name) { return parse_run_output(name).has_value(); }

std::string output_path_problem(const std::string& dir) {
  struct stat st {};
  if (::stat(dir.c_str(), &st) == 0) {
    if (!S_ISDIR(st.st_mode)) return "it exists and is not a directory";
    if (::access(dir.c_str(), W_OK | X_OK) != 0)
      return std::string("the run cannot write in it: ") + std::strerror(errno) + "; choose another directory";
    return "";
  }
  const int error = errno;
  if (error == ENOENT) {
    struct stat link {};
    if (::lstat(dir.c_str(), &link) == 0 && S_ISLNK(link.st_mode))
      return "it is a symbolic link to '" + link_target(dir) + "', which does not exist: create that directory, " +
             "or remove the link, or choose another directory";
    // The nearest existing parent decides whether the rest can be made.
    fs::path parent = fs::absolute(dir).lexically_normal();
    for (const auto& part : parent)
      if (part.string().size() > NAME_MAX) return "the name '" + part.string() + "' is too long for the file system";
    while (parent.has_parent_path() && parent != parent.root_path()) {
      parent = parent.parent_path();
      if (::stat(parent.c_str(), &st) == 0) {
        if (!S_ISDIR(st.st_mode)) return "'" + parent.string() + "' is a file, so no directory can be made in it";
        if (::access(parent.c_str(), W_OK | X_OK) != 0)
          return "it cannot be created in '" + parent.string() + "': " + std::strerror(errno) +
                 "; choose another directory";
        return "";
      }
      if (errno != ENOENT) break;
      if (::lstat(parent.c_str(), &link) == 0 && S_ISLNK(link.st_mode))
        return "'" + parent.string() + "' is a symbolic link to '" + link_target(parent.string()) +
               "', which does not exist: create that directory, or choose another";
    }
    if (errno != ENOENT) return stat_problem(parent.string(), errno);
    return "";
  }
  if (error == ENOTDIR) return "a part of the path is a file, not a directory, so the directory cannot be made there";
  return stat_problem(dir, error) + "; choose another directory";
}

OutputDirectoryPlan plan_output_directory(const std::string& dir, const std::string& restart_file, bool overwrite) {
  OutputDirectoryPlan plan;
  plan.path = dir;
  const std::string problem = output_path_problem(dir);
  if (!problem.empty()) throw ParameterError("--output " + dir + ": " + problem);
  std::error_code error;
  const auto status = fs::status(dir, error);
  if (!fs::exists(status)) return plan;  // created when the run claims it
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

OutputClaim::~OutputClaim() { release(); }

void OutputClaim::claim(const std::string& dir) {
  dir_ = dir;
  if (const std::string problem = output_path_problem(dir); !problem.empty())
    throw ParameterError("--output " + dir + ": " + problem);
  auto undo = [&]() {
    for (auto it = created_.rbegin(); it != created_.rend(); ++it) ::rmdir(it->c_str());
    created_.clear();
  };
  // The missing directories, outermost first; one made at this moment by
  // another run is that run's, not to be removed by this one.
  std::vector<fs::path> missing;
  for (fs::path p = fs::path(dir).lexically_normal(); !p.empty(); p = p.parent_path()) {
    std::error_code error;
    if (fs::exists(fs::symlink_status(p, error)) || p == p.parent_path()) break;
    missing.push_back(p);
  }
  for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
    if (::mkdir(it->c_str(), 0777) == 0) {
      created_.push_back(it->string());
    } else if (errno != EEXIST) {
      const int error = errno;
      undo();
      throw ParameterError("--output " + dir + ": cannot create '" + it->string() + "': " + std::strerror(error) +
                           "; choose another directory");
    }
  }
  lock_path_ = dir + "/" + kOutputLockName;
  // A run that ends removes its lock file; one that opened the file just
  // before that holds a lock on a name that no longer exists, so the lock
  // counts only if the file locked is the one under the name.
  for (int attempt = 0; attempt < 100; ++attempt) {
    const int fd = ::open(lock_path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) {
      const int error = errno;
      undo();
      throw ParameterError("--output " + dir + ": the run cannot write in it (" + lock_path_ +
                           "): " + std::strerror(error) + "; choose another directory");
    }
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      // The holder names itself just after it takes the lock: a moment's wait for that.
      char holder[256] = {};
      ssize_t n = 0;
      for (int wait = 0; wait < 20 && n <= 0; ++wait) {
        if (wait > 0) ::usleep(5000);
        n = ::pread(fd, holder, sizeof holder - 1, 0);
      }
      ::close(fd);
      std::string who(holder, n > 0 ? static_cast<size_t>(n) : 0);
      while (!who.empty() && (who.back() == '\n' || who.back() == '\0')) who.pop_back();
      undo();  // nothing of ours is in it: only directories left empty are removed
      throw ParameterError("--output " + dir + " is in use by another run" + (who.empty() ? "" : " (" + who + ")") +
                           "; wait until it has ended, or choose another directory");
    }
    struct stat locked {}, named {};
    if (::fstat(fd, &locked) == 0 && ::stat(lock_path_.c_str(), &named) == 0 && locked.st_dev == named.st_dev &&
        locked.st_ino == named.st_ino) {
      fd_ = fd;
      break;
    }
    ::close(fd);
  }
  if (fd_ < 0) {
    undo();
    throw ParameterError("--output " + dir + ": could not lock " + lock_path_ + "; choose another directory");
  }
  char host[256] = "?";
  ::gethostname(host, sizeof host - 1);
  char started[32] = "";
  const std::time_t now = std::time(nullptr);
  std::tm local{};
  ::localtime_r(&now, &local);
  std::strftime(started, sizeof started, "%Y-%m-%d %H:%M:%S", &local);
  const std::string who = "process " + std::to_string(::getpid()) + " on " + host + ", since " + started + "\n";
  // Who holds it, for the message of a run refused: a failure here costs only that message.
  const bool said = ::ftruncate(fd_, 0) == 0 &&
                    ::pwrite(fd_, who.data(), who.size(), 0) == static_cast<ssize_t>(who.size());
  static_cast<void>(said);
}

void OutputClaim::release() {
  if (fd_ < 0) return;
  // Removed while still locked: a run waiting for it finds the name gone and takes a new one.
  ::unlink(lock_path_.c_str());
  ::close(fd_);
  fd_ = -1;
  if (!written_)
    for (auto it = created_.rbegin(); it != created_.rend(); ++it) ::rmdir(it->c_str());
  created_.clear();
}

void remove_files_after_checkpoint(const std::string& dir, const std::string& suffix,
                                   const std::vector<double>& frame_steps,
                                   const std::vector<std::string>& later_suffixes) {
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(dir, error)) {
    const auto file = parse_run_output(entry.path().filename().string());
    // The run's own files are rewritten as they were (a temporary one is truncated by its next write).
    if (!file || file->stem == "summary" || file->stem == "parameters_used" || file->stem == "grains_used" ||
        file->stem == "checkpoint")
      continue;
    const bool later =
        std::find(later_suffixes.begin(), later_suffixes.end(), file->suffix) != later_suffixes.end();
    const bool this_stage = file->suffix == suffix;
    const bool unlisted_frame =
        file->stem == "fields" &&
        std::find(frame_steps.begin(), frame_steps.end(), static_cast<double>(file->step)) == frame_steps.end();
    // particles<suffix>.csv is written at a stage's end: the continued run writes its own.
    const bool end_file = file->stem == "particles" && file->extension == ".csv";
    if (later || (this_stage && (file->temporary || unlisted_frame || end_file))) fs::remove(entry.path(), error);
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
