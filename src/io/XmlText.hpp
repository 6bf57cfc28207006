#pragma once
// The text of a scene file, made ready for Teuchos's XML reader, which reads
// bytes: it knows no byte order marks or encodings, turns a character
// reference &#233; into the one byte 0xE9 (Latin-1, so that what PoreSPH
// writes back is no longer UTF-8) and refuses &#xE9; and references beyond
// 255. Here the file is checked to be UTF-8 (a UTF-8 byte order mark is
// dropped; a file declared ISO-8859-1 is converted), other encodings are
// named as such, and every character reference is replaced by the
// character in UTF-8, so that parameters_used.xml, summary.json and the
// messages hold the name the user wrote.
#include <cctype>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

namespace poresph {
namespace xml_text_detail {

inline std::string hex_byte(unsigned char c) {
  const char* digits = "0123456789ABCDEF";
  return std::string("0x") + digits[c >> 4] + digits[c & 15];
}

inline int line_of(const std::string& text, size_t at) {
  int line = 1;
  for (size_t k = 0; k < at && k < text.size(); ++k) line += text[k] == '\n';
  return line;
}

// Length of the UTF-8 sequence at `at`, or 0 where the bytes are not UTF-8
// (overlong forms, surrogates and values beyond U+10FFFF included).
inline size_t utf8_length(const std::string& text, size_t at) {
  const auto byte = [&](size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char c = byte(at);
  if (c < 0x80) return 1;
  size_t n = c >= 0xC2 && c <= 0xDF ? 2 : c >= 0xE0 && c <= 0xEF ? 3 : c >= 0xF0 && c <= 0xF4 ? 4 : 0;
  if (n == 0 || at + n > text.size()) return 0;
  for (size_t k = 1; k < n; ++k)
    if ((byte(at + k) & 0xC0) != 0x80) return 0;
  const unsigned char d = byte(at + 1);
  if ((c == 0xE0 && d < 0xA0) || (c == 0xED && d > 0x9F) || (c == 0xF0 && d < 0x90) || (c == 0xF4 && d > 0x8F))
    return 0;
  return n;
}

inline std::string utf8(std::uint32_t code) {
  std::string out;
  if (code < 0x80) {
    out += static_cast<char>(code);
  } else if (code < 0x800) {
    out += static_cast<char>(0xC0 | (code >> 6));
    out += static_cast<char>(0x80 | (code & 0x3F));
  } else if (code < 0x10000) {
    out += static_cast<char>(0xE0 | (code >> 12));
    out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (code & 0x3F));
  } else {
    out += static_cast<char>(0xF0 | (code >> 18));
    out += static_cast<char>(0x80 | ((code >> 12) & 0x3F));
    out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (code & 0x3F));
  }
  return out;
}

// A character XML 1.0 allows (its production Char).
inline bool xml_char(std::uint32_t c) {
  return c == 0x9 || c == 0xA || c == 0xD || (c >= 0x20 && c <= 0xD7FF) || (c >= 0xE000 && c <= 0xFFFD) ||
         (c >= 0x10000 && c <= 0x10FFFF);
}

// The encoding named in an XML declaration at the start, lower case, if any.
inline std::optional<std::string> declared_encoding(const std::string& text) {
  if (text.rfind("<?xml", 0) != 0) return std::nullopt;
  const size_t end = text.find("?>");
  const size_t at = text.find("encoding", 0);
  if (end == std::string::npos || at == std::string::npos || at > end) return std::nullopt;
  size_t q = text.find_first_of("\"'", at);
  if (q == std::string::npos || q > end) return std::nullopt;
  const size_t close = text.find(text[q], q + 1);
  if (close == std::string::npos || close > end) return std::nullopt;
  std::string name = text.substr(q + 1, close - q - 1);
  for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return name;
}

}  // namespace xml_text_detail

// The text for Teuchos, or std::invalid_argument saying what is wrong with
// the encoding or a reference, by line.
inline std::string xml_text_for_parser(std::string text) {
  using namespace xml_text_detail;
  auto at_start = [&](std::initializer_list<unsigned char> bytes) {
    size_t k = 0;
    for (unsigned char b : bytes)
      if (k >= text.size() || static_cast<unsigned char>(text[k++]) != b) return false;
    return true;
  };
  const std::string save_as = ": save it as UTF-8 (for example iconv -t UTF-8), which PoreSPH reads";
  if (at_start({0x00, 0x00, 0xFE, 0xFF}) || at_start({0xFF, 0xFE, 0x00, 0x00}))
    throw std::invalid_argument("the file is in UTF-32 (it starts with that byte order mark)" + save_as);
  if (at_start({0xFE, 0xFF}) || at_start({0xFF, 0xFE}))
    throw std::invalid_argument("the file is in UTF-16 (it starts with that byte order mark)" + save_as);
  if (at_start({0xEF, 0xBB, 0xBF})) text.erase(0, 3);  // UTF-8's own mark, which XML allows
  if (text.size() >= 2 && (text[0] == '\0' || text[1] == '\0'))
    throw std::invalid_argument("the file is in UTF-16 or UTF-32 (every other byte is zero)" + save_as);
  if (const size_t nul = text.find('\0'); nul != std::string::npos)
    throw std::invalid_argument("line " + std::to_string(line_of(text, nul)) +
                                " holds a zero byte: the file is not text in UTF-8");
  if (const auto encoding = declared_encoding(text)) {
    if (*encoding == "iso-8859-1" || *encoding == "latin1" || *encoding == "latin-1") {
      std::string converted;
      for (char c : text) converted += utf8(static_cast<unsigned char>(c));
      text = converted;
    } else if (*encoding != "utf-8" && *encoding != "utf8" && *encoding != "us-ascii" && *encoding != "ascii") {
      throw std::invalid_argument("its XML declaration says encoding \"" + *encoding + "\"" + save_as +
                                  " (and declare encoding=\"UTF-8\")");
    }
  }
  // The length of the UTF-8 character at k, or why the file is not UTF-8.
  auto character_at = [&](size_t k) {
    const size_t n = utf8_length(text, k);
    if (n == 0)
      throw std::invalid_argument(
          "line " + std::to_string(line_of(text, k)) + ": the byte " + hex_byte(static_cast<unsigned char>(text[k])) +
          " is not UTF-8 (the file is in another encoding, Latin-1 or Windows-1252 perhaps)" + save_as +
          ", or declare encoding=\"ISO-8859-1\" in its first line if it is Latin-1");
    return n;
  };
  std::string out;
  out.reserve(text.size());
  for (size_t k = 0; k < text.size();) {
    // Comments and CDATA hold text as it is: no reference is read there.
    bool skipped = false;
    for (const auto& [open, close] : {std::pair<std::string, std::string>{"<!--", "-->"}, {"<![CDATA[", "]]>"}}) {
      if (text.compare(k, open.size(), open) != 0) continue;
      const size_t end = text.find(close, k + open.size());
      const size_t stop = end == std::string::npos ? text.size() : end + close.size();
      for (size_t m = k; m < stop;) m += character_at(m);
      out.append(text, k, stop - k);
      k = stop;
      skipped = true;
      break;
    }
    if (skipped) continue;
    const size_t n = character_at(k);
    if (text[k] != '&') {
      out.append(text, k, n);
      k += n;
      continue;
    }
    const size_t semicolon = text.find(';', k);
    const std::string line = "line " + std::to_string(line_of(text, k));
    const bool short_name = semicolon != std::string::npos && semicolon - k <= 12;
    const std::string name = short_name ? text.substr(k + 1, semicolon - k - 1) : "";
    if (name == "amp" || name == "lt" || name == "gt" || name == "quot" || name == "apos") {
      out.append(text, k, semicolon + 1 - k);
      k = semicolon + 1;
      continue;
    }
    if (name.size() >= 2 && name[0] == '#') {
      const bool hex = name[1] == 'x';
      const std::string digits = name.substr(hex ? 2 : 1);
      std::uint32_t code = 0;
      bool valid = !digits.empty() && digits.size() <= 8;
      for (char c : digits) {
        const int v = std::isdigit(static_cast<unsigned char>(c))                  ? c - '0'
                      : hex && std::isxdigit(static_cast<unsigned char>(c)) ? std::tolower(c) - 'a' + 10
                                                                                     : -1;
        if (v < 0) valid = false;
        else code = code * (hex ? 16 : 10) + static_cast<std::uint32_t>(v);
      }
      if (!valid || !xml_char(code))
        throw std::invalid_argument(line + ": '&" + name + ";' is not a character XML allows");
      // Markup characters stay references, which the parser reads as text.
      if (code == '&' || code == '<' || code == '>' || code == '"' || code == '\'')
        out += "&#" + std::to_string(code) + ";";
      else
        out += utf8(code);
      k = semicolon + 1;
      continue;
    }
    if (!name.empty() && std::isalpha(static_cast<unsigned char>(name[0])))
      throw std::invalid_argument(line + ": '&" + name + ";' is not an entity XML knows (it knows &amp; &lt; &gt; "
                                  "&quot; &apos;): write the character itself in UTF-8, or as a numeric reference "
                                  "such as &#233;");
    throw std::invalid_argument(line + ": a bare '&' that begins no reference: write it as &amp;");
  }
  return out;
}

// A Teuchos exception's message without the lines that locate the throw in
// Teuchos's own sources ("file.cpp:249:", "Throw number = 1", "Throw test
// that evaluated to true: ..."), which say nothing to a user.
inline std::string teuchos_message(const std::string& what) {
  std::string kept, line;
  size_t start = 0;
  while (start <= what.size()) {
    size_t end = what.find('\n', start);
    if (end == std::string::npos) end = what.size();
    line = what.substr(start, end - start);
    start = end + 1;
    const bool source = line.find(".cpp:") != std::string::npos || line.find(".hpp:") != std::string::npos;
    if (source || line.rfind("Throw number", 0) == 0 || line.rfind("Throw test that evaluated", 0) == 0) continue;
    if (line.empty() && (kept.empty() || kept.back() == '\n')) continue;
    kept += line + "\n";
  }
  while (!kept.empty() && kept.back() == '\n') kept.pop_back();
  return kept;
}

}  // namespace poresph
