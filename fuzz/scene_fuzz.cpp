// raybench_fuzz: seeded mutations of small scenes of every format (OBJ, PLY ascii and binary, NFF,
// JSON) through the engine, as `raybench info`, `raybench trace` (with Embree) and
// `raybench render` run them: the very command functions, on each mutated file, in a child
// process per input (a crash or a hang is counted and the input kept, and the run goes on).
//
// Mutations (1 to 3 per input, from one seed): truncation, byte flips, a number replaced by a huge,
// NaN, infinite, denormal, negative or overflowing one, a line repeated, a block of lines repeated,
// a garbage line inserted, a line deleted.
//
// Outcome per input: loaded (every command exit 0), refused (exit 1 with exactly one error line
// "raybench CMD: ..." that names the input), bad message (anything else on a failure), crash
// (a signal or a sanitizer's exit status), hang (over --timeout seconds). Exit status 0 when there
// was no crash, hang or bad message. The failing inputs are kept in --keep.
//
//   raybench_fuzz [--runs N per format] [--seed S] [--format obj|ply|plyb|nff|json|all]
//                 [--timeout SECONDS] [--slow SECONDS] [--keep DIR] [--json FILE]
// An input slower than --slow seconds (default 20) is kept too, as slow-NAME (not a failure).
#include "apps/commands.hpp"
#include "core/output_file.hpp"
#include "apps/render_options.hpp"
#include "apps/trace_options.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;

namespace {

std::string ply_binary_seed() {
  std::string o =
      "ply\nformat binary_little_endian 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 3\nproperty list uchar int vertex_indices\nend_header\n";
  auto put = [&](const void* p, std::size_t n) { o.append(static_cast<const char*>(p), n); };
  const float v[5][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5f, 0.5f, 1}};
  for (auto& r : v)
    for (float x : r) put(&x, 4);
  const std::vector<std::vector<std::int32_t>> faces = {{0, 1, 2, 3}, {0, 1, 4}, {2, 3, 4}};
  for (const auto& f : faces) {
    const std::uint8_t n = std::uint8_t(f.size());
    put(&n, 1);
    for (std::int32_t i : f) put(&i, 4);
  }
  return o;
}

struct Format {
  std::string name, ext, seed;
};

std::vector<Format> formats() {
  return {
      {"obj", "obj",
       "# a cube\nv -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\nvn 0 0 1\nvt 0.5 0.5\n"
       "f 1 2 3 4\nf 5 6 7 8\nf 1 2 6 5\nf 2//1 3//1 7//1 6//1\nf 3/1 4/1 8/1 7/1\nf -8 -4 -1 -5\ng top\nf 1 3 5\n"},
      {"ply", "ply",
       "ply\nformat ascii 1.0\ncomment seed\nelement vertex 5\nproperty float x\nproperty float y\nproperty double z\n"
       "element face 3\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 0.5 1\n4 0 1 2 3\n3 0 1 4\n"
       "3 2 3 4\n"},
      {"plyb", "ply", ply_binary_seed()},
      {"nff", "nff",
       "v\nfrom 1 2 -6\nat 0 0 0\nup 0 1 0\nangle 45\nhither 0.5\nresolution 32 24\nb 0.1 0.2 0.3\nl 3 4 -5\nl -2 2 -2 0.5 0.5 0.5\n"
       "f 1 0 0 0.7 0.3 20 0 1\ns 0 0 0 1\nc\n0 -1 0 0.5\n0 1 0 0.2\nf 0 1 0 0.7 0.3 20 0.5 1.5\ns 2 0 0 0.5\np 4\n-3 -1 -3\n3 -1 -3\n"
       "3 -1 3\n-3 -1 3\npp 3\n0 0 2 0 0 1\n1 0 2 0 0 1\n0 1 2 0 0.6 0.8\n"},
      {"json", "json",
       "{\"camera\": {\"from\": [0, 1, -6], \"at\": [0, 0, 0], \"up\": [0, 1, 0], \"angle\": 40},\n"
       "\"background\": [0.1, 0.1, 0.2],\n"
       "\"lights\": [{\"position\": [4, 5, -6], \"color\": [1, 1, 1]}],\n"
       "\"objects\": [\n"
       "{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1},\n"
       "{\"type\": \"box\", \"min\": [1, -1, -1], \"max\": [2, 0, 0]},\n"
       "{\"type\": \"difference\", \"left\": {\"type\": \"sphere\", \"center\": [-2, 0, 0], \"radius\": 0.8},\n"
       " \"right\": {\"type\": \"cylinder\", \"base\": [-2, -1, 0], \"axis\": [0, 1, 0], \"radius\": 0.3, \"height\": 2}},\n"
       "{\"type\": \"union\", \"children\": [{\"type\": \"box\", \"min\": [0, 1, 0], \"max\": [1, 2, 1]},\n"
       " {\"type\": \"sphere\", \"center\": [0.5, 2, 0.5], \"radius\": 0.4}]}\n"
       "]}\n"},
  };
}

const char* const kNumbers[] = {"1e38",  "-1e38", "3.4e38", "1e39",        "-1e39",      "1e308",         "1e309",
                                "nan",   "-nan",  "inf",    "-inf",        "1e-45",      "1.4e-45",       "4.9e-324",
                                "1e-38", "0",     "-0",     "4294967296",  "4294967295", "-2147483649",   "2147483648",
                                "1e12",  "1e13",  "1e20",   "-1",          "65536",      "1000000000",    "99999999999999999999",
                                "0x10",  "1e",    ".",      "-",           "1e-300",     "18446744073709551616"};

using Rng = std::mt19937_64;

std::vector<std::string> split_lines(const std::string& s) {
  std::vector<std::string> v;
  std::size_t a = 0;
  while (a < s.size()) {
    const std::size_t b = s.find('\n', a);
    if (b == std::string::npos) {
      v.push_back(s.substr(a));
      break;
    }
    v.push_back(s.substr(a, b - a + 1));
    a = b + 1;
  }
  return v;
}
std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& l : v) s += l;
  return s;
}

std::string mutate_once(std::string s, Rng& g) {
  auto pick = [&](std::size_t n) { return n ? std::size_t(g() % n) : 0; };
  switch (g() % 8) {
    case 0:  // truncation
      if (!s.empty()) s.resize(pick(s.size()));
      break;
    case 1:  // byte flips
      for (int k = 1 + int(g() % 4); k > 0 && !s.empty(); --k) s[pick(s.size())] ^= char(1u << (g() % 8));
      break;
    case 2:    // a number replaced
    case 3: {  // (twice as likely: most of the formats' meaning is in their numbers)
      std::vector<std::pair<std::size_t, std::size_t>> nums;
      for (std::size_t i = 0; i < s.size();) {
        if (std::isdigit(static_cast<unsigned char>(s[i])) || ((s[i] == '-' || s[i] == '.') && i + 1 < s.size() && std::isdigit(static_cast<unsigned char>(s[i + 1])))) {
          std::size_t j = i + 1;
          while (j < s.size() && (std::isalnum(static_cast<unsigned char>(s[j])) || s[j] == '.' || s[j] == '-' || s[j] == '+')) ++j;
          nums.push_back({i, j - i});
          i = j;
        } else {
          ++i;
        }
      }
      if (nums.empty()) break;
      const auto [at, len] = nums[pick(nums.size())];
      s.replace(at, len, kNumbers[pick(std::size(kNumbers))]);
      break;
    }
    case 4: {  // a line repeated
      auto l = split_lines(s);
      if (l.empty()) break;
      const std::size_t i = pick(l.size());
      const std::size_t n = 1 + pick(g() % 4 == 0 ? 2000 : 20);
      l.insert(l.begin() + std::ptrdiff_t(i), n, l[i]);
      s = join(l);
      break;
    }
    case 5: {  // a block of lines repeated
      auto l = split_lines(s);
      if (l.size() < 2) break;
      const std::size_t i = pick(l.size()), len = 1 + pick(std::min<std::size_t>(8, l.size() - i));
      const std::vector<std::string> block(l.begin() + std::ptrdiff_t(i), l.begin() + std::ptrdiff_t(i + len));
      for (std::size_t r = 1 + pick(30); r > 0; --r) l.insert(l.begin() + std::ptrdiff_t(i), block.begin(), block.end());
      s = join(l);
      break;
    }
    case 6: {  // a garbage line
      auto l = split_lines(s);
      std::string garbage;
      const int kind = int(g() % 3);
      const std::size_t n = 1 + pick(kind == 2 ? 300 : 40);
      for (std::size_t k = 0; k < n; ++k)
        garbage += kind == 0 ? char(32 + g() % 95) : kind == 1 ? "0123456789 .-e"[g() % 14] : char(g() % 256);
      l.insert(l.begin() + std::ptrdiff_t(pick(l.size() + 1)), garbage + "\n");
      s = join(l);
      break;
    }
    default: {  // a line deleted
      auto l = split_lines(s);
      if (l.empty()) break;
      l.erase(l.begin() + std::ptrdiff_t(pick(l.size())));
      s = join(l);
      break;
    }
  }
  return s;
}

std::string mutate(const std::string& seed, Rng& g) {
  std::string s = seed;
  for (int k = 1 + int(g() % 3); k > 0; --k) s = mutate_once(s, g);
  return s;
}

// In the child: the three commands on `path`, stdout to /dev/null, stderr to `err`.
[[noreturn]] void child(const std::string& path, const std::string& err) {
  const int devnull = ::open("/dev/null", O_WRONLY);
  const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  ::dup2(devnull, 1);
  ::dup2(e, 2);
  using namespace rb::app;
  int worst = 0;
  const JsonOut none;
  worst = std::max(worst, run_info_command(path, none));
  TraceRunOptions t;
  t.scene = path;
  t.threads = 2;
  t.count = 512;
  t.repetitions = 1;
  t.warmup = 0;
  t.brute_rays = 64;
  t.embree = true;
  for (const char* set : {"primary", "shadow"}) {
    t.ray_set = set;
    t.packet = set[0] == 'p' ? 8 : 1;
    worst = std::max(worst, run_trace_command(t, none));
  }
  RenderRunOptions r;
  r.scene = path;
  r.out = path + ".png";
  r.width = 24;
  r.height = 16;
  r.threads = 2;
  r.progress = false;
  r.warmup = 0;
  r.repetitions = 1;
  worst = std::max(worst, run_render_command(r, none));
  std::fflush(nullptr);
  std::exit(worst);
}

enum Outcome { kLoaded, kRefused, kBadMessage, kCrash, kHang, kOutcomes };
const char* const kOutcomeNames[] = {"loaded", "refused", "bad_message", "crash", "hang"};

// A refusal must be one error line per failing command, "raybench CMD: ..." naming the input.
bool good_message(const std::string& err, const std::string& path, std::string& why) {
  std::istringstream in(err);
  int errors = 0;
  for (std::string l; std::getline(in, l);) {
    if (l.find("ERROR: AddressSanitizer") != std::string::npos || l.find("runtime error:") != std::string::npos) {
      why = "sanitizer report: " + l;
      return false;
    }
    const bool cmd_line = l.rfind("raybench info: ", 0) == 0 || l.rfind("raybench trace: ", 0) == 0 || l.rfind("raybench render: ", 0) == 0;
    if (!cmd_line) continue;
    ++errors;
    if (l.find(path) == std::string::npos) {
      why = "an error line without the input's name: " + l;
      return false;
    }
  }
  if (errors == 0) {
    why = "a failure without an error line";
    return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  long runs = 200;
  std::uint64_t seed = 1;
  std::string only = "all", keep = "fuzz-failures", json_out;
  double timeout = 60, slow = 20;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto val = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::cerr << "raybench_fuzz: " << a << " needs a value\n";
        std::exit(1);
      }
      return argv[++i];
    };
    if (a == "--runs") runs = std::stol(val());
    else if (a == "--seed") seed = std::stoull(val());
    else if (a == "--format") only = val();
    else if (a == "--timeout") timeout = std::stod(val());
    else if (a == "--slow") slow = std::stod(val());
    else if (a == "--keep") keep = val();
    else if (a == "--json") json_out = val();
    else {
      std::cerr << "usage: raybench_fuzz [--runs N] [--seed S] [--format obj|ply|plyb|nff|json|all] [--timeout S] [--slow S] [--keep DIR] [--json FILE]\n";
      return a == "--help" ? 0 : 1;
    }
  }
  const fs::path work = fs::temp_directory_path() / ("raybench-fuzz-" + std::to_string(::getpid()));
  fs::create_directories(work);
  fs::create_directories(keep);
  int bad_total = 0;
  std::string json = "{\"seed\": " + std::to_string(seed) + ", \"runs_per_format\": " + std::to_string(runs) + ", \"formats\": {";
  bool first_fmt = true;
  for (const Format& f : formats()) {
    if (only != "all" && only != f.name) continue;
    long count[kOutcomes] = {};
    double max_s = 0;
    const auto t0 = std::chrono::steady_clock::now();
    for (long r = 0; r < runs; ++r) {
      Rng g(seed * 1000003u + std::uint64_t(r) * 7919u + std::hash<std::string>{}(f.name));
      // Input 0 is the seed itself: it must load (else the mutations test little).
      const std::string input = r == 0 ? f.seed : mutate(f.seed, g);
      const std::string name = f.name + "-s" + std::to_string(seed) + "-r" + std::to_string(r) + "." + f.ext;
      const std::string path = (work / name).string(), err = (work / (name + ".err")).string();
      {
        std::ofstream(path, std::ios::binary) << input;
      }
      const auto s0 = std::chrono::steady_clock::now();
      const pid_t pid = ::fork();
      if (pid == 0) child(path, err);
      int st = 0;
      bool hung = false;
      for (;;) {
        if (::waitpid(pid, &st, WNOHANG) == pid) break;
        if (std::chrono::duration<double>(std::chrono::steady_clock::now() - s0).count() > timeout) {
          ::kill(pid, SIGKILL);
          ::waitpid(pid, &st, 0);
          hung = true;
          break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
      }
      const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - s0).count();
      max_s = std::max(max_s, took);
      if (!hung && took > slow) {
        fs::copy_file(path, fs::path(keep) / ("slow-" + name), fs::copy_options::overwrite_existing);
        std::cerr << "raybench_fuzz: slow (" << took << " s): " << (fs::path(keep) / ("slow-" + name)).string() << "\n";
      }
      std::ifstream ef(err);
      std::stringstream es;
      es << ef.rdbuf();
      Outcome o;
      std::string why;
      if (hung) o = kHang, why = "no exit within the timeout";
      else if (!WIFEXITED(st)) o = kCrash, why = std::string("signal ") + strsignal(WTERMSIG(st));
      else if (WEXITSTATUS(st) == 0) o = kLoaded;
      else if (WEXITSTATUS(st) == 1 || WEXITSTATUS(st) == 2) o = good_message(es.str(), path, why) ? kRefused : kBadMessage;
      else o = kCrash, why = "exit status " + std::to_string(WEXITSTATUS(st));
      if (o == kLoaded && !good_message(es.str() + "raybench info: " + path + "\n", path, why)) o = kBadMessage;  // a sanitizer report on success
      if (r == 0 && o != kLoaded) {
        std::cerr << "raybench_fuzz: the " << f.name << " seed does not load:\n" << es.str();
        ++bad_total;
      }
      ++count[o];
      if (o >= kBadMessage) {
        ++bad_total;
        fs::copy_file(path, fs::path(keep) / name, fs::copy_options::overwrite_existing);
        std::ofstream(fs::path(keep) / (name + ".stderr")) << es.str();
        std::cerr << "raybench_fuzz: " << kOutcomeNames[o] << ": " << (fs::path(keep) / name).string() << ": " << why << "\n";
      }
      fs::remove(path);
      fs::remove(err);
      fs::remove(path + ".png");
    }
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("%-5s %6ld runs: %6ld loaded, %6ld refused, %ld bad messages, %ld crashes, %ld hangs (%.0f s, slowest input %.1f s)\n",
                f.name.c_str(), runs, count[kLoaded], count[kRefused], count[kBadMessage], count[kCrash], count[kHang], secs, max_s);
    std::fflush(stdout);
    json += std::string(first_fmt ? "" : ", ") + "\"" + f.name + "\": {\"runs\": " + std::to_string(runs);
    for (int k = 0; k < kOutcomes; ++k) json += ", \"" + std::string(kOutcomeNames[k]) + "\": " + std::to_string(count[k]);
    json += ", \"seconds\": " + std::to_string(secs) + "}";
    first_fmt = false;
  }
  json += "}}\n";
  if (!json_out.empty()) {
    try {
      rb::write_output(json_out, json);  // raybench's one output rule (core/output_file.hpp)
    } catch (const std::exception& e) {
      std::fprintf(stderr, "raybench_fuzz: %s\n", e.what());
      return 1;
    }
  }
  std::error_code ec;
  fs::remove_all(work, ec);
  return bad_total ? 1 : 0;
}
