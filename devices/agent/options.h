#pragma once
// The agent's command line.

#include <span>
#include <string>
#include <string_view>

#include "devices/parse_result.h"

namespace incise::devices::agent {

// Where the server's /agent WebSocket endpoint is, from a ws:// URL.
struct ServerAddress {
  std::string host = "127.0.0.1";
  std::string port = "8080";
  std::string target = "/agent";  // path and query
  std::string url() const { return "ws://" + host + ":" + port + target; }
};

struct AgentOptions {
  ServerAddress server;
  std::string token;        // station token: --token, else $INCISE_STATION_TOKEN
  std::string script_path;  // empty: the built-in script
  double rate_hz = 500.0;   // device-state messages per second, kMinRateHz..kMaxRateHz
  bool help = false;        // --help: print usage, do nothing else
};

// The server's simulation wants the hand at >= 250 Hz; above 1000 Hz there is nothing new to
// send, the haptic loop samples the device at 1 kHz.
inline constexpr double kMinRateHz = 250.0;
inline constexpr double kMaxRateHz = 1000.0;

// "ws://host[:port][/path]"; the port defaults to 80, the path to "/". wss:// is refused: this
// build has no TLS.
ParseResult<ServerAddress> parse_server_url(std::string_view url);

// args excludes the program name. Flags take their value as the next argument or after '='.
// env_token is $INCISE_STATION_TOKEN (nullptr if unset); --token wins over it.
ParseResult<AgentOptions> parse_agent_options(std::span<const char* const> args,
                                              const char* env_token);

std::string agent_usage();

}  // namespace incise::devices::agent
