#pragma once
// A child process with stdout on a pipe, read line by line, and stderr in a file. The destructor
// kills (SIGKILL) and reaps it if it is still running, whatever the test did; if the test process
// dies without destructors, the kernel kills the child (PR_SET_PDEATHSIG, which follows the
// creating thread: create children on the test's main thread).
#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace incise::test {

// Our environment with `name` set to `value` (any value it had replaced): for a child that takes
// a secret from its environment, such as the agent's INCISE_STATION_TOKEN.
std::vector<std::string> environment_with(std::string_view name, std::string_view value);

class ChildProcess {
 public:
  // Runs argv[0] (a path) with `environment` ("NAME=value" entries), or with ours when it is
  // nullopt. Throws std::runtime_error when it cannot fork; an exec failure shows as exit status
  // 127.
  explicit ChildProcess(const std::vector<std::string>& argv,
                        std::optional<std::vector<std::string>> environment = std::nullopt);
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  pid_t pid() const { return pid_; }

  // Reads stdout until a line that starts with `prefix` and returns it; nullopt if the child
  // closes stdout (exits) or `timeout` passes first.
  std::optional<std::string> wait_for_line(std::string_view prefix,
                                           std::chrono::milliseconds timeout);

  void send_signal(int signal_number);
  bool running();
  // The exit status once the child has exited (128 + n when signal n ended it), or nullopt when
  // it still runs after `timeout`.
  std::optional<int> wait_for_exit(std::chrono::milliseconds timeout);

  std::string stderr_text() const;
  // Everything the child has written to stdout so far (reads what is waiting in the pipe).
  const std::string& stdout_text();

 private:
  pid_t pid_ = -1;
  int stdout_fd_ = -1;
  std::string stdout_;       // everything read so far
  std::size_t scanned_ = 0;  // lines before this offset have been looked at
  // Waits up to timeout_ms for stdout and appends what it reads; false once stdout is closed or
  // nothing came in time.
  bool read_stdout(int timeout_ms);
  std::optional<int> exit_status_;
  std::string stderr_path_;
};

}  // namespace incise::test
