// Plain-text layout for terminals and reports: display width of UTF-8 text, words wrapped to a
// width, long lines of a table-like text folded. One home for the command line (apps/cli.hpp), the
// ops table (bench/ops_table.cpp) and every text result.
#pragma once

#include <cstddef>
#include <sstream>
#include <string>

namespace rb {

// `s` without the blanks (spaces, tabs, line ends) at either end.
inline std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r\n");
  if (a == std::string::npos) return "";
  return s.substr(a, s.find_last_not_of(" \t\r\n") - a + 1);
}

// Display columns of UTF-8 text (continuation bytes take none).
inline std::size_t display_width(const std::string& s) {
  std::size_t n = 0;
  for (unsigned char c : s) n += (c & 0xC0) != 0x80;
  return n;
}

// The words of `text` on lines of at most `width` columns (a longer word alone on its line), the
// first line with text's own indentation, each further line starting with `indent`; ends with a
// newline. Two spaces in a row stay inside a line (alignment) and are dropped at a break.
inline std::string wrap_words(const std::string& text, std::size_t width = 80, const std::string& indent = "") {
  std::string out, line;
  bool fresh = true;  // nothing but the indent on this line yet
  std::size_t i = text.find_first_not_of(' ');
  if (i == std::string::npos) return text + "\n";
  line = text.substr(0, i);
  while (i < text.size()) {
    std::size_t j = text.find(' ', i);
    if (j == std::string::npos) j = text.size();
    const std::string w = text.substr(i, j - i);
    i = j + 1;
    if (w.empty() && fresh) continue;
    if (!fresh && !w.empty() && display_width(line) + 1 + display_width(w) > width) {
      out += line + "\n";
      line = indent;
      fresh = true;
    }
    line += (fresh ? "" : " ") + w;
    fresh = false;
  }
  return out + line + "\n";
}

// Every line of `text` within `width` columns: a longer one wrapped, its further lines indented by
// `indent` spaces.
inline std::string fit_columns(const std::string& text, std::size_t indent, std::size_t width = 80) {
  std::istringstream in(text);
  std::string line, out;
  while (std::getline(in, line)) out += display_width(line) <= width ? line + "\n" : wrap_words(line, width, std::string(indent, ' '));
  return out;
}

}  // namespace rb
