#pragma once
// Command line of incise-server.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace incise::server {

struct ServerOptions {
  std::string host = "127.0.0.1";
  unsigned short port = 8080;  // 0 picks a free port (printed at start-up)
  std::filesystem::path data_dir = "data";
  std::filesystem::path web_root = "web/dist";
  bool demo = false;
  int threads = 2;
  bool help = false;
};

// The options, or the error message for a bad command line.
struct ParsedOptions {
  std::optional<ServerOptions> options;
  std::string error;
};
ParsedOptions parse_server_options(const std::vector<std::string>& args);

extern const char* const kServerUsage;

}  // namespace incise::server
