// Shared helpers of the scene loaders (internal to scene/): whole-file reads, error messages
// that name the file and the line (or byte offset), and allocation-free number parsing.
// Numbers go through std::from_chars (GCC 12: fast_float, locale-independent, exact rounding
// straight to float, so "0.1" in a file is the float nearest 0.1, never a double rounded twice).
#pragma once

#include "scene/sources.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

namespace rb::scene::detail {

// Reads a whole file; SceneError if it cannot be opened or read.
std::string read_file(const std::string& path);
// Material i of n's name in the JSON scene format's output (scene/json_scene.cpp).
std::string material_name(std::uint32_t i, std::size_t n);

[[noreturn]] inline void fail_line(std::string_view file, std::size_t line, std::string_view what) {
  throw SceneError(fmt::format("{}:{}: {}", file, line, what));
}
[[noreturn]] inline void fail_byte(std::string_view file, std::size_t byte, std::string_view what) {
  throw SceneError(fmt::format("{}: byte {}: {}", file, byte, what));
}

// Shortens a token for quoting in an error message (hostile input may hold megabyte "tokens").
inline std::string quote(std::string_view s) {
  std::string q;
  for (char c : s.substr(0, 40)) q += (c >= 32 && c < 127) ? c : '?';
  if (s.size() > 40) q += "...";
  return "'" + q + "'";
}

inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// One line of text, consumed token by token (no allocation).
struct LineReader {
  const char* p;
  const char* e;

  void skip_ws() { while (p < e && is_space(*p)) ++p; }
  bool at_end() { skip_ws(); return p == e; }
  std::string_view word() {
    skip_ws();
    const char* s = p;
    while (p < e && !is_space(*p)) ++p;
    return {s, std::size_t(p - s)};
  }
  std::string_view rest() { skip_ws(); return {p, std::size_t(e - p)}; }

  // Parses a number; returns false (without consuming) if the next token is not exactly one.
  template <class T>
  bool number(T& out) {
    skip_ws();
    const char* s = p;
    if (s < e && *s == '+') ++s;  // from_chars takes no '+'
    T v{};
    const auto r = std::from_chars(s, e, v);
    if (r.ec != std::errc() || (r.ptr < e && !is_space(*r.ptr))) return false;
    out = v;
    p = r.ptr;
    return true;
  }
};

// Splits a buffer into lines ('\n'; a trailing '\r' is whitespace), counting from 1.
struct Lines {
  const char* p;
  const char* e;
  std::size_t number = 0;
  explicit Lines(std::string_view text) : p(text.data()), e(text.data() + text.size()) {}
  bool next(LineReader& line) {
    if (p >= e) return false;
    const char* nl = static_cast<const char*>(std::memchr(p, '\n', std::size_t(e - p)));
    const char* end = nl ? nl : e;
    line = {p, end};
    p = nl ? nl + 1 : e;
    ++number;
    return true;
  }
  std::size_t remaining_bytes() const { return std::size_t(e - p); }
};

}  // namespace rb::scene::detail
