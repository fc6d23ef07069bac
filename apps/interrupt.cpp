#include "apps/interrupt.hpp"

#include "core/output_file.hpp"

#include <signal.h>
#include <spawn.h>
#include <fcntl.h>
#include <sys/mman.h>
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

extern "C" void on_interrupt(int sig) {
  const int k = sig == SIGINT ? 0 : 1;
  if (g_len[k]) (void)!::write(2, g_msg[k], g_len[k]);
  const pid_t c = g_child.load();
  if (c > 0) ::kill(c, SIGTERM);
  temp_files().unlink_all();
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

int run_command(const std::string& cmd, const std::string* input, std::string* output) {
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
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  // The input in an anonymous memory file (no file on disk, no pipe to fill while the child has
  // not started reading); the output through a pipe read to its end.
  int in_fd = -1, out_pipe[2] = {-1, -1};
  auto close_all = [&] {
    if (in_fd >= 0) ::close(in_fd);
    for (int& f : out_pipe)
      if (f >= 0) ::close(f), f = -1;
    in_fd = -1;
  };
  if (input) {
    in_fd = ::memfd_create("raybench-input", MFD_CLOEXEC);
    if (in_fd < 0 || ::write(in_fd, input->data(), input->size()) != ssize_t(input->size()) || ::lseek(in_fd, 0, SEEK_SET) != 0) {
      close_all();
      return -1;
    }
    posix_spawn_file_actions_adddup2(&fa, in_fd, 0);
  }
  if (output) {
    if (::pipe2(out_pipe, O_CLOEXEC) != 0) {
      close_all();
      return -1;
    }
    posix_spawn_file_actions_adddup2(&fa, out_pipe[1], 1);
  }
  const int rc = posix_spawn(&pid, "/bin/sh", &fa, &attr, const_cast<char* const*>(argv), environ);
  posix_spawn_file_actions_destroy(&fa);
  posix_spawnattr_destroy(&attr);
  if (in_fd >= 0) ::close(in_fd), in_fd = -1;
  if (out_pipe[1] >= 0) ::close(out_pipe[1]), out_pipe[1] = -1;
  if (rc != 0) {
    close_all();
    return -1;
  }
  g_child.store(pid);
  if (output) {
    char buf[65536];
    for (;;) {
      const ssize_t n = ::read(out_pipe[0], buf, sizeof buf);
      if (n > 0) output->append(buf, std::size_t(n));
      else if (n == 0 || errno != EINTR) break;
    }
  }
  close_all();
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
