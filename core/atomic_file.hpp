// Output files written whole or not at all: the bytes go to a hidden temporary file beside the
// target (".NAME.tmp-PID"), which is renamed over the target once complete, so a reader (or the
// next run) sees the previous file or the new one, never half of one. The temporaries being
// written are listed in a fixed table that an interrupt handler may read (async-signal-safe:
// no allocation, one atomic flag per slot) to unlink them before the process exits
// (apps/interrupt.cpp).
#pragma once

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
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

// The hidden temporary beside `path`.
inline std::string temp_path_for(const std::string& path) {
  const std::size_t slash = path.rfind('/');
  const std::string dir = slash == std::string::npos ? "" : path.substr(0, slash + 1);
  const std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  return dir + "." + name + ".tmp-" + std::to_string(::getpid());
}

// Writes `data` to `path` through a temporary and a rename. Throws std::runtime_error naming the
// file and the system's reason; the temporary is gone on failure.
inline void write_file_atomic(const std::string& path, std::string_view data) {
  const std::string tmp = temp_path_for(path);
  const int slot = temp_files().add(tmp);
  auto fail = [&](int err) {
    ::unlink(tmp.c_str());
    temp_files().remove(slot);
    throw std::runtime_error("cannot write " + path + ": " + std::strerror(err));
  };
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) {
    const int err = errno;
    temp_files().remove(slot);
    throw std::runtime_error("cannot write " + path + ": " + std::strerror(err));
  }
  std::size_t off = 0;
  while (off < data.size()) {
    const ssize_t n = ::write(fd, data.data() + off, data.size() - off);
    if (n < 0) {
      if (errno == EINTR) continue;
      const int err = errno;
      ::close(fd);
      fail(err);
    }
    off += std::size_t(n);
  }
  if (::close(fd) != 0) fail(errno);
  if (std::rename(tmp.c_str(), path.c_str()) != 0) fail(errno);
  temp_files().remove(slot);
}

}  // namespace rb
