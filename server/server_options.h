#pragma once
// Command line of incise-server.
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace incise::server {

struct ServerOptions {
  std::string host = "127.0.0.1";
  unsigned short port = 8080;  // 0 picks a free port (printed at start-up)
  std::filesystem::path data_dir = "data";
  std::string database;  // --database URL; "" = $INCISE_DATABASE_URL, else sqlite:DATA/incise.db
  std::string node_id;   // --node-id; "" = $INCISE_NODE_ID, else the host's name
  std::string node_address;  // --node-address; "" = $INCISE_NODE_ADDRESS, else host:port
  int node_timeout_s = 30;   // --node-timeout: a node silent this long is taken for dead
  std::filesystem::path web_root = "web/dist";
  bool demo = false;
  int threads = 2;
  int render_threads = 0;       // the render pool's size; 0: RenderPool::default_threads()
  bool secure_cookies = false;  // the login cookie carries Secure (served over HTTPS)
  std::string trusted_proxy;  // "", or the address or CIDR range whose X-Forwarded-For is believed
  std::filesystem::path tls_cert;  // PEM certificate chain: HTTPS when set (with tls_key)
  std::filesystem::path tls_key;   // PEM private key
  bool help = false;
};

// The options, or the error message for a bad command line.
struct ParsedOptions {
  std::optional<ServerOptions> options;
  std::string error;
};
ParsedOptions parse_server_options(const std::vector<std::string>& args);
bool is_ip_address(const std::string& text);     // IPv4 or IPv6
bool is_address_range(const std::string& text);  // an IP address, or a CIDR range of them
// Whether `peer` is `trusted_proxy`: that address, or in that CIDR range ("" trusts no one).
bool from_trusted_proxy(const std::string& peer, const std::string& trusted_proxy);
bool is_node_id(const std::string& text);       // 1-64 of a-z, A-Z, 0-9, '.', '_', '-'
bool is_node_address(const std::string& text);  // HOST:PORT, HOST a name, IPv4 or [IPv6]

// The client of a request that came from `peer`: the peer itself, unless it is a trusted proxy,
// whose X-Forwarded-For's last address (the one the proxy appended) is the client then. Anything
// else in the header may be the client's own invention and is ignored.
std::string request_client(const std::string& peer, std::string_view forwarded_for,
                           const std::string& trusted_proxy);

// Whether the browser reached us over TLS: on a TLS connection, or through `trusted_proxy` whose
// X-Forwarded-Proto (its last value) says https. Decides the login cookie's Secure flag.
bool reached_over_tls(bool tls_connection, const std::string& peer,
                      std::string_view forwarded_proto, const std::string& trusted_proxy);

extern const char* const kServerUsage;

}  // namespace incise::server
