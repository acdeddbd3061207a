#include "agent_process.h"

#include <cstring>

extern char** environ;

namespace incise::devices::agent::testing {
namespace {

std::vector<std::string> agent_argv(const std::vector<std::string>& args) {
  std::vector<std::string> argv = {INCISE_AGENT_BIN};
  argv.insert(argv.end(), args.begin(), args.end());
  return argv;
}

std::vector<std::string> agent_environment(const std::vector<std::string>& extra_env) {
  std::vector<std::string> env;
  for (char** e = environ; *e != nullptr; ++e) {
    if (std::strncmp(*e, "INCISE_STATION_TOKEN=", 21) != 0) env.emplace_back(*e);
  }
  env.insert(env.end(), extra_env.begin(), extra_env.end());
  return env;
}

}  // namespace

AgentProcess::AgentProcess(const std::vector<std::string>& args,
                           const std::vector<std::string>& extra_env)
    : child_(agent_argv(args), agent_environment(extra_env)) {}

}  // namespace incise::devices::agent::testing
