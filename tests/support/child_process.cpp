#include "child_process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace incise::test {

namespace {
std::string make_temp_file(const char* stem) {
  std::string path = std::string("/tmp/") + stem + "-XXXXXX";
  const int fd = mkstemp(path.data());
  if (fd < 0) throw std::runtime_error("mkstemp: " + std::string(std::strerror(errno)));
  close(fd);
  return path;
}
}  // namespace

std::vector<std::string> environment_with(std::string_view name, std::string_view value) {
  const std::string prefix = std::string(name) + "=";
  std::vector<std::string> env;
  for (char** e = environ; *e != nullptr; ++e) {
    if (!std::string_view(*e).starts_with(prefix)) env.emplace_back(*e);
  }
  env.push_back(prefix + std::string(value));
  return env;
}

ChildProcess::ChildProcess(const std::vector<std::string>& args,
                           std::optional<std::vector<std::string>> environment)
    : stderr_path_(make_temp_file("incise-child-err")) {
  std::vector<std::string> strings = args;
  std::vector<char*> argv;
  for (auto& a : strings)
    argv.push_back(a.data());
  argv.push_back(nullptr);
  std::vector<char*> own_env;
  if (environment) {
    for (auto& entry : *environment)
      own_env.push_back(entry.data());
    own_env.push_back(nullptr);
  }
  char* const* envp = environment ? own_env.data() : environ;

  // Close-on-exec here, so that later children do not inherit the pipe; dup2 clears the flag on
  // the child's fd 1.
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0)
    throw std::runtime_error("pipe2: " + std::string(strerror(errno)));
  const int err = open(stderr_path_.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
  const pid_t parent = getpid();
  // fork/exec rather than posix_spawn, for PR_SET_PDEATHSIG: the child dies with the test even
  // when the test crashes and no destructor runs. Only async-signal-safe calls after fork.
  pid_ = fork();
  if (pid_ == 0) {
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(127);  // the test died before prctl took effect
    signal(SIGPIPE, SIG_DFL);             // the tests ignore it; the programs must not inherit that
    dup2(fds[1], 1);
    if (err >= 0) dup2(err, 2);
    execve(argv[0], argv.data(), envp);
    _exit(127);
  }
  const int fork_errno = errno;
  close(fds[1]);
  if (err >= 0) close(err);
  stdout_fd_ = fds[0];
  if (pid_ < 0) {
    close(stdout_fd_);
    unlink(stderr_path_.c_str());
    throw std::runtime_error("fork: " + std::string(std::strerror(fork_errno)));
  }
}

ChildProcess::~ChildProcess() {
  if (!exit_status_) {
    kill(pid_, SIGKILL);
    int status = 0;
    waitpid(pid_, &status, 0);
  }
  if (stdout_fd_ >= 0) close(stdout_fd_);
  unlink(stderr_path_.c_str());
}

std::optional<std::string> ChildProcess::wait_for_line(std::string_view prefix,
                                                       std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (true) {
    for (auto end = stdout_.find('\n', scanned_); end != std::string::npos;
         end = stdout_.find('\n', scanned_)) {
      const std::string line = stdout_.substr(scanned_, end - scanned_);
      scanned_ = end + 1;
      if (line.starts_with(prefix)) return line;
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0 || stdout_fd_ < 0) return std::nullopt;
    // Nothing in time gives up; the end of stdout scans what is left, then gives up.
    if (!read_stdout(static_cast<int>(left.count())) && stdout_fd_ >= 0) return std::nullopt;
  }
}

bool ChildProcess::read_stdout(int timeout_ms) {
  while (stdout_fd_ >= 0) {
    pollfd p{stdout_fd_, POLLIN, 0};
    const int ready = poll(&p, 1, timeout_ms);
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) return false;
    char buffer[4096];
    const ssize_t n = read(stdout_fd_, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      close(stdout_fd_);
      stdout_fd_ = -1;
      return false;
    }
    stdout_.append(buffer, static_cast<std::size_t>(n));
    return true;
  }
  return false;
}

const std::string& ChildProcess::stdout_text() {
  while (read_stdout(0)) {
  }
  return stdout_;
}

void ChildProcess::send_signal(int signal_number) {
  if (running()) kill(pid_, signal_number);
}

bool ChildProcess::running() {
  return !wait_for_exit(std::chrono::milliseconds(0));
}

std::optional<int> ChildProcess::wait_for_exit(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!exit_status_) {
    int status = 0;
    const pid_t done = waitpid(pid_, &status, WNOHANG);
    if (done == pid_) {
      exit_status_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    } else if (std::chrono::steady_clock::now() >= deadline) {
      break;
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }
  return exit_status_;
}

std::string ChildProcess::stderr_text() const {
  std::ifstream file(stderr_path_);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

}  // namespace incise::test
