#include "devices/agent/options.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace incise::devices::agent {
namespace {

using Result = ParseResult<AgentOptions>;

bool parse_rate(const std::string& text, double& rate) {
  if (text.empty()) return false;
  char* end = nullptr;
  errno = 0;
  rate = std::strtod(text.c_str(), &end);
  return errno == 0 && *end == '\0' && std::isfinite(rate);
}

}  // namespace

ParseResult<ServerAddress> parse_server_url(std::string_view url) {
  using Result = ParseResult<ServerAddress>;
  ServerAddress address;
  address.tls = url.starts_with("wss://");
  const std::string_view scheme = address.tls ? "wss://" : "ws://";
  if (!url.starts_with(scheme)) {
    return Result::failure("--server " + std::string(url) + ": must start with ws:// or wss://");
  }
  std::string_view rest = url.substr(scheme.size());
  const auto slash = rest.find('/');
  address.target = slash == std::string_view::npos ? "/" : std::string(rest.substr(slash));
  std::string_view authority = rest.substr(0, slash);
  address.port = address.tls ? "443" : "80";
  // A bracketed IPv6 literal carries colons of its own: [::1]:8080.
  const auto close_bracket = authority.starts_with('[') ? authority.find(']') : 0;
  if (close_bracket == std::string_view::npos) {
    return Result::failure("--server " + std::string(url) + ": unterminated [IPv6 address]");
  }
  const auto colon = authority.find(':', close_bracket);
  if (colon != std::string_view::npos) {
    address.port = std::string(authority.substr(colon + 1));
    authority = authority.substr(0, colon);
    const bool digits = !address.port.empty() && address.port.size() <= 5 &&
                        address.port.find_first_not_of("0123456789") == std::string::npos;
    if (!digits || std::stoul(address.port) < 1 || std::stoul(address.port) > 65535) {
      return Result::failure("--server " + std::string(url) + ": port must be 1..65535");
    }
  }
  if (authority.starts_with('[')) authority = authority.substr(1, authority.size() - 2);
  if (authority.empty()) return Result::failure("--server " + std::string(url) + ": no host");
  address.host = std::string(authority);
  return Result::success(std::move(address));
}

namespace {

// Flags that take a value, and those that are switches ("--no-deadband") with their config
// file spelling ("deadband = off").
constexpr std::string_view kValueFlags[] = {
    "--server",    "--ca",       "--token",         "--device", "--script",   "--rate",
    "--max-force", "--coupling", "--record-states", "--config", "--deadband", "--passivity"};

bool takes_value(std::string_view flag) {
  for (std::string_view f : kValueFlags)
    if (f == flag) return true;
  return false;
}

bool parse_switch(const std::string& value, bool& out) {
  if (value == "on" || value == "true" || value == "yes" || value == "1") return out = true, true;
  if (value == "off" || value == "false" || value == "no" || value == "0") return out = false, true;
  return false;
}

}  // namespace

ParseResult<std::string> config_path(std::span<const char* const> args) {
  using PathResult = ParseResult<std::string>;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string_view arg = args[i];
    if (arg.starts_with("--config=")) return PathResult::success(std::string(arg.substr(9)));
    if (arg == "--config") {
      if (i + 1 == args.size()) return PathResult::failure("--config needs a value");
      return PathResult::success(args[i + 1]);
    }
  }
  return PathResult::success("");
}

ParseResult<std::vector<std::string>> config_file_args(std::string_view text,
                                                       const std::string& path) {
  using ArgsResult = ParseResult<std::vector<std::string>>;
  std::vector<std::string> out;
  int line_number = 0;
  while (!text.empty()) {
    ++line_number;
    const auto newline = text.find('\n');
    std::string line(text.substr(0, newline));
    text = newline == std::string_view::npos ? std::string_view{} : text.substr(newline + 1);
    if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    const auto trim = [](std::string value) {
      const auto first = value.find_first_not_of(" \t\r");
      if (first == std::string::npos) return std::string();
      const auto last = value.find_last_not_of(" \t\r");
      return value.substr(first, last - first + 1);
    };
    line = trim(line);
    if (line.empty()) continue;
    const std::string where = path + ":" + std::to_string(line_number) + ": ";
    const auto eq = line.find('=');
    if (eq == std::string::npos) return ArgsResult::failure(where + "expected key = value");
    const std::string key = trim(line.substr(0, eq));
    const std::string value = trim(line.substr(eq + 1));
    if (key == "config" || !takes_value("--" + key)) {
      return ArgsResult::failure(where + "unknown key '" + key + "'");
    }
    if (value.empty()) return ArgsResult::failure(where + "'" + key + "' has no value");
    out.push_back("--" + key + "=" + value);
  }
  return ArgsResult::success(std::move(out));
}

ParseResult<AgentOptions> parse_agent_options(std::span<const char* const> args,
                                              const char* env_token,
                                              std::span<const std::string> config_args) {
  AgentOptions options;
  bool token_given = false;
  bool devices_from_command_line = false;
  std::vector<const char*> all;
  for (const std::string& arg : config_args)
    all.push_back(arg.c_str());
  const std::size_t from_config = all.size();
  all.insert(all.end(), args.begin(), args.end());
  for (std::size_t i = 0; i < all.size(); ++i) {
    const bool command_line = i >= from_config;
    std::string flag = all[i];
    std::string value;
    bool has_value = false;
    if (const auto eq = flag.find('='); flag.starts_with("--") && eq != std::string::npos) {
      value = flag.substr(eq + 1);
      flag.resize(eq);
      has_value = true;
    }
    if (flag == "--help" || flag == "-h") {
      options.help = true;
      return Result::success(std::move(options));
    }
    if (flag == "--list-drivers") {
      options.list_drivers = true;
      continue;
    }
    if (flag == "--self-test") {
      options.self_test = true;
      continue;
    }
    if (flag == "--no-deadband") {
      options.deadband = false;
      continue;
    }
    if (flag == "--no-passivity") {
      options.guard.passivity = false;
      continue;
    }
    if (!takes_value(flag)) return Result::failure("unknown option '" + flag + "'");
    if (!has_value) {
      if (i + 1 == all.size()) return Result::failure(flag + " needs a value");
      value = all[++i];
    }
    if (flag == "--server") {
      auto address = parse_server_url(value);
      if (!address) return Result::failure(address.error);
      options.server = std::move(*address.value);
    } else if (flag == "--ca") {
      options.ca_file = value;
    } else if (flag == "--token") {
      if (command_line) {
        // Any local user reads a process's command line (ps, /proc/PID/cmdline).
        return Result::failure(
            "--token on the command line is refused (any local user can read it in ps): set "
            "INCISE_STATION_TOKEN or put token = ... in the --config file");
      }
      options.token = value;
      token_given = true;
    } else if (flag == "--config") {
      // Read by the caller (config_path) before parsing.
    } else if (flag == "--device" || flag == "--script") {
      if (command_line && !devices_from_command_line) {
        // Devices named on the command line replace the configuration file's.
        options.devices.clear();
        devices_from_command_line = true;
      }
      if (options.devices.size() == 2) {
        return Result::failure(flag + " " + value + ": a station has at most 2 devices");
      }
      options.devices.push_back(flag == "--script" ? "simulated:" + value : value);
    } else if (flag == "--rate") {
      if (!parse_rate(value, options.rate_hz) || options.rate_hz < kMinRateHz ||
          options.rate_hz > kMaxRateHz) {
        return Result::failure("--rate " + value + ": must be a number of Hz in [250, 1000]");
      }
    } else if (flag == "--max-force") {
      double limit = 0;
      if (!parse_rate(value, limit) || limit <= 0 || limit > 40) {
        return Result::failure("--max-force " + value + ": must be a number of N in (0, 40]");
      }
      options.guard.max_force_n = {limit, limit, limit};
    } else if (flag == "--coupling") {
      double& stiffness = options.guard.coupling_stiffness;
      if (!parse_rate(value, stiffness) || stiffness < 10 || stiffness > 20000) {
        return Result::failure("--coupling " + value + ": must be a number of N/m in [10, 20000]");
      }
    } else if (flag == "--record-states") {
      options.record_states = value;
    } else if (flag == "--deadband" || flag == "--passivity") {
      bool& target = flag == "--deadband" ? options.deadband : options.guard.passivity;
      if (!parse_switch(value, target)) {
        return Result::failure(flag + " " + value + ": must be on or off");
      }
    }
  }
  if (options.devices.empty()) options.devices.push_back("simulated");
  if (!token_given && env_token != nullptr) options.token = env_token;
  if (options.token.empty() && !options.list_drivers) {
    return Result::failure(
        "no station token: set INCISE_STATION_TOKEN or put token = ... in the --config file");
  }
  return Result::success(std::move(options));
}

std::string agent_usage() {
  return R"(usage: incise-agent [--config FILE] [--server URL] [--ca FILE] [--device SPEC]...
                    [--rate HZ] [--no-deadband] [--max-force N] [--coupling N/M]
                    [--record-states FILE] [--self-test] [--list-drivers]

Bridges this station's haptic devices (one per hand, at most two) to the Incise server. A 1 kHz
haptic loop polls the devices and renders the latest local force model the server sent for each,
through a virtual coupling, a passivity guard and per-axis force limits; a watchdog fades the
force to zero within 10 ms of any fault (link down, no model for 15 ms, a model answering a
state over 300 ms old, a device fault). Device states go to the server over its /agent
WebSocket (held back while the hand is still), which is reconnected (0.25 s backoff doubling to
5 s) when it drops. SIGUSR1 logs the loop and link statistics (they are also logged at exit).

  --config FILE        settings file: "key = value" lines with these flags' names (see
                       deploy/agent/incise-agent.conf); the command line overrides it
  --server URL         the server's agent endpoint (default ws://127.0.0.1:8080/agent);
                       wss://HOST[:PORT]/agent over TLS, the server's certificate checked
                       against the system's CAs and HOST
  --ca FILE            with wss://: trust the server certificates this PEM file vouches for (a
                       private CA, or the server's self-signed certificate) instead
  The station token (shown once when the station was created) comes from the environment,
  INCISE_STATION_TOKEN, or from "token = ..." in the --config file (readable by the agent's user
  only): never from the command line, which every local user can read.
  --device SPEC        a device driver, NAME[:ARGUMENT]; repeat for the second hand (device 1).
                       --list-drivers shows the drivers of this build. Default: simulated
  --script FILE        short for --device simulated:FILE
  --rate HZ            device-state messages per second, [250, 1000] (default 500)
  --no-deadband        send every state, also while the hand is still (default: deadband on)
  --max-force N        per-axis force limit, (0, 40] N (default 8)
  --coupling N/M       virtual coupling stiffness, [10, 20000] N/m (default 1500)
  --no-passivity       turn the passivity guard off (measurements only: never with a person)
  --record-states FILE write every device state (full rate, also those held back) to FILE;
                       play it back with --device replay:FILE
  --self-test          check each device (polls, finite unit-quaternion states, no fault) and
                       the link (connect, hello/welcome, round trips), print one line per check,
                       exit 0 if all pass and 1 if any fails
  --list-drivers       print the device drivers of this build and exit
  --help               print this help

Exit status: 0 stopped by SIGINT/SIGTERM (or a passed self-test), 2 bad command line, config or
device, 3 refused by the server (unknown token, unsupported protocol), 1 any other failure.
)";
}

}  // namespace incise::devices::agent
