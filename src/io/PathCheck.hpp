#pragma once
// Why a path given as input (the scene, a grain file, an image, a
// checkpoint) cannot be opened as a file, in words that say what to fix:
// "no such file" is kept for a name that is not there, and told apart from
// a symbolic link that leads nowhere or in a loop, a parent that is not a
// directory, and a directory or device where a file was meant.
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstring>
#include <string>

namespace poresph {

// Where the symbolic link `path` points, or "" if it is not one.
inline std::string link_target(const std::string& path) {
  char target[PATH_MAX];
  const ssize_t n = ::readlink(path.c_str(), target, sizeof target - 1);
  return n < 0 ? std::string() : std::string(target, static_cast<size_t>(n));
}

// The problem stat(2) reported for `path` (errno `error`), in words.
inline std::string stat_problem(const std::string& path, int error) {
  switch (error) {
    case ELOOP:
      return "its symbolic links lead in a loop (ls -l shows where each leads): correct or remove the link";
    case ENOENT: {
      struct stat link {};
      if (::lstat(path.c_str(), &link) == 0 && S_ISLNK(link.st_mode))
        return "it is a symbolic link to '" + link_target(path) + "', which does not exist";
      return "no such file";
    }
    case ENOTDIR:
      return "a part of the path before its last name is a file, not a directory";
    case EACCES:
      return "permission denied on a directory of the path";
    case ENAMETOOLONG:
      return "the name is too long for the file system";
    default:
      return std::strerror(error);
  }
}

// "" if `path` is an existing regular file; otherwise why not. `meant`
// names what was expected, for a directory given instead ("an XML file").
inline std::string regular_file_problem(const std::string& path, const std::string& meant) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return stat_problem(path, errno);
  if (S_ISDIR(st.st_mode)) return "it is a directory, not " + meant;
  if (!S_ISREG(st.st_mode)) return "it is not a regular file";
  return "";
}

}  // namespace poresph
