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
  constexpr std::string_view kScheme = "ws://";
  if (url.starts_with("wss://")) {
    return Result::failure("--server " + std::string(url) + ": wss:// is not supported (no TLS)");
  }
  if (!url.starts_with(kScheme)) {
    return Result::failure("--server " + std::string(url) + ": must start with ws://");
  }
  std::string_view rest = url.substr(kScheme.size());
  ServerAddress address;
  const auto slash = rest.find('/');
  address.target = slash == std::string_view::npos ? "/" : std::string(rest.substr(slash));
  std::string_view authority = rest.substr(0, slash);
  address.port = "80";
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

ParseResult<AgentOptions> parse_agent_options(std::span<const char* const> args,
                                              const char* env_token) {
  AgentOptions options;
  bool token_given = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    std::string flag = args[i];
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
    if (flag != "--server" && flag != "--token" && flag != "--script" && flag != "--rate") {
      return Result::failure("unknown option '" + flag + "'");
    }
    if (!has_value) {
      if (i + 1 == args.size()) return Result::failure(flag + " needs a value");
      value = args[++i];
    }
    if (flag == "--server") {
      auto address = parse_server_url(value);
      if (!address) return Result::failure(address.error);
      options.server = std::move(*address.value);
    } else if (flag == "--token") {
      options.token = value;
      token_given = true;
    } else if (flag == "--script") {
      options.script_path = value;
    } else if (!parse_rate(value, options.rate_hz) || options.rate_hz < kMinRateHz ||
               options.rate_hz > kMaxRateHz) {
      return Result::failure("--rate " + value + ": must be a number of Hz in [250, 1000]");
    }
  }
  if (!token_given && env_token != nullptr) options.token = env_token;
  if (options.token.empty()) {
    return Result::failure("no station token: pass --token or set INCISE_STATION_TOKEN");
  }
  return Result::success(std::move(options));
}

std::string agent_usage() {
  return R"(usage: incise-agent [--server URL] [--token TOKEN] [--script FILE] [--rate HZ]

Bridges this station's haptic device to the Incise server. A 1 kHz haptic loop polls the device
and renders the latest local force model the server sent (fading the force to zero within 10 ms
when the link drops or the model is older than 100 ms); the device state goes to the server over
its /agent WebSocket, which is reconnected (0.25 s backoff doubling to 5 s) when it drops.
SIGUSR1 logs the loop and link statistics (they are also logged at exit).

  --server URL     the server's agent endpoint (default ws://127.0.0.1:8080/agent)
  --token TOKEN    the station token shown when the station was created; prefer the
                   INCISE_STATION_TOKEN environment variable, which other users cannot see in ps
  --script FILE    JSON script for the simulated device (default: a built-in looping script)
  --rate HZ        device-state messages per second, [250, 1000] (default 500); the loop
                   sends every round(1000 / HZ)-th sample
  --help           print this help

Exit status: 0 stopped by SIGINT/SIGTERM, 2 bad command line or script, 3 refused by the server
(unknown token, unsupported protocol), 1 any other failure.
)";
}

}  // namespace incise::devices::agent
