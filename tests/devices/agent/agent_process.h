#pragma once
// Runs the real incise-agent binary (INCISE_AGENT_BIN) as a child process, so tests can signal it
// and read what it printed.

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "tests/support/child_process.h"

namespace incise::devices::agent::testing {

class AgentProcess {
 public:
  // Starts the agent with args. The child's environment is ours without INCISE_STATION_TOKEN,
  // plus extra_env ("NAME=value").
  explicit AgentProcess(const std::vector<std::string>& args,
                        const std::vector<std::string>& extra_env = {});

  void send_signal(int signal_number) { child_.send_signal(signal_number); }

  // The exit code once the child has exited (128 + n if signal n killed it), or nullopt if it
  // is still running after timeout.
  std::optional<int> wait_for_exit(std::chrono::milliseconds timeout) {
    return child_.wait_for_exit(timeout);
  }

  std::string stdout_text() { return child_.stdout_text(); }
  std::string stderr_text() const { return child_.stderr_text(); }

 private:
  incise::test::ChildProcess child_;
};

}  // namespace incise::devices::agent::testing
