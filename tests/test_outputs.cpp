// Where outputs go (core/output_file.hpp): a regular file or a new path is replaced whole, a
// symlink is followed and stays a link, a FIFO or a character device is written as it is, a
// process's own descriptors (/dev/stdout, "-") are written directly, and a directory, a socket or
// a block device is refused before the work. The rule is tested as a function, then through the
// command line of trace, render, report and history as a user meets it.
#include "core/output_file.hpp"
#include "cli_test_util.hpp"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <future>
#include <string>
#include <vector>

namespace {

using namespace rbtest;

// What a path is, without following it: its type, inode and device number.
struct Node {
  bool exists = false;
  mode_t type = 0;
  ino_t ino = 0;
  dev_t rdev = 0;
  bool operator==(const Node& o) const { return exists == o.exists && type == o.type && ino == o.ino && rdev == o.rdev; }
};
Node node(const std::string& p) {
  struct stat st {};
  Node n;
  if (::lstat(p.c_str(), &st) != 0) return n;
  return {true, mode_t(st.st_mode & S_IFMT), st.st_ino, st.st_rdev};
}
std::ostream& operator<<(std::ostream& o, const Node& n) { return o << "{type " << std::oct << n.type << std::dec << ", inode " << n.ino << "}"; }

// Hidden temporaries (".NAME.tmp-PID") left in `dir`.
std::vector<std::string> temporaries(const fs::path& dir) {
  std::vector<std::string> t;
  for (const auto& e : fs::directory_iterator(dir))
    if (has(e.path().filename().string(), ".tmp-")) t.push_back(e.path().string());
  return t;
}

// A character device made for the test (a copy of /dev/null), or "" where this process may not
// make one (not root, or a container without the capability).
std::string make_null_device(const Scratch& s, const std::string& name) {
  if (::geteuid() != 0) return "";
  const std::string p = s / name;
  if (::mknod(p.c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0) return "";
  return p;
}

// Reads a FIFO to its end in another thread: started before the writer, so the writer finds a
// reader waiting.
std::future<std::string> read_fifo(const std::string& path) {
  return std::async(std::launch::async, [path] {
    std::string got;
    const int fd = ::open(path.c_str(), O_RDONLY);
    if (fd < 0) return got;
    char buf[65536];
    for (ssize_t n; (n = ::read(fd, buf, sizeof buf)) != 0;) {
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) break;
      got.append(buf, std::size_t(n));
    }
    ::close(fd);
    return got;
  });
}

bool is_png(const std::string& bytes) { return bytes.size() > 8 && bytes.compare(0, 4, "\x89PNG") == 0; }
bool is_json(const std::string& text) { return !text.empty() && nlohmann::json::accept(text); }

// ---- the rule as a function ---------------------------------------------------------------------

TEST(OutputRule, ClassifiesEveryKindOfPath) {
  Scratch s("output-rule");
  using K = rb::OutputTarget;
  std::ofstream(s / "file") << "old";
  fs::create_directory(s.dir / "dir");
  fs::create_symlink("file", s.dir / "link");                // relative, resolved from the link's folder
  fs::create_symlink(s / "link", s.dir / "link2");           // a chain
  fs::create_symlink("dir/new.json", s.dir / "dangling");    // to a file not there yet
  fs::create_symlink("loop_b", s.dir / "loop_a");
  fs::create_symlink("loop_a", s.dir / "loop_b");
  ASSERT_EQ(::mkfifo((s / "fifo").c_str(), 0600), 0);

  EXPECT_EQ(rb::output_target(s / "file").kind, K::kRegular);
  EXPECT_EQ(rb::output_target(s / "absent.json").kind, K::kNewFile);
  rb::OutputTarget t = rb::output_target(s / "link2");
  EXPECT_EQ(t.kind, K::kRegular);
  EXPECT_EQ(fs::canonical(t.file), fs::canonical(s / "file"));
  t = rb::output_target(s / "dangling");
  EXPECT_EQ(t.kind, K::kNewFile);
  EXPECT_EQ(fs::path(t.file).filename(), "new.json");
  EXPECT_EQ(rb::output_target(s / "fifo").kind, K::kStream);
  EXPECT_EQ(rb::output_target("/dev/null").kind, K::kStream);
  EXPECT_EQ(rb::output_target(s / "dir").why, std::strerror(EISDIR));
  EXPECT_EQ(rb::output_target(s / "loop_a").why, std::strerror(ELOOP));
  EXPECT_EQ(rb::output_target(s / "file/x.json").why, std::strerror(ENOTDIR));
  EXPECT_EQ(rb::output_target(s / "missing/x.json").why, std::strerror(ENOENT));
  EXPECT_TRUE(has(rb::output_target("/dev/raybench-no-such-device").why, "/dev")) << "a new file in /dev is refused";

  // The process's own descriptors.
  for (const char* p : {"-", "/dev/stdout", "/dev/fd/1", "/proc/self/fd/1"}) {
    t = rb::output_target(p);
    EXPECT_EQ(t.kind, K::kDescriptor) << p;
    EXPECT_EQ(t.fd, 1) << p;
    EXPECT_TRUE(rb::is_standard_output(p)) << p;
  }
  EXPECT_EQ(rb::output_target("/dev/stderr").fd, 2);
  EXPECT_FALSE(rb::is_standard_output("/dev/fd/12"));
  EXPECT_TRUE(has(rb::output_target("/dev/fd/987").why, "not open"));
  const int ro = ::open((s / "file").c_str(), O_RDONLY);
  EXPECT_TRUE(has(rb::output_target("/dev/fd/" + std::to_string(ro)).why, "not open for writing"));
  ::close(ro);

  // A socket and (as root) a block device: refused, with the reason.
  const int sock = ::socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un addr {};
  addr.sun_family = AF_UNIX;
  const std::string sp = s / "sock";
  ASSERT_LT(sp.size(), sizeof addr.sun_path);
  std::memcpy(addr.sun_path, sp.c_str(), sp.size() + 1);
  ASSERT_EQ(::bind(sock, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  EXPECT_TRUE(has(rb::output_target(sp).why, "socket"));
  ::close(sock);
  if (::geteuid() == 0 && ::mknod((s / "blk").c_str(), S_IFBLK | 0600, makedev(7, 200)) == 0) {
    EXPECT_TRUE(has(rb::output_target(s / "blk").why, "block device"));
  }
}

TEST(OutputRule, WritesEachKindAndKeepsWhatThePathIs) {
  Scratch s("output-write");
  std::ofstream(s / "file") << "old";
  ::chmod((s / "file").c_str(), 0640);
  fs::create_symlink("file", s.dir / "link");
  fs::create_symlink("made.json", s.dir / "dangling");
  const Node link = node(s / "link"), dangling = node(s / "dangling");

  rb::write_output(s / "link", "via the link");
  EXPECT_EQ(node(s / "link"), link);
  EXPECT_EQ(slurp(s / "file"), "via the link");
  EXPECT_EQ(fs::status(s.dir / "file").permissions() & fs::perms::all, fs::perms(0640)) << "the file keeps its permission bits";
  rb::write_output(s / "dangling", "made");
  EXPECT_EQ(node(s / "dangling"), dangling);
  EXPECT_EQ(slurp(s / "made.json"), "made");
  EXPECT_TRUE(temporaries(s.dir).empty());

  // A FIFO with a reader: the reader gets every byte, and the FIFO stays a FIFO.
  ASSERT_EQ(::mkfifo((s / "fifo").c_str(), 0600), 0);
  const Node fifo = node(s / "fifo");
  const std::string big(1 << 20, 'x');  // more than a pipe holds at once
  auto got = read_fifo(s / "fifo");
  rb::write_output(s / "fifo", big);
  EXPECT_EQ(got.get(), big);
  EXPECT_EQ(node(s / "fifo"), fifo);

  // A reader that takes a little and leaves: EPIPE, reported, and the process lives on.
  auto quitter = std::async(std::launch::async, [p = s / "fifo"] {
    const int fd = ::open(p.c_str(), O_RDONLY);
    char c;
    (void)!::read(fd, &c, 1);
    ::close(fd);
  });
  std::string what;
  try {
    rb::write_output(s / "fifo", big);
  } catch (const std::exception& e) {
    what = e.what();
  }
  quitter.get();
  EXPECT_TRUE(has(what, std::strerror(EPIPE))) << what;

  // A device: written in place; /dev/full reports its ENOSPC.
  if (const std::string dev = make_null_device(s, "null"); !dev.empty()) {
    const Node before = node(dev);
    rb::write_output(dev, "discarded");
    EXPECT_EQ(node(dev), before);
  }
  if (fs::exists("/dev/full")) {
    const Node before = node("/dev/full");
    try {
      rb::write_output("/dev/full", "x");
      ADD_FAILURE() << "/dev/full took the bytes";
    } catch (const std::exception& e) {
      EXPECT_TRUE(has(e.what(), "/dev/full") && has(e.what(), std::strerror(ENOSPC))) << e.what();
    }
    EXPECT_EQ(node("/dev/full"), before);
  }
  EXPECT_TRUE(temporaries(s.dir).empty());
}

// ---- through the command line -------------------------------------------------------------------

// One output option of one command, to be pointed at each kind of path.
struct Case {
  std::string name;
  std::string args;  // the command line with "OUT" where the path goes
  bool png = false;  // the output is a PNG (else JSON)
};

// The commands' outputs: each needs what `prepare` leaves in the folder (a mesh, a history).
std::vector<Case> cases() {
  return {{"trace --json", "trace oct.obj --count 64 -r 1 --warmup 0 --no-embree --brute 0 --json OUT"},
          {"render -o", "render oct.obj --width 8 -r 1 --warmup 0 -o OUT", true},
          {"render --json", "render oct.obj --width 8 -r 1 --warmup 0 -o img.png --json OUT"},
          {"history --json", "history --history h.sqlite --json OUT"},
          {"history --plot", "history --history h.sqlite --metric mrays_per_s --plot OUT", true}};
}

std::string with(const std::string& args, const std::string& out) {
  std::string a = args;
  a.replace(a.find("OUT"), 3, "'" + out + "'");
  return a;
}

void prepare(const Scratch& s) {
  std::ofstream(s / "oct.obj") << kOctahedron;
  const Outcome r = run_in(s.dir, "trace oct.obj --count 64 -r 1 --warmup 0 --no-embree --history h.sqlite");
  ASSERT_EQ(r.status, 0) << r.err;
}

bool right_content(const Case& c, const std::string& bytes) { return c.png ? is_png(bytes) : is_json(bytes); }

TEST(Outputs, SymlinksAreFollowedAndStayLinks) {
  Scratch s("outputs-links");
  prepare(s);
  fs::create_directory(s.dir / "targets");
  for (const Case& c : cases()) {
    // A link to an existing file, and a dangling link to a file in another folder.
    std::ofstream(s / "targets/old") << "old";
    fs::remove(s.dir / "link");
    fs::remove(s.dir / "dangling");
    fs::remove(s.dir / "targets/new");
    fs::create_symlink("targets/old", s.dir / "link");
    fs::create_symlink(s / "targets/new", s.dir / "dangling");
    for (const char* l : {"link", "dangling"}) {
      const Node before = node(s / l);
      const Outcome r = run_in(s.dir, with(c.args, l));
      EXPECT_EQ(r.status, 0) << c.name << " " << l << ": " << r.err;
      EXPECT_EQ(node(s / l), before) << c.name << ": the link is still the same link";
      EXPECT_TRUE(right_content(c, slurp(s / (std::string("targets/") + (l == std::string("link") ? "old" : "new")))))
          << c.name << " " << l << ": the target holds the output";
    }
    EXPECT_TRUE(temporaries(s.dir).empty() && temporaries(s.dir / "targets").empty()) << c.name;
  }
}

TEST(Outputs, AFifosReaderGetsTheWholeOutput) {
  Scratch s("outputs-fifo");
  prepare(s);
  ASSERT_EQ(::mkfifo((s / "fifo").c_str(), 0600), 0);
  const Node fifo = node(s / "fifo");
  for (const Case& c : cases()) {
    auto got = read_fifo(s / "fifo");
    const Outcome r = run_in(s.dir, with(c.args, "fifo"));
    EXPECT_EQ(r.status, 0) << c.name << ": " << r.err;
    EXPECT_TRUE(right_content(c, got.get())) << c.name;
    EXPECT_EQ(node(s / "fifo"), fifo) << c.name;
  }
  EXPECT_TRUE(temporaries(s.dir).empty());
}

TEST(Outputs, DevicesAreWrittenInPlaceAndTheirErrorsReported) {
  Scratch s("outputs-devices");
  prepare(s);
  const std::string dev = make_null_device(s, "null");
  for (const Case& c : cases()) {
    if (!dev.empty()) {
      const Node before = node(dev);
      const Outcome r = run_in(s.dir, with(c.args, dev));
      EXPECT_EQ(r.status, 0) << c.name << ": " << r.err;
      EXPECT_EQ(node(dev), before) << c.name << ": the device is still the device";
    }
    if (fs::exists("/dev/full")) {
      const Node before = node("/dev/full");
      const Outcome r = run_in(s.dir, with(c.args, "/dev/full"));
      EXPECT_EQ(r.status, 1) << c.name;
      EXPECT_TRUE(has(r.err, "/dev/full") && has(r.err, std::strerror(ENOSPC))) << c.name << ": " << r.err;
      EXPECT_EQ(node("/dev/full"), before) << c.name;
    }
  }
  if (dev.empty()) std::cout << "[ skipped  ] a character device of the test's own: not root, or mknod not permitted\n";
}

TEST(Outputs, StandardOutputByName) {
  Scratch s("outputs-stdout");
  prepare(s);
  // The JSON alone on standard output, whichever name it is given by.
  for (const char* p : {"-", "/dev/stdout", "/dev/fd/1"}) {
    const Outcome r = run_in(s.dir, with(cases()[0].args, p));
    EXPECT_EQ(r.status, 0) << p << ": " << r.err;
    EXPECT_TRUE(is_json(r.out)) << p << ": " << r.out.substr(0, 200);
  }
  // The image on standard output: the table moves to stderr; the JSON then needs a file.
  for (const char* p : {"-", "/dev/stdout"}) {
    Outcome r = run_in(s.dir, with(cases()[1].args, p));
    EXPECT_EQ(r.status, 0) << p << ": " << r.err;
    EXPECT_TRUE(is_png(r.out)) << p;
    EXPECT_TRUE(has(r.err, "standard output")) << r.err;
    r = run_in(s.dir, with(cases()[1].args, p) + " --json");
    EXPECT_EQ(r.status, 1) << p;
    EXPECT_TRUE(has(r.err, "cannot both go to standard output")) << r.err;
    EXPECT_EQ(r.out, "");
  }
  const Outcome r = run_in(s.dir, with(cases()[4].args, "-"));
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(is_png(r.out));
}

TEST(Outputs, WhatCannotBeWrittenIsRefusedBeforeTheWork) {
  Scratch s("outputs-refused");
  prepare(s);
  fs::create_directory(s.dir / "dir");
  const int sock = ::socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un addr {};
  addr.sun_family = AF_UNIX;
  const std::string sp = s / "sock";
  std::memcpy(addr.sun_path, sp.c_str(), sp.size() + 1);
  ASSERT_EQ(::bind(sock, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  std::vector<std::string> bad = {"dir", "sock"};
  if (::geteuid() == 0 && ::mknod((s / "blk").c_str(), S_IFBLK | 0600, makedev(7, 200)) == 0) bad.push_back("blk");
  std::vector<Case> all = cases();
  all.push_back({"report --json", "report -o rep --no-history --json OUT"});
  for (const Case& c : all)
    for (const auto& b : bad) {
      const Node before = node(s / b);
      const Outcome r = run_in(s.dir, with(c.args, b));
      EXPECT_EQ(r.status, 1) << c.name << " " << b;
      EXPECT_TRUE(has(r.err, b)) << c.name << ": the path is named: " << r.err;
      EXPECT_FALSE(has(r.err, "thread(s) of")) << c.name << ": refused before the work: " << r.err;
      EXPECT_EQ(r.out, "") << c.name;
      EXPECT_EQ(node(s / b), before) << c.name;
    }
  ::close(sock);
  EXPECT_FALSE(fs::exists(s.dir / "rep/index.md"));
  // A results history cannot live in a device or a FIFO (SQLite keeps a journal beside it).
  ASSERT_EQ(::mkfifo((s / "fifo").c_str(), 0600), 0);
  for (const char* h : {"/dev/null", "fifo"}) {
    const Outcome r = run_in(s.dir, std::string("trace oct.obj --count 64 -r 1 --no-embree --history ") + h);
    EXPECT_EQ(r.status, 1) << h;
    EXPECT_TRUE(has(r.err, "regular file")) << r.err;
  }
}

// The report writes a folder of files: one run, with a file of the folder a symlink, one a FIFO
// with a reader, one a character device (as root), and the summary JSON to /dev/full, written last:
// the report fails with the device's error and exit 1 after writing everything else where it
// pointed. (A quick report without charts and with one benchmark: still minutes under the
// sanitizers, so one run for every kind, in a ctest entry of its own: tests/CMakeLists.txt.)
TEST(Outputs, AReportFollowsTheRuleForEveryFileItWrites) {
  Scratch s("outputs-report");
  fs::create_directory(s.dir / "rep");
  std::ofstream(s / "kept.md") << "old";
  fs::create_symlink("../kept.md", s.dir / "rep/index.md");
  ASSERT_EQ(::mkfifo((s / "rep/index.html").c_str(), 0600), 0);
  const std::string dev = make_null_device(s, "rep/ops.json");
  const Node link = node(s / "rep/index.md"), fifo = node(s / "rep/index.html"), device = dev.empty() ? Node{} : node(dev);
  auto html = read_fifo(s / "rep/index.html");
  const bool full = fs::exists("/dev/full");
  const Outcome r = run_in(s.dir, std::string("report --quick --no-charts --no-history --filter '^sphere/geometric/scalar/hit$' -o rep --json ") + (full ? "/dev/full" : "summary.json"));
  const std::string page = html.get();
  if (full) {
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_TRUE(has(r.err, "/dev/full") && has(r.err, std::strerror(ENOSPC))) << r.err;
  } else {
    EXPECT_EQ(r.status, 0) << r.err;
  }
  EXPECT_EQ(node(s / "rep/index.md"), link);
  EXPECT_TRUE(has(slurp(s / "kept.md"), "# ")) << "the link's target holds the report";
  // With no pgo.md in the folder, the PGO section says how to measure it.
  EXPECT_TRUE(has(slurp(s / "kept.md"), "Profile-guided optimisation\n\nNot measured for this report")) << "the PGO placeholder";
  EXPECT_EQ(node(s / "rep/index.html"), fifo);
  EXPECT_TRUE(has(page, "<html") && has(page, "</html>")) << page.substr(0, 200);
  if (!dev.empty()) {
    EXPECT_EQ(node(dev), device);
  }
  EXPECT_TRUE(is_json(slurp(s / "rep/tracing.json")));
  EXPECT_TRUE(temporaries(s.dir / "rep").empty() && temporaries(s.dir).empty());
  // --no-charts: the page names the charts it leaves out rather than linking missing files.
  EXPECT_FALSE(has(r.err, ".png\": no such file beside the page")) << r.err;
  EXPECT_TRUE(has(slurp(s / "kept.md"), "_Chart not drawn (`--no-charts`)")) << "an undrawn chart named";

  // The same page again from the folder's record, without measuring: the one line that says so added.
  const std::string first = slurp(s / "kept.md");
  auto html2 = read_fifo(s / "rep/index.html");
  const Outcome again = run_in(s.dir, "report --from rep --no-charts");
  EXPECT_TRUE(has(html2.get(), "</html>"));
  EXPECT_EQ(again.status, 0) << again.err;
  std::string second = slurp(s / "kept.md");
  const std::string added = "Written again from its record (measured.json) by `raybench report --from rep`.\n";
  ASSERT_TRUE(has(second, added)) << second.substr(second.size() > 400 ? second.size() - 400 : 0);
  second.erase(second.find(added), added.size());
  EXPECT_EQ(second, first);
  EXPECT_FALSE(has(again.err, "  load ")) << "nothing measured again (no scene loaded): " << again.err;

  // A PGO section left in the folder by `./run.sh pgo` is carried; measured on another revision, it says so.
  std::ofstream(s / "rep/pgo.md") << "## Profile-guided optimisation\n\nPGO / normal 1.01x.\n";
  std::ofstream(s / "rep/pgo.json") << R"({"context": {"normal": {"raybench_git": "0000000"}}})";
  auto html3 = read_fifo(s / "rep/index.html");
  const Outcome pgo = run_in(s.dir, "report --from rep --no-charts");
  EXPECT_TRUE(has(html3.get(), "</html>"));
  EXPECT_EQ(pgo.status, 0) << pgo.err;
  const std::string third = slurp(s / "kept.md");
  EXPECT_TRUE(has(third, "Profile-guided optimisation\n\n**Measured on revision `0000000`, not on this report's")) << "the stale section";
  EXPECT_TRUE(has(third, "PGO / normal 1.01x.\n\n<!-- /pgo-section -->")) << "the section's own text";
}

// A folder the user may not write to, for every command's outputs (the history file itself is
// readable by all): as root the check is made as another user (root may write anywhere), where the
// system lets this process become one.
TEST(Outputs, AReadOnlyFolderIsRefusedBeforeTheWork) {
  Scratch s("outputs-readonly");
  prepare(s);
  fs::create_directory(s.dir / "ro");
  ::chmod((s / "ro").c_str(), 0555);
  std::string as_user;
  if (::geteuid() == 0) {
    as_user = "setpriv --reuid=65534 --regid=65534 --clear-groups ";
    const Outcome probe = run_in(s.dir, "--version", "", "", as_user + RB_RAYBENCH);
    if (probe.status != 0) {
      std::cout << "[ skipped  ] a read-only folder for another user: cannot run raybench as uid 65534 here (" << probe.err << ")\n";
      ::chmod((s / "ro").c_str(), 0755);
      return;
    }
  }
  std::vector<Case> all = cases();
  all.push_back({"report --json", "report -o rep --no-history --json OUT"});
  all.push_back({"report -o", "report --no-history -o OUT/rep"});
  for (const Case& c : all) {
    const Outcome r = run_in(s.dir, with(c.args, "ro/out"), "", "", as_user + RB_RAYBENCH);
    EXPECT_EQ(r.status, 1) << c.name << ": " << r.err;
    EXPECT_TRUE(has(r.err, std::strerror(EACCES))) << c.name << ": " << r.err;
    EXPECT_FALSE(has(r.err, "thread(s) of")) << c.name << ": refused before the work: " << r.err;
  }
  EXPECT_TRUE(fs::is_empty(s.dir / "ro"));
  ::chmod((s / "ro").c_str(), 0755);
}

}  // namespace
