// SIGINT and SIGTERM in the middle of a long run: raybench stops with one message line and the
// exit status 128 + signal, and the folder holds the previous run's files untouched (every output
// is written through a temporary and a rename), no temporary and no empty placeholder.
#include "cli_test_util.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <fcntl.h>
#include <iostream>
#include <map>
#include <spawn.h>
#include <thread>

extern char** environ;

namespace {

using namespace rbtest;

struct Killed {
  int status = -1;         // exit status (-1: killed by a signal or not exited)
  double wait_s = 0;       // from the signal to the exit
  bool was_running = false;
  std::string err;
};

// Starts `raybench ARGS` in `dir`, sends `sig` after `after_s` seconds, waits for the exit (at
// most 30 s, then SIGKILL).
Killed start_and_signal(const fs::path& dir, const std::vector<std::string>& args, int sig, double after_s) {
  std::vector<std::string> a = {RB_RAYBENCH};
  a.insert(a.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& s : a) argv.push_back(s.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  const std::string err_path = (dir / ".stderr").string();
  posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&fa, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  const fs::path cwd = fs::current_path();
  fs::current_path(dir);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, RB_RAYBENCH, &fa, nullptr, argv.data(), environ);
  fs::current_path(cwd);
  posix_spawn_file_actions_destroy(&fa);
  Killed k;
  if (rc != 0) return k;
  std::this_thread::sleep_for(std::chrono::duration<double>(after_s));
  int st = 0;
  k.was_running = ::waitpid(pid, &st, WNOHANG) == 0;
  if (!k.was_running) {
    k.err = slurp(err_path);
    return k;
  }
  const auto t0 = std::chrono::steady_clock::now();
  ::kill(pid, sig);
  for (;;) {
    const pid_t w = ::waitpid(pid, &st, WNOHANG);
    if (w == pid) break;
    if (std::chrono::steady_clock::now() - t0 > std::chrono::seconds(30)) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &st, 0);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  k.wait_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  k.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  k.err = slurp(err_path);
  fs::remove(err_path);
  return k;
}

// Every file of `dir` (recursively) that is not in `expected` with its content.
std::vector<std::string> unexpected_files(const fs::path& dir, const std::map<std::string, std::string>& expected) {
  std::vector<std::string> bad;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    const std::string rel = fs::relative(e.path(), dir).string();
    const auto it = expected.find(rel);
    if (it == expected.end()) bad.push_back(rel + " (" + std::to_string(fs::file_size(e.path())) + " bytes, not expected)");
    else if (slurp(e.path()) != it->second) bad.push_back(rel + " (changed)");
  }
  return bad;
}

void check_interrupt(const std::string& name, const std::vector<std::string>& args, int sig, const std::map<std::string, std::string>& old,
                     const std::vector<std::string>& new_files = {}) {
  Scratch s(name);
  for (const auto& [f, text] : old) {
    fs::create_directories((s.dir / f).parent_path());
    std::ofstream(s.dir / f) << text;
  }
  const Killed k = start_and_signal(s.dir, args, sig, 2.0);
  ASSERT_TRUE(k.was_running) << name << " finished before the signal; stderr:\n" << k.err;
  // Reported, not asserted (tests assert no timing): the time from the signal to the exit.
  std::cout << "[ interrupt ] " << name << ": exit " << k.status << " " << k.wait_s << " s after the signal\n";
  EXPECT_EQ(k.status, 128 + sig) << k.err;
  const std::string signame = sig == SIGINT ? "SIGINT" : "SIGTERM";
  EXPECT_NE(k.err.find("interrupted by " + signame), std::string::npos) << k.err;
  // The previous run's files are intact; nothing else is there (no temporary, no placeholder).
  std::map<std::string, std::string> expect = old;
  for (const auto& f : new_files) expect.erase(f);
  auto bad = unexpected_files(s.dir, expect);
  // Files this run may have finished whole: allowed, when complete (not checked byte by byte).
  bad.erase(std::remove_if(bad.begin(), bad.end(),
                           [&](const std::string& b) {
                             for (const auto& f : new_files)
                               if (b.rfind(f + " ", 0) == 0) return true;
                             return false;
                           }),
            bad.end());
  EXPECT_TRUE(bad.empty()) << name << ": " << ::testing::PrintToString(bad);
}

}  // namespace

TEST(Interrupt, SigtermStopsARenderAndKeepsThePreviousOutputs) {
  check_interrupt("render", {"render", "spd:balls:3", "--width", "2048", "--height", "2048", "-r", "5", "-o", "out.png", "--json", "out.json"},
                  SIGTERM, {{"out.png", "OLD PNG"}, {"out.json", "{\"old\": true}\n"}});
}

TEST(Interrupt, SigintStopsATraceAndLeavesNoNewFile) {
  // out.json does not exist yet, and the interrupted run leaves none behind (no temporary, no empty file).
  check_interrupt("trace", {"trace", "spd:balls:3", "--count", "2000000", "--no-embree", "-r", "50", "--json", "out.json"}, SIGINT,
                  {{"keep.txt", "unrelated\n"}});
}

TEST(Interrupt, SigtermStopsAReportAndKeepsThePreviousReport) {
  check_interrupt("report", {"report", "--out", "rep", "--no-history"}, SIGTERM,
                  {{"rep/index.md", "# the previous report\n"}, {"rep/summary.json", "{\"old\": true}\n"}, {"rep/bench.json", "{}\n"}},
                  {"rep/ops.json"});
}

// Load: `trace` and `render` at 64 and 256 threads on this machine (whatever its cores) finish
// with the same answers as on one thread: every ray's hit and every pixel, by their digests.
TEST(Load, TraceAndRenderAt64And256ThreadsGiveTheOneThreadResults) {
  Scratch s("load");
  std::string trace_ref, render_ref;
  for (int threads : {1, 64, 256}) {
    const Outcome t = run_in(s.dir, "trace spd:balls:1 --rays diffuse --packet 8 --count 2048 --no-embree -r 1 --warmup 0 --brute 0 --threads " +
                                        std::to_string(threads) + " --json");
    ASSERT_EQ(t.status, 0) << t.err;
    const std::string d = t.json().at("hits_fnv1a").get<std::string>();
    if (threads == 1) trace_ref = d;
    EXPECT_EQ(d, trace_ref) << threads << " threads";
    const Outcome r = run_in(s.dir, "render lecture:five_glass_balls --width 48 --height 32 -r 1 --warmup 0 -o img.png --threads " +
                                        std::to_string(threads) + " --json");
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string e = r.json().at("image_fnv1a").get<std::string>();
    if (threads == 1) render_ref = e;
    EXPECT_EQ(e, render_ref) << threads << " threads";
  }
}
