#pragma once
// summary.json: a JSON object for scripts, built member by member in a fixed
// key order and written by nlohmann-json (Debian's nlohmann-json3-dev), which
// escapes every string so that it reads back as written (control characters
// included; bytes that are not UTF-8 become U+FFFD) and writes NaN and
// infinity as null. Files are written to a temporary name and renamed, so
// that a reader never sees half a file.
#include <nlohmann/json_fwd.hpp>

#include <memory>
#include <string>
#include <vector>

namespace poresph {

class JsonObject {
 public:
  JsonObject();
  JsonObject(const JsonObject& other);
  JsonObject& operator=(const JsonObject& other);
  ~JsonObject();

  JsonObject& add(const std::string& key, double value);
  JsonObject& add(const std::string& key, long long value);
  JsonObject& add(const std::string& key, int value) { return add(key, static_cast<long long>(value)); }
  JsonObject& add(const std::string& key, bool value);
  JsonObject& add(const std::string& key, const std::string& value);
  JsonObject& add(const std::string& key, const char* value) { return add(key, std::string(value)); }
  JsonObject& add(const std::string& key, const JsonObject& value);
  JsonObject& add(const std::string& key, const std::vector<JsonObject>& values);
  JsonObject& add(const std::string& key, const std::vector<std::string>& values);
  // The text, indented by two spaces.
  std::string str() const;
  const nlohmann::ordered_json& json() const { return *value_; }

 private:
  std::unique_ptr<nlohmann::ordered_json> value_;
};

// Writes text to path through path + ".tmp", synced to the disk, and a
// rename, then syncs the directory. On failure (a full disk, say) throws
// with the reason, removes the temporary file, and leaves an earlier file
// under `path` as it was.
void write_file_atomically(const std::string& path, const std::string& text);

// fsync(2) of the directory holding `path`, so that a rename into it
// survives a power loss; best effort (some file systems cannot).
void sync_directory_of(const std::string& path);

// summary.json, through write_file_atomically. If it cannot be written, an
// earlier summary.json there is removed before the error is thrown: a
// summary of another state of the run must not be taken for this one's.
void write_summary_file(const std::string& path, const std::string& text);

}  // namespace poresph
