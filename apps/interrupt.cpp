#include "apps/interrupt.hpp"

#include "core/atomic_file.hpp"

#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstring>

extern char** environ;

namespace rb::app {

namespace {

char g_msg[2][256];
std::size_t g_len[2] = {0, 0};
std::atomic<pid_t> g_child{0};

TempFiles& placeholders() {
  static TempFiles t;
  return t;
}

extern "C" void on_interrupt(int sig) {
  const int k = sig == SIGINT ? 0 : 1;
  if (g_len[k]) (void)!::write(2, g_msg[k], g_len[k]);
  const pid_t c = g_child.load();
  if (c > 0) ::kill(c, SIGTERM);
  temp_files().unlink_all();
  TempFiles& p = placeholders();
  for (int i = 0; i < TempFiles::kSlots; ++i) {
    if (p.used[i].load() != 1) continue;
    struct stat st {};
    if (::stat(p.path[i], &st) == 0 && S_ISREG(st.st_mode) && st.st_size == 0) ::unlink(p.path[i]);
  }
  ::_exit(128 + sig);
}

void set_message(int k, const std::string& command, const char* signame) {
  const std::string m = "\nraybench " + command + ": interrupted by " + signame + "; stopped, no partial output left\n";
  const std::size_t n = std::min(m.size(), sizeof g_msg[k] - 1);
  std::memcpy(g_msg[k], m.data(), n);
  g_msg[k][n] = 0;
  g_len[k] = n;
}

}  // namespace

void install_interrupt_handlers(const std::string& command) {
  set_message(0, command.empty() ? "" : command, "SIGINT");
  set_message(1, command.empty() ? "" : command, "SIGTERM");
  struct sigaction sa {};
  sa.sa_handler = on_interrupt;
  sigemptyset(&sa.sa_mask);
  sigaddset(&sa.sa_mask, SIGINT);
  sigaddset(&sa.sa_mask, SIGTERM);
  sa.sa_flags = 0;
  ::sigaction(SIGINT, &sa, nullptr);
  ::sigaction(SIGTERM, &sa, nullptr);
}

void note_placeholder(const std::string& path) { placeholders().add(path); }

int run_command(const std::string& cmd) {
  const char* argv[] = {"sh", "-c", cmd.c_str(), nullptr};
  pid_t pid = 0;
  // The child starts with default signal dispositions (so an interrupt's SIGTERM ends it).
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  sigset_t def;
  sigemptyset(&def);
  sigaddset(&def, SIGINT);
  sigaddset(&def, SIGTERM);
  posix_spawnattr_setsigdefault(&attr, &def);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGDEF);
  const int rc = posix_spawn(&pid, "/bin/sh", nullptr, &attr, const_cast<char* const*>(argv), environ);
  posix_spawnattr_destroy(&attr);
  if (rc != 0) return -1;
  g_child.store(pid);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) {
      status = -1;
      break;
    }
  }
  g_child.store(0);
  return status;
}

}  // namespace rb::app
