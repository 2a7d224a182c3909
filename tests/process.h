// Runs a program for a test, as a user's shell would but without one: the
// arguments go to the program exactly as given (no quoting, no globbing, no
// injection), stdout and stderr are captured together, and a program that
// runs past its time limit is killed and reported as such.
#pragma once

#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

extern char** environ;

namespace bounce::testing {

struct ProcessResult {
  int exitCode = -1;      // the program's exit status; -1 when it did not exit normally
  int signal = 0;         // the signal that ended it, or 0
  bool timedOut = false;  // killed after the time limit
  std::string output;     // stdout and stderr interleaved as written; stdout alone with separateStderr
  std::string errors;     // stderr, with separateStderr
  double seconds = 0.0;   // wall-clock time from start to exit
  long peakMegabytes = 0; // the program's peak resident memory (its own, not its children's)
};

// Runs `argv` (argv[0] is the program's path) with `environment` entries
// ("NAME=value") added to or replacing this process's environment.
inline ProcessResult runProcess(const std::vector<std::string>& argv, const std::vector<std::string>& environment = {},
                                double timeoutSeconds = 120.0, bool separateStderr = false) {
  ProcessResult result;
  int pipeFds[2], errorFds[2] = {-1, -1};
  if (pipe(pipeFds) != 0 || (separateStderr && pipe(errorFds) != 0)) {
    result.output = std::string("pipe: ") + std::strerror(errno);
    return result;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipeFds[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, separateStderr ? errorFds[1] : pipeFds[1], STDERR_FILENO);
  for (int fd : {pipeFds[0], pipeFds[1], errorFds[0], errorFds[1]})
    if (fd >= 0) posix_spawn_file_actions_addclose(&actions, fd);

  std::vector<std::string> env;
  for (char** entry = environ; *entry; ++entry) {
    const std::string text = *entry;
    const std::string name = text.substr(0, text.find('='));
    bool replaced = false;
    for (const std::string& extra : environment) replaced |= extra.substr(0, extra.find('=')) == name;
    if (!replaced) env.push_back(text);
  }
  env.insert(env.end(), environment.begin(), environment.end());
  std::vector<char*> argvPointers, envPointers;
  for (const std::string& a : argv) argvPointers.push_back(const_cast<char*>(a.c_str()));
  argvPointers.push_back(nullptr);
  for (const std::string& e : env) envPointers.push_back(const_cast<char*>(e.c_str()));
  envPointers.push_back(nullptr);

  pid_t child = -1;
  const auto started = std::chrono::steady_clock::now();
  const int spawnError =
      posix_spawn(&child, argv.at(0).c_str(), &actions, nullptr, argvPointers.data(), envPointers.data());
  posix_spawn_file_actions_destroy(&actions);
  close(pipeFds[1]);
  if (errorFds[1] >= 0) close(errorFds[1]);
  if (spawnError != 0) {
    close(pipeFds[0]);
    if (errorFds[0] >= 0) close(errorFds[0]);
    result.output = "cannot start " + argv[0] + ": " + std::strerror(spawnError);
    return result;
  }

  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeoutSeconds);
  std::array<char, 4096> buffer;
  std::vector<pollfd> open = {{pipeFds[0], POLLIN, 0}};
  if (errorFds[0] >= 0) open.push_back({errorFds[0], POLLIN, 0});
  while (!open.empty()) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
    if (left <= 0) {
      result.timedOut = true;
      kill(child, SIGKILL);
      break;
    }
    const int ready = poll(open.data(), nfds_t(open.size()), int(std::min<long long>(left, 1000)));
    if (ready <= 0) continue;  // timeout slice or EINTR
    for (std::size_t i = 0; i < open.size();) {
      if (!(open[i].revents & (POLLIN | POLLHUP | POLLERR))) {
        ++i;
        continue;
      }
      const ssize_t count = read(open[i].fd, buffer.data(), buffer.size());
      if (count < 0 && errno == EINTR) continue;
      if (count <= 0) {
        open.erase(open.begin() + long(i));
        continue;
      }
      (open[i].fd == pipeFds[0] ? result.output : result.errors).append(buffer.data(), std::size_t(count));
      ++i;
    }
  }
  close(pipeFds[0]);
  if (errorFds[0] >= 0) close(errorFds[0]);
  int status = 0;
  rusage usage{};
  while (wait4(child, &status, 0, &usage) < 0 && errno == EINTR) {
  }
  result.peakMegabytes = usage.ru_maxrss / 1024;  // Linux reports kilobytes
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  if (WIFEXITED(status)) result.exitCode = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) result.signal = WTERMSIG(status);
  return result;
}

// `words` split at spaces: for tests whose arguments hold no spaces.
inline std::vector<std::string> splitWords(const std::string& words) {
  std::vector<std::string> list;
  std::istringstream stream(words);
  for (std::string word; stream >> word;) list.push_back(word);
  return list;
}

}  // namespace bounce::testing
