// incise-agent: bridges a station's haptic devices to the Incise server (see agent_usage()).

#include <cstdlib>
#include <exception>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <vector>

#include <boost/asio/io_context.hpp>

#include "devices/agent/agent.h"
#include "devices/agent/log.h"
#include "devices/agent/options.h"
#include "devices/agent/self_test.h"
#include "devices/driver_registry.h"
#include "devices/state_log.h"
#include "transport/tls_contexts.h"

namespace {

using namespace incise::devices;
using namespace incise::devices::agent;

// The configuration file's settings as arguments, or an error naming the file.
ParseResult<std::vector<std::string>> read_config(const std::string& path) {
  using Result = ParseResult<std::vector<std::string>>;
  if (path.empty()) return Result::success({});
  std::ifstream file(path, std::ios::binary);
  if (!file) return Result::failure("config " + path + ": cannot open");
  std::ostringstream text;
  text << file.rdbuf();
  return config_file_args(text.str(), path);
}

int run(int argc, char** argv) {
  const std::span<const char* const> args(const_cast<const char* const*>(argv) + 1, argc - 1);
  for (std::string_view arg : args) {
    if (arg == "--help" || arg == "-h") {
      std::cout << agent_usage();
      return kExitStopped;
    }
  }
  const auto path = config_path(args);
  if (!path) {
    log_line(path.error + " (see --help)");
    return kExitUsage;
  }
  const auto config = read_config(*path.value);
  if (!config) {
    log_line(config.error);
    return kExitUsage;
  }
  const auto options =
      parse_agent_options(args, std::getenv("INCISE_STATION_TOKEN"), *config.value);
  if (!options) {
    log_line(options.error + " (see --help)");
    return kExitUsage;
  }
  if (options.value->help) {
    std::cout << agent_usage();
    return kExitStopped;
  }
  const DriverRegistry& drivers = builtin_drivers();
  if (options.value->list_drivers) {
    for (const DriverInfo& driver : drivers.list())
      std::cout << "  " << driver.usage << "\n";
    return kExitStopped;
  }
  std::vector<std::unique_ptr<Device>> devices;
  std::vector<Device*> hands;
  for (const std::string& spec : options.value->devices) {
    auto device = drivers.open(spec);
    if (!device) {
      log_line(device.error);
      return kExitUsage;
    }
    hands.push_back(device.value->get());
    devices.push_back(std::move(*device.value));
  }
  std::shared_ptr<asio::ssl::context> tls;
  if (options.value->server.tls) {
    try {
      tls = incise::transport::make_client_tls(options.value->ca_file);
    } catch (const std::exception& e) {
      log_line(e.what());
      return kExitUsage;
    }
  }
  if (options.value->self_test) {
    return run_self_test(*options.value, hands, tls.get(), std::cout) ? kExitStopped : kExitFailure;
  }
  std::unique_ptr<StateLogWriter> recorder;
  if (!options.value->record_states.empty()) {
    auto writer = StateLogWriter::create(options.value->record_states);
    if (!writer) {
      log_line(writer.error);
      return kExitUsage;
    }
    recorder = std::move(*writer.value);
  }
  asio::io_context io(1);
  Agent agent(io, *options.value, hands, recorder.get(), tls);
  agent.start();
  io.run();
  agent.finish();
  if (recorder) {
    log_line("recorded " + std::to_string(recorder->written()) + " device states to " +
             options.value->record_states);
  }
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
