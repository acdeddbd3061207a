// incise-agent: bridges a station's haptic device to the Incise server (see agent_usage()).

#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include <boost/asio/io_context.hpp>

#include "devices/agent/agent.h"
#include "devices/agent/log.h"
#include "devices/agent/options.h"
#include "devices/simulated_device.h"
#include "devices/simulated_script.h"

namespace {

using namespace incise::devices;
using namespace incise::devices::agent;

// The script's text, or an error naming the file.
ParseResult<std::string> read_script_text(const std::string& path) {
  if (path.empty())
    return ParseResult<std::string>::success(std::string(default_simulated_script()));
  std::ifstream file(path, std::ios::binary);
  if (!file) return ParseResult<std::string>::failure("script " + path + ": cannot open");
  std::ostringstream text;
  text << file.rdbuf();
  return ParseResult<std::string>::success(text.str());
}

int run(int argc, char** argv) {
  const auto options = parse_agent_options(
      std::span<const char* const>(const_cast<const char* const*>(argv) + 1, argc - 1),
      std::getenv("INCISE_STATION_TOKEN"));
  if (!options) {
    log_line(options.error + " (see --help)");
    return kExitUsage;
  }
  if (options.value->help) {
    std::cout << agent_usage();
    return kExitStopped;
  }
  const std::string& path = options.value->script_path;
  const auto text = read_script_text(path);
  if (!text) {
    log_line(text.error);
    return kExitUsage;
  }
  auto script = parse_simulated_script(*text.value);
  if (!script) {
    log_line("script " + (path.empty() ? std::string("(built-in)") : path) + ": " + script.error);
    return kExitUsage;
  }
  const std::string script_name =
      path.empty() ? "built-in script" : std::filesystem::path(path).filename().string();
  SimulatedDevice device(std::move(*script.value), "simulated (" + script_name + ")");

  asio::io_context io(1);
  Agent agent(io, *options.value, device);
  agent.start();
  io.run();
  agent.finish();
  return agent.exit_code();
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    log_line(std::string("fatal: ") + e.what());
    return kExitFailure;
  }
}
