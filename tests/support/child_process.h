// A child process for end-to-end tests: argv as given (no shell), stdout and
// stderr in log files (together unless a separate stderr log is named),
// killed (SIGKILL) and reaped by the destructor if it is still running.
#ifndef GROUNDLINE_TESTS_SUPPORT_CHILD_PROCESS_H_
#define GROUNDLINE_TESTS_SUPPORT_CHILD_PROCESS_H_

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "test_data.h"

extern char** environ;

namespace groundline::testing {

class ChildProcess {
 public:
  // Starts argv[0] (an absolute path, or a name looked up in PATH) with the
  // test's environment, where each "NAME=value" of `environment` replaces or
  // adds that variable; started() is false if it could not be spawned.
  // output() reads the stdout log.
  ChildProcess(std::vector<std::string> argv, const std::filesystem::path& log,
               const std::filesystem::path& stderr_log = {},
               std::vector<std::string> environment = {})
      : log_(log), environment_(std::move(environment)) {
    std::vector<char*> args;
    for (std::string& a : argv) args.push_back(a.data());
    args.push_back(nullptr);
    std::vector<char*> env;
    for (char** e = environ; *e != nullptr; ++e) {
      const std::string entry(*e);
      bool replaced = false;
      for (const std::string& o : environment_) {
        replaced = replaced || entry.compare(0, o.find('=') + 1, o, 0, o.find('=') + 1) == 0;
      }
      if (!replaced) env.push_back(*e);
    }
    for (std::string& o : environment_) env.push_back(o.data());
    env.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (stderr_log.empty()) {
      posix_spawn_file_actions_adddup2(&actions, 1, 2);
    } else {
      posix_spawn_file_actions_addopen(&actions, 2, stderr_log.c_str(),
                                       O_WRONLY | O_CREAT | O_TRUNC, 0644);
    }
    if (posix_spawnp(&pid_, args[0], &actions, nullptr, args.data(), env.data()) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&actions);
  }
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;
  ~ChildProcess() {
    if (pid_ > 0 && !exited_) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }

  bool started() const { return pid_ > 0; }

  // The exit code (128 + signal when killed) once it exits within timeout;
  // -1 while it still runs.
  int Wait(std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (pid_ > 0 && !exited_) {
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        exited_ = true;
        code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        break;
      }
      if (std::chrono::steady_clock::now() >= deadline) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return exited_ ? code_ : -1;
  }

  // SIGTERM: a graceful stop for the groundline service.
  void Terminate() {
    if (pid_ > 0 && !exited_) kill(pid_, SIGTERM);
  }

  // Waits until the log contains text; false after timeout or once the
  // process exited without writing it.
  bool WaitForOutput(const std::string& text, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      if (output().find(text) != std::string::npos) return true;
      if (Wait(std::chrono::milliseconds(0)) >= 0) return output().find(text) != std::string::npos;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return false;
  }

  std::string output() const { return ReadText(log_); }

 private:
  std::filesystem::path log_;
  std::vector<std::string> environment_;  // outlives the spawn: env points into it
  pid_t pid_ = -1;
  bool exited_ = false;
  int code_ = -1;
};

}  // namespace groundline::testing

#endif  // GROUNDLINE_TESTS_SUPPORT_CHILD_PROCESS_H_
