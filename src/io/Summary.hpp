#pragma once
// summary.json: a flat-ish JSON object for scripts, written to a temporary
// name and renamed, so that a reader never sees half a file.
#include <string>
#include <vector>

namespace poresph {

class JsonObject {
 public:
  JsonObject& add(const std::string& key, double value);
  JsonObject& add(const std::string& key, long long value);
  JsonObject& add(const std::string& key, int value) { return add(key, static_cast<long long>(value)); }
  JsonObject& add(const std::string& key, bool value);
  JsonObject& add(const std::string& key, const std::string& value);
  JsonObject& add(const std::string& key, const char* value) { return add(key, std::string(value)); }
  JsonObject& add(const std::string& key, const JsonObject& value);
  JsonObject& add(const std::string& key, const std::vector<JsonObject>& values);
  JsonObject& add(const std::string& key, const std::vector<std::string>& values);
  std::string str(int indent = 0) const;

 private:
  enum class Kind { Scalar, Object, Array, StringArray };
  struct Member {
    std::string key;
    Kind kind;
    std::string scalar;               // serialised number, bool or string
    std::vector<JsonObject> children; // one for Object, any number for Array
    std::vector<std::string> strings; // StringArray
  };
  std::vector<Member> members_;
};

// Writes text to path through path + ".tmp" and a rename.
void write_file_atomically(const std::string& path, const std::string& text);

}  // namespace poresph
