#pragma once
// Numbers, booleans and arrays read from text, strictly and in one way for
// every input: the scene's XML, --set, grain files and the command line. The
// whole text must be the value (surrounding blanks aside): "0.005abc" is not
// 0.005, "12.5" is not the integer 12, and NaN or infinity is no number of a
// scene. std::from_chars is used because it ignores the locale and takes no
// hexadecimal or partial input.
#include <charconv>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <type_traits>
#include <vector>

namespace poresph {

inline std::string_view trimmed(std::string_view text) {
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; };
  while (!text.empty() && blank(text.front())) text.remove_prefix(1);
  while (!text.empty() && blank(text.back())) text.remove_suffix(1);
  return text;
}

// The value, or why the text is not one ("" when it is).
template <class T>
struct Parsed {
  std::optional<T> value;
  std::string problem;
};

// A finite double, an int or a long long.
template <class T>
Parsed<T> parse_number(std::string_view text) {
  static_assert(std::is_same_v<T, double> || std::is_same_v<T, int> || std::is_same_v<T, long long>);
  constexpr bool real = std::is_same_v<T, double>;
  const char* kind = real ? "a number" : "an integer";
  text = trimmed(text);
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);  // from_chars takes '-' only
  if (text.empty()) return {std::nullopt, "is empty, not " + std::string(kind)};
  T value{};
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error == std::errc::result_out_of_range)
    return {std::nullopt, "is out of the range of " + std::string(real ? "a double" : "an integer of this type")};
  if (error != std::errc() || end != text.data() + text.size()) return {std::nullopt, "is not " + std::string(kind)};
  if constexpr (real)
    if (!std::isfinite(value)) return {std::nullopt, "is not a finite number"};
  return {value, ""};
}

inline Parsed<bool> parse_bool(std::string_view text) {
  text = trimmed(text);
  if (text == "true" || text == "1") return {true, ""};
  if (text == "false" || text == "0") return {false, ""};
  return {std::nullopt, "is not true or false"};
}

// "{a, b, c}" (Teuchos's notation for arrays; "{}" is empty), each element as parse_number.
template <class T>
Parsed<std::vector<T>> parse_array(std::string_view text) {
  text = trimmed(text);
  if (text.size() < 2 || text.front() != '{' || text.back() != '}')
    return {std::nullopt, "is not an array like {1, 2}"};
  text = trimmed(text.substr(1, text.size() - 2));
  std::vector<T> values;
  if (text.empty()) return {values, ""};
  for (size_t k = 1;; ++k) {
    const size_t comma = text.find(',');
    const auto element = parse_number<T>(text.substr(0, comma));
    if (!element.value)
      return {std::nullopt, "has element " + std::to_string(k) + " '" + std::string(trimmed(text.substr(0, comma))) +
                                "' that " + element.problem};
    values.push_back(*element.value);
    if (comma == std::string_view::npos) break;
    text.remove_prefix(comma + 1);
  }
  return {values, ""};
}

}  // namespace poresph
