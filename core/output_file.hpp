// Where an output goes, one rule for every file raybench writes (JSON, markdown, HTML, PNG,
// charts, Google Benchmark JSON, scenes):
//  - a regular file, or a path that does not exist yet, is written whole or not at all: the bytes
//    go to a hidden temporary beside the file (".NAME.tmp-PID"), renamed over it once complete,
//    so a reader (or the next run) sees the previous file or the new one, never half of one. An
//    existing file keeps its permission bits.
//  - a symbolic link is followed (link by link, a dangling one included) and its final target
//    written by the rule for that target, the temporary beside the target: the link stays a link.
//  - a FIFO or a character device (/dev/null, /dev/full, a terminal) is written directly, with no
//    temporary and no rename: the path keeps its type and inode. A FIFO nobody reads yet is waited
//    for, saying so on stderr.
//  - "-", /dev/stdout, /dev/stderr, /dev/fd/N and /proc/self/fd/N name this process's own
//    descriptors ("-" is standard output): the bytes are written to that descriptor as it is.
//  - a directory, a socket or a block device is refused, naming the path; so is a new file
//    directly in /dev.
// Every write and close error (ENOSPC from /dev/full, EPIPE from a FIFO whose reader left) is an
// exception naming the path and the system's reason. The temporaries being written are listed in
// a fixed table that an interrupt handler may read (async-signal-safe: no allocation, one atomic
// flag per slot) to unlink them before the process exits (apps/interrupt.cpp).
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <stdexcept>
#include <string>
#include <string_view>

namespace rb {

// The temporaries in flight (at most kSlots at a time; a writer beyond that waits for none and
// simply is not listed, so an interrupt may then leave its hidden temporary behind).
struct TempFiles {
  static constexpr int kSlots = 16;
  static constexpr std::size_t kPath = 4096;
  std::atomic<int> used[kSlots] = {};
  char path[kSlots][kPath] = {};
  int add(const std::string& p) {
    if (p.size() >= kPath) return -1;
    for (int i = 0; i < kSlots; ++i) {
      int expect = 0;
      if (used[i].compare_exchange_strong(expect, 2)) {  // 2: being filled, not yet readable
        std::memcpy(path[i], p.c_str(), p.size() + 1);
        used[i].store(1);
        return i;
      }
    }
    return -1;
  }
  void remove(int slot) {
    if (slot >= 0) used[slot].store(0);
  }
  // From a signal handler: unlink every listed temporary.
  void unlink_all() {
    for (int i = 0; i < kSlots; ++i)
      if (used[i].load() == 1) ::unlink(path[i]);
  }
};
inline TempFiles& temp_files() {
  static TempFiles t;
  return t;
}

// What a path is as an output, after the rule above.
struct OutputTarget {
  enum Kind {
    kNewFile,     // nothing there yet: created whole through a temporary in `file`'s folder
    kRegular,     // a regular file: replaced whole through a temporary in its folder
    kStream,      // a FIFO or a character device: opened and written directly
    kDescriptor,  // one of this process's descriptors (`fd`): written as it is
    kRefused,     // `why` says why (a directory, a socket, a block device, a broken path)
  };
  Kind kind = kRefused;
  std::string file;  // the path the bytes go to: the symlinks' final target, or the path itself
  int fd = -1;       // kDescriptor
  std::string why;   // kRefused: the reason, without the path
};

namespace output_detail {

inline std::string folder_of(const std::string& path) {
  const std::size_t slash = path.rfind('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

// "-", /dev/stdout, /dev/stderr, /dev/stdin, /dev/fd/N, /proc/self/fd/N, /proc/PID/fd/N (PID
// this process): the descriptor's number, else -1.
inline int descriptor_named(const std::string& p) {
  if (p == "-" || p == "/dev/stdout") return 1;
  if (p == "/dev/stderr") return 2;
  if (p == "/dev/stdin") return 0;
  std::string rest;
  const std::string own = "/proc/" + std::to_string(::getpid()) + "/fd/";
  for (const std::string& pre : {std::string("/dev/fd/"), std::string("/proc/self/fd/"), own})
    if (p.size() > pre.size() && p.compare(0, pre.size(), pre) == 0) rest = p.substr(pre.size());
  if (rest.empty() || rest.size() > 9 || rest.find_first_not_of("0123456789") != std::string::npos) return -1;
  return std::atoi(rest.c_str());
}

}  // namespace output_detail

// True when `path` is this process's standard output ("-", /dev/stdout, /dev/fd/1, ...).
inline bool is_standard_output(const std::string& path) { return output_detail::descriptor_named(path) == 1; }

// Classifies `path` by the rule at the top of this file, following symbolic links one by one.
inline OutputTarget output_target(const std::string& path) {
  using output_detail::descriptor_named;
  using output_detail::folder_of;
  OutputTarget t;
  if (path.empty()) {
    t.why = std::strerror(ENOENT);
    return t;
  }
  std::string cur = path;
  for (int hop = 0; hop < 40; ++hop) {
    if (const int fd = descriptor_named(cur); fd >= 0) {
      const int fl = ::fcntl(fd, F_GETFL);
      if (fl < 0) {
        t.why = "descriptor " + std::to_string(fd) + " is not open";
      } else if ((fl & O_ACCMODE) == O_RDONLY) {
        t.why = "descriptor " + std::to_string(fd) + " is not open for writing";
      } else {
        t.kind = OutputTarget::kDescriptor;
        t.fd = fd;
      }
      t.file = cur;
      return t;
    }
    struct stat st {};
    if (::lstat(cur.c_str(), &st) != 0) {
      if (errno != ENOENT) {
        t.why = std::strerror(errno);
        return t;
      }
      const std::string dir = folder_of(cur);
      struct stat ds {};
      if (::stat(dir.c_str(), &ds) != 0) {
        t.why = (cur == path ? "" : "the link's target " + cur + ": ") + std::strerror(errno);
      } else if (!S_ISDIR(ds.st_mode)) {
        t.why = std::strerror(ENOTDIR);
      } else if (dir == "/dev") {
        t.why = "does not exist, and raybench creates no files in /dev (a device there is written as it is)";
      } else {
        t.kind = OutputTarget::kNewFile;
        t.file = cur;
      }
      return t;
    }
    if (S_ISLNK(st.st_mode)) {
      char buf[4096];
      const ssize_t n = ::readlink(cur.c_str(), buf, sizeof buf - 1);
      if (n < 0) {
        t.why = std::strerror(errno);
        return t;
      }
      const std::string to(buf, std::size_t(n));
      cur = to.empty() || to[0] == '/' ? to : folder_of(cur) + "/" + to;
      continue;
    }
    t.file = cur;
    if (S_ISREG(st.st_mode)) t.kind = OutputTarget::kRegular;
    else if (S_ISFIFO(st.st_mode) || S_ISCHR(st.st_mode)) t.kind = OutputTarget::kStream;
    else if (S_ISDIR(st.st_mode)) t.why = std::strerror(EISDIR);
    else if (S_ISSOCK(st.st_mode)) t.why = "is a socket (raybench writes files, FIFOs and character devices)";
    else if (S_ISBLK(st.st_mode)) t.why = "is a block device (raybench writes files, FIFOs and character devices)";
    else t.why = "is neither a file, a FIFO nor a character device";
    return t;
  }
  t.why = std::strerror(ELOOP);
  return t;
}

// The hidden temporary beside `file`.
inline std::string temp_path_for(const std::string& file) {
  const std::size_t slash = file.rfind('/');
  const std::string dir = slash == std::string::npos ? "" : file.substr(0, slash + 1);
  const std::string name = slash == std::string::npos ? file : file.substr(slash + 1);
  return dir + "." + name + ".tmp-" + std::to_string(::getpid());
}

namespace output_detail {

// SIGPIPE ignored while in scope, so a reader that left shows as EPIPE, not as a silent death.
struct NoSigpipe {
  struct sigaction old {};
  NoSigpipe() {
    struct sigaction ign {};
    ign.sa_handler = SIG_IGN;
    sigemptyset(&ign.sa_mask);
    ::sigaction(SIGPIPE, &ign, &old);
  }
  ~NoSigpipe() { ::sigaction(SIGPIPE, &old, nullptr); }
};

// Writes all of `data` to `fd`; 0 or the errno of the failure.
inline int write_all(int fd, std::string_view data) {
  std::size_t off = 0;
  while (off < data.size()) {
    const ssize_t n = ::write(fd, data.data() + off, data.size() - off);
    if (n < 0) {
      if (errno == EINTR) continue;
      if (errno == EAGAIN) {  // a descriptor someone left non-blocking: wait until it drains
        ::usleep(1000);
        continue;
      }
      return errno;
    }
    off += std::size_t(n);
  }
  return 0;
}

[[noreturn]] inline void fail(const std::string& path, int err) {
  throw std::runtime_error("cannot write " + path + ": " + std::strerror(err));
}

inline void write_whole(const std::string& path, const OutputTarget& t, std::string_view data) {
  const std::string tmp = temp_path_for(t.file);
  const int slot = temp_files().add(tmp);
  auto give_up = [&](int err) {
    ::unlink(tmp.c_str());
    temp_files().remove(slot);
    fail(path, err);
  };
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) {
    const int err = errno;
    temp_files().remove(slot);
    fail(path, err);
  }
  struct stat st {};
  if (t.kind == OutputTarget::kRegular && ::stat(t.file.c_str(), &st) == 0) (void)::fchmod(fd, st.st_mode & 07777);
  if (const int err = write_all(fd, data); err != 0) {
    ::close(fd);
    give_up(err);
  }
  if (::close(fd) != 0) give_up(errno);
  if (std::rename(tmp.c_str(), t.file.c_str()) != 0) give_up(errno);
  temp_files().remove(slot);
}

inline void write_stream(const std::string& path, const OutputTarget& t, std::string_view data) {
  NoSigpipe quiet;
  int fd = ::open(t.file.c_str(), O_WRONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
  if (fd < 0 && errno == ENXIO) {  // a FIFO with no reader yet: wait for one, as a shell would
    std::cerr << "raybench: " << path << " is a FIFO with no reader yet; waiting for one (Ctrl-C stops)\n";
    do fd = ::open(t.file.c_str(), O_WRONLY | O_CLOEXEC | O_NOCTTY);
    while (fd < 0 && errno == EINTR);
  }
  if (fd < 0) fail(path, errno);
  const int fl = ::fcntl(fd, F_GETFL);
  if (fl >= 0) (void)::fcntl(fd, F_SETFL, fl & ~O_NONBLOCK);
  if (const int err = write_all(fd, data); err != 0) {
    ::close(fd);
    fail(path, err);
  }
  if (::close(fd) != 0) fail(path, errno);
}

inline void write_descriptor(const std::string& path, const OutputTarget& t, std::string_view data) {
  std::cout.flush();  // what the program printed before comes first
  std::cerr.flush();
  std::fflush(nullptr);
  NoSigpipe quiet;
  if (const int err = write_all(t.fd, data); err != 0) fail(path == "-" ? "standard output" : path, err);
}

}  // namespace output_detail

// Writes `data` to `path` by the rule at the top of this file. Throws std::runtime_error naming
// the path and the system's reason; a temporary is gone on failure.
inline void write_output(const std::string& path, std::string_view data) {
  const OutputTarget t = output_target(path);
  switch (t.kind) {
    case OutputTarget::kNewFile:
    case OutputTarget::kRegular: output_detail::write_whole(path, t, data); return;
    case OutputTarget::kStream: output_detail::write_stream(path, t, data); return;
    case OutputTarget::kDescriptor: output_detail::write_descriptor(path, t, data); return;
    case OutputTarget::kRefused: break;
  }
  throw std::runtime_error("cannot write " + path + ": " + t.why);
}

// Whether an output just written to `path` can be read back (a regular file, or a link to one; a
// FIFO or a device cannot): the report's chart scripts read the JSON it wrote.
inline bool readable_back(const std::string& path) { return output_target(path).kind == OutputTarget::kRegular; }

// Whether `path` can take an output, checked before a long run: "" if so, else the reason. A FIFO
// is not opened (its reader would see the end of the data); a new file's folder must be writable.
inline std::string output_problem(const std::string& path) {
  const OutputTarget t = output_target(path);
  switch (t.kind) {
    case OutputTarget::kRefused: return t.why;
    case OutputTarget::kDescriptor: return "";
    case OutputTarget::kStream:
    case OutputTarget::kRegular:
      if (::access(t.file.c_str(), W_OK) != 0) return std::strerror(errno);
      if (t.kind == OutputTarget::kStream) return "";
      [[fallthrough]];
    case OutputTarget::kNewFile:
      if (::access(output_detail::folder_of(t.file).c_str(), W_OK | X_OK) != 0) return std::strerror(errno);
      return "";
  }
  return "";
}

}  // namespace rb
