#pragma once
// The agent's command line.

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "devices/agent/force_guard.h"
#include "devices/parse_result.h"

namespace incise::devices::agent {

// Where the server's /agent WebSocket endpoint is, from a ws:// or wss:// URL.
struct ServerAddress {
  std::string host = "127.0.0.1";
  std::string port = "8080";
  std::string target = "/agent";  // path and query
  bool tls = false;               // wss://
  std::string url() const { return (tls ? "wss://" : "ws://") + host + ":" + port + target; }
};

struct AgentOptions {
  ServerAddress server;
  std::string token;  // station token: "token" in the config file, else $INCISE_STATION_TOKEN
  // --ca FILE: for wss://, the PEM certificates that vouch for the server (a private CA, or a
  // self-signed server certificate itself); empty: the system's trusted CAs.
  std::string ca_file;
  // Driver specs "name[:argument]", one per hand (at most 2): --device, repeated. Default: the
  // simulated device with its built-in script. --script FILE is short for --device simulated:FILE.
  std::vector<std::string> devices;
  double rate_hz = 500.0;  // device-state messages per second, kMinRateHz..kMaxRateHz
  bool deadband = true;    // --no-deadband: send every state even when the hand is still
  // --max-force (per-axis limit), --coupling (stiffness), --no-passivity (measurements only).
  ForceGuardSettings guard;
  std::string record_states;  // --record-states FILE: every state, full rate, for replay:FILE
  bool self_test = false;     // --self-test: check the devices and the link, then exit
  bool help = false;          // --help: print usage, do nothing else
  bool list_drivers = false;  // --list-drivers
};

// The server's simulation wants the hand at >= 250 Hz; above 1000 Hz there is nothing new to
// send, the haptic loop samples the device at 1 kHz.
inline constexpr double kMinRateHz = 250.0;
inline constexpr double kMaxRateHz = 1000.0;

// "ws://host[:port][/path]" or "wss://..."; the port defaults to 80 (443 for wss://), the path to
// "/".
ParseResult<ServerAddress> parse_server_url(std::string_view url);

// args excludes the program name. Flags take their value as the next argument or after '='.
// env_token is $INCISE_STATION_TOKEN (nullptr if unset); the config file's token wins over it, and
// --token on the command line is refused (ps shows it to every local user). config_args are the
// configuration file's settings (config_file_args), which the command line overrides.
ParseResult<AgentOptions> parse_agent_options(std::span<const char* const> args,
                                              const char* env_token,
                                              std::span<const std::string> config_args = {});

// A configuration file (deploy/agent/incise-agent.conf): one "key = value" per line, the keys
// being the long flags without "--" (server, ca, token, device, script, rate, deadband, max-force,
// coupling, passivity, record-states); '#' starts a comment. Returns the settings as "--key=value"
// arguments, or the first bad line as `FILE:LINE: ...`.
ParseResult<std::vector<std::string>> config_file_args(std::string_view text,
                                                       const std::string& path);
// The value of --config in args ("" if none), or an error if it has no value.
ParseResult<std::string> config_path(std::span<const char* const> args);

std::string agent_usage();

}  // namespace incise::devices::agent
