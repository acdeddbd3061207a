#pragma once
// Runs the real incise-agent binary as a child process with stdout and stderr captured in
// files, so tests can signal it and read its log.

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace incise::devices::agent::testing {

class AgentProcess {
 public:
  // Starts INCISE_AGENT_PATH with args. The child's environment is ours without
  // INCISE_STATION_TOKEN, plus extra_env ("NAME=value").
  explicit AgentProcess(const std::vector<std::string>& args,
                        const std::vector<std::string>& extra_env = {});
  // Kills (SIGKILL) and reaps the child if it is still running.
  ~AgentProcess();

  AgentProcess(const AgentProcess&) = delete;
  AgentProcess& operator=(const AgentProcess&) = delete;

  void send_signal(int signal_number) const;

  // The exit code once the child has exited (128 + n if signal n killed it), or nullopt if it
  // is still running after timeout.
  std::optional<int> wait_for_exit(std::chrono::milliseconds timeout);

  std::string stdout_text() const;
  std::string stderr_text() const;

 private:
  pid_t pid_ = -1;
  std::optional<int> exit_code_;
  std::string stdout_path_;
  std::string stderr_path_;
};

}  // namespace incise::devices::agent::testing
