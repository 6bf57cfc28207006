#include "io/Summary.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace poresph {
namespace {

std::string quote(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\', out += c;
    else if (c == '\n') out += "\\n";
    else if (static_cast<unsigned char>(c) < 0x20) out += ' ';
    else out += c;
  }
  return out + "\"";
}

}  // namespace

JsonObject& JsonObject::add(const std::string& key, double value) {
  // JSON has no NaN or Inf: write null so that a reader sees "no number".
  char buffer[32] = "null";
  if (std::isfinite(value)) std::snprintf(buffer, sizeof buffer, "%.17g", value);
  members_.push_back({key, Kind::Scalar, buffer, {}, {}});
  return *this;
}
JsonObject& JsonObject::add(const std::string& key, long long value) {
  members_.push_back({key, Kind::Scalar, std::to_string(value), {}, {}});
  return *this;
}
JsonObject& JsonObject::add(const std::string& key, bool value) {
  members_.push_back({key, Kind::Scalar, value ? "true" : "false", {}, {}});
  return *this;
}
JsonObject& JsonObject::add(const std::string& key, const std::string& value) {
  members_.push_back({key, Kind::Scalar, quote(value), {}, {}});
  return *this;
}
JsonObject& JsonObject::add(const std::string& key, const JsonObject& value) {
  members_.push_back({key, Kind::Object, {}, {value}, {}});
  return *this;
}
JsonObject& JsonObject::add(const std::string& key, const std::vector<JsonObject>& values) {
  members_.push_back({key, Kind::Array, {}, values, {}});
  return *this;
}
JsonObject& JsonObject::add(const std::string& key, const std::vector<std::string>& values) {
  members_.push_back({key, Kind::StringArray, {}, {}, values});
  return *this;
}

std::string JsonObject::str(int indent) const {
  const std::string pad(indent + 2, ' '), end_pad(indent, ' ');
  std::ostringstream out;
  out << "{";
  for (size_t k = 0; k < members_.size(); ++k) {
    const Member& m = members_[k];
    out << (k ? ",\n" : "\n") << pad << quote(m.key) << ": ";
    if (m.kind == Kind::Scalar) {
      out << m.scalar;
    } else if (m.kind == Kind::StringArray) {
      out << "[";
      for (size_t i = 0; i < m.strings.size(); ++i) out << (i ? ", " : "") << quote(m.strings[i]);
      out << "]";
    } else if (m.kind == Kind::Object) {
      out << m.children.front().str(indent + 2);
    } else {
      out << "[";
      for (size_t i = 0; i < m.children.size(); ++i) out << (i ? ", " : "") << m.children[i].str(indent + 2);
      out << "]";
    }
  }
  out << "\n" << end_pad << "}";
  return out.str();
}

void write_file_atomically(const std::string& path, const std::string& text) {
  const std::string temporary = path + ".tmp";
  {
    std::ofstream file(temporary, std::ios::trunc);
    file << text;
    file.flush();
    if (!file) throw std::runtime_error("cannot write " + temporary);
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) throw std::runtime_error("cannot rename " + temporary);
}

}  // namespace poresph
