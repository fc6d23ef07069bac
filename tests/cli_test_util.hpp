// Running the built `raybench` binary from a test: its exit status, stdout and stderr, in a
// scratch folder of its own. The command line's conventions are properties of the program as a
// user runs it (exit statuses, messages, files written or not), so these tests run the program.
#pragma once

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

namespace rbtest {

namespace fs = std::filesystem;

struct Outcome {
  int status = -1;
  std::string out, err;
  std::vector<std::string> err_lines() const {
    std::vector<std::string> v;
    std::istringstream in(err);
    for (std::string l; std::getline(in, l);) v.push_back(l);
    return v;
  }
  nlohmann::json json() const { return nlohmann::json::parse(out); }
};

inline std::string slurp(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// A fresh folder under the build's temporary space, removed when the test ends.
struct Scratch {
  fs::path dir;
  explicit Scratch(const std::string& name) {
    dir = fs::temp_directory_path() / ("raybench-test-" + name + "-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  std::string operator/(const std::string& f) const { return (dir / f).string(); }
};

// Runs `BINARY ARGS` in `cwd` (shell syntax in ARGS is the test's own), with `env` prepended
// (e.g. "RAYBENCH_HISTORY=x.sqlite") and stdin from /dev/null unless `input` is given.
inline Outcome run_in(const fs::path& cwd, const std::string& args, const std::string& env = "", const std::string& input = "",
                  const std::string& binary = RB_RAYBENCH) {
  const fs::path out = cwd / ".stdout", err = cwd / ".stderr", in = cwd / ".stdin";
  std::ofstream(in) << input;
  // The user's own history and share folder stay out of the tests.
  const std::string cmd = "cd '" + cwd.string() + "' && env -u RAYBENCH_HISTORY -u RAYBENCH_SHARE " + env + " " + binary + " " + args + " <'" +
                          in.string() + "' >'" + out.string() + "' 2>'" + err.string() + "'";
  Outcome r;
  const int st = std::system(cmd.c_str());
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  fs::remove(out);
  fs::remove(err);
  fs::remove(in);
  return r;
}

// The widest line of `text`, in display columns (UTF-8 code points).
inline std::size_t widest(const std::string& text) {
  std::size_t w = 0, n = 0;
  for (unsigned char c : text) {
    if (c == '\n') w = std::max(w, n), n = 0;
    else n += (c & 0xC0) != 0x80;
  }
  return std::max(w, n);
}

// An octahedron: the smallest closed triangle mesh, so that Embree traces it too.
inline const char* const kOctahedron =
    "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n"
    "f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n";

inline bool has(const std::string& hay, const std::string& needle) { return hay.find(needle) != std::string::npos; }

// One error line on stderr, "raybench COMMAND: ...", naming `input` once. Before it, trace and
// render may have printed their header ("raybench trace SCENE: ... thread(s) ..."), which is not an
// error message.
inline void expect_one_error_line(const Outcome& r, const std::string& command, const std::string& input) {
  auto lines = r.err_lines();
  if ((command == "trace" || command == "render") && lines.size() == 2 && has(lines[0], "thread(s) of")) lines.erase(lines.begin());
  ASSERT_EQ(lines.size(), 1u) << r.err;
  EXPECT_EQ(lines[0].rfind("raybench " + command + ":", 0), 0u) << lines[0];
  if (!input.empty()) {
    EXPECT_TRUE(has(lines[0], input)) << lines[0];
    EXPECT_EQ(lines[0].find(input), lines[0].rfind(input)) << "names the input twice: " << lines[0];
  }
}

}  // namespace rbtest
