#include "io/Summary.hpp"

#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace poresph {

JsonObject::JsonObject() : value_(std::make_unique<nlohmann::ordered_json>(nlohmann::ordered_json::object())) {}
JsonObject::JsonObject(const JsonObject& other) : value_(std::make_unique<nlohmann::ordered_json>(*other.value_)) {}
JsonObject& JsonObject::operator=(const JsonObject& other) {
  *value_ = *other.value_;
  return *this;
}
JsonObject::~JsonObject() = default;

JsonObject& JsonObject::add(const std::string& key, double value) {
  (*value_)[key] = value;  // NaN and infinity are written as null: "no number"
  return *this;
}
JsonObject& JsonObject::add(const std::string& key, long long value) {
  (*value_)[key] = value;
  return *this;
}
JsonObject& JsonObject::add(const std::string& key, bool value) {
  (*value_)[key] = value;
  return *this;
}
JsonObject& JsonObject::add(const std::string& key, const std::string& value) {
  (*value_)[key] = value;
  return *this;
}
JsonObject& JsonObject::add(const std::string& key, const JsonObject& value) {
  (*value_)[key] = *value.value_;
  return *this;
}
JsonObject& JsonObject::add(const std::string& key, const std::vector<JsonObject>& values) {
  auto array = nlohmann::ordered_json::array();
  for (const auto& v : values) array.push_back(*v.value_);
  (*value_)[key] = std::move(array);
  return *this;
}
JsonObject& JsonObject::add(const std::string& key, const std::vector<std::string>& values) {
  (*value_)[key] = values;
  return *this;
}

std::string JsonObject::str() const {
  // Messages may quote file names in any encoding: replace what is not UTF-8 rather than fail.
  return value_->dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

void sync_directory_of(const std::string& path) {
  std::string dir = path.substr(0, path.find_last_of('/') == std::string::npos ? 0 : path.find_last_of('/'));
  if (dir.empty()) dir = path.rfind('/', 0) == 0 ? "/" : ".";
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);  // best effort: some file systems cannot sync a directory, and the file is in place already
  ::close(fd);
}

void write_file_atomically(const std::string& path, const std::string& text) {
  const std::string temporary = path + ".tmp";
  auto fail = [&](const std::string& what, int error) {
    std::remove(temporary.c_str());
    throw std::runtime_error("cannot write " + path + ": " + what + ": " + std::strerror(error));
  };
  errno = 0;
  std::FILE* file = std::fopen(temporary.c_str(), "wb");
  if (!file) fail("cannot create " + temporary, errno);
  // On the disk before it takes the final name: after a power loss the name
  // holds the old file or the new one, never an empty or partial one.
  const bool written = std::fwrite(text.data(), 1, text.size(), file) == text.size() && std::fflush(file) == 0 &&
                       ::fsync(fileno(file)) == 0;
  const int write_error = errno;
  if (std::fclose(file) != 0 || !written) fail("writing " + temporary, written ? errno : write_error);
  if (std::rename(temporary.c_str(), path.c_str()) != 0) fail("renaming " + temporary, errno);
  sync_directory_of(path);  // and the rename itself
}

void write_summary_file(const std::string& path, const std::string& text) {
  try {
    write_file_atomically(path, text);
  } catch (const std::exception& e) {
    const bool removed = std::remove(path.c_str()) == 0;
    throw std::runtime_error(std::string(e.what()) +
                             (removed ? "; the earlier summary.json was removed, so that it is not taken for this "
                                        "run's"
                                      : ""));
  }
}

}  // namespace poresph
