#include "server/server_options.h"

#include <boost/asio/ip/address.hpp>
#include <boost/asio/ip/network_v4.hpp>
#include <boost/asio/ip/network_v6.hpp>
#include <charconv>
#include <stdexcept>

#include "db/database_url.h"

namespace incise::server {

const char* const kServerUsage =
    "usage: incise-server [--host ADDR] [--port N] [--data DIR] [--database URL] [--web DIR]\n"
    "                     [--demo] [--threads N] [--render-threads N]\n"
    "                     [--node-id ID] [--node-address HOST:PORT] [--node-timeout S]\n"
    "                     [--tls-cert FILE --tls-key FILE] [--secure-cookies] [--trusted-proxy "
    "ADDR]\n"
    "\n"
    "Serves the Incise dashboard, REST API and station-agent WebSocket on one port.\n"
    "  --host ADDR   address to listen on (default 127.0.0.1)\n"
    "  --port N      port; 0 picks a free one (default 8080)\n"
    "  --data DIR    data directory; the database is DIR/incise.db, created on first run\n"
    "                (default ./data)\n"
    "  --database URL  where the data lives instead: sqlite:PATH, or a PostgreSQL server as\n"
    "                postgresql://USER:PASSWORD@HOST:PORT/DB (libpq's form). Default: the\n"
    "                environment's INCISE_DATABASE_URL (keeps a password out of the process\n"
    "                list), else sqlite:DIR/incise.db\n"
    "  --node-id ID  this server's name among the nodes sharing the database (1-64 of a-z, A-Z,\n"
    "                0-9, '.', '_', '-'; default: $INCISE_NODE_ID, else the host's name). It\n"
    "                runs its own sessions; at start-up it ends only the ones it left running\n"
    "  --node-address HOST:PORT  where the other nodes reach this one, to forward a call about\n"
    "                a session it runs (plain HTTP; default: $INCISE_NODE_ADDRESS, else\n"
    "                --host, or the host's name when --host is 0.0.0.0 or ::, and the port)\n"
    "  --node-timeout S  a node whose heartbeat (every S/6 s) is S seconds old is taken for\n"
    "                dead: another node aborts its sessions (3-3600, default 30)\n"
    "  --web DIR     the built dashboard (default ./web/dist)\n"
    "  --demo        on a new database, add demo logins, a station and a curriculum\n"
    "  --threads N   I/O threads (default 2)\n"
    "  --render-threads N  threads (each with its EGL context) that render every session's and\n"
    "                replay's pictures (default half the cores, 1 to 8)\n"
    "  --tls-cert FILE  serve HTTPS and wss:// (TLS 1.2 or newer) with this PEM certificate\n"
    "                chain; needs --tls-key FILE, its PEM private key. Without them: plain HTTP\n"
    "  --secure-cookies  always mark the login cookie Secure (it is whenever a request came over\n"
    "                TLS, directly or from --trusted-proxy with X-Forwarded-Proto: https)\n"
    "  --trusted-proxy ADDR  the proxy's address, or a range of them (CIDR, as 10.244.0.0/16:\n"
    "                a Kubernetes pod network, where the Ingress and the other nodes are): for\n"
    "                their requests, the client is the last address of X-Forwarded-For (login\n"
    "                limits and logs count per client) and X-Forwarded-Proto says whether the\n"
    "                browser used HTTPS\n"
    "  --help        this text\n"
    "INCISE_ADMIN_PASSWORD in the environment: on a database without users, create the admin\n"
    "\"admin\" with this password, to be replaced at the first login (a real site's first login)\n"
    "Prints 'incise-server: listening on http://HOST:PORT' (https:// with TLS) when ready;\n"
    "SIGINT/SIGTERM stop it.\n";

bool is_node_id(const std::string& text) {
  if (text.empty() || text.size() > 64) return false;
  for (const char c : text) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '.' || c == '_' || c == '-';
    if (!ok) return false;
  }
  return true;
}

namespace {
bool parse_int(const std::string& text, long min, long max, long& out) {
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
  return ec == std::errc{} && end == text.data() + text.size() && out >= min && out <= max;
}
}  // namespace

bool is_ip_address(const std::string& text) {
  boost::system::error_code ec;
  boost::asio::ip::make_address(text, ec);
  return !ec;
}

bool is_node_address(const std::string& text) {
  const auto colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size()) return false;
  const std::string host = text.substr(0, colon);
  const std::string port = text.substr(colon + 1);
  long n = 0;
  if (!parse_int(port, 1, 65535, n)) return false;
  if (host.front() == '[') {
    return host.size() > 2 && host.back() == ']' && is_ip_address(host.substr(1, host.size() - 2));
  }
  if (host.size() > 253) return false;
  for (const char c : host) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '.' || c == '-';
    if (!ok) return false;
  }
  return true;
}

namespace {
// The last element of a comma-separated header, trimmed: what the proxy nearest to us appended.
std::string_view last_list_value(std::string_view list) {
  const auto comma = list.rfind(',');
  auto last = comma == std::string_view::npos ? list : list.substr(comma + 1);
  while (!last.empty() && (last.front() == ' ' || last.front() == '\t'))
    last.remove_prefix(1);
  while (!last.empty() && (last.back() == ' ' || last.back() == '\t'))
    last.remove_suffix(1);
  return last;
}
}  // namespace

bool is_address_range(const std::string& text) {
  if (text.find('/') == std::string::npos) return is_ip_address(text);
  boost::system::error_code ec;
  if (text.find(':') == std::string::npos) {
    boost::asio::ip::make_network_v4(text, ec);
  } else {
    boost::asio::ip::make_network_v6(text, ec);
  }
  return !ec;
}

bool from_trusted_proxy(const std::string& peer, const std::string& trusted_proxy) {
  if (trusted_proxy.empty()) return false;
  boost::system::error_code ec;
  auto address = boost::asio::ip::make_address(peer, ec);
  if (ec) return false;
  // An IPv4 client of a dual-stack listener arrives as ::ffff:a.b.c.d.
  if (address.is_v6() && address.to_v6().is_v4_mapped()) {
    address = boost::asio::ip::make_address_v4(boost::asio::ip::v4_mapped, address.to_v6());
  }
  if (trusted_proxy.find('/') == std::string::npos) {
    const auto trusted = boost::asio::ip::make_address(trusted_proxy, ec);
    return !ec && trusted == address;
  }
  if (address.is_v4()) {
    const auto range = boost::asio::ip::make_network_v4(trusted_proxy, ec);
    if (ec) return false;
    const auto mask = range.netmask().to_uint();
    return (address.to_v4().to_uint() & mask) == (range.address().to_uint() & mask);
  }
  const auto range = boost::asio::ip::make_network_v6(trusted_proxy, ec);
  if (ec) return false;
  const auto a = address.to_v6().to_bytes();
  const auto r = range.address().to_bytes();
  const int bits = range.prefix_length();
  for (int i = 0; i < bits; ++i) {
    const int mask = 0x80 >> (i % 8);
    if ((a[i / 8] & mask) != (r[i / 8] & mask)) return false;
  }
  return true;
}

std::string request_client(const std::string& peer, std::string_view forwarded_for,
                           const std::string& trusted_proxy) {
  if (!from_trusted_proxy(peer, trusted_proxy)) return peer;
  std::string client(last_list_value(forwarded_for));
  return is_ip_address(client) ? client : peer;
}

bool reached_over_tls(bool tls_connection, const std::string& peer,
                      std::string_view forwarded_proto, const std::string& trusted_proxy) {
  if (tls_connection) return true;
  if (!from_trusted_proxy(peer, trusted_proxy)) return false;
  return last_list_value(forwarded_proto) == "https";
}

ParsedOptions parse_server_options(const std::vector<std::string>& args) {
  ServerOptions o;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    auto value = [&](std::string& out) {
      if (i + 1 >= args.size()) return false;
      out = args[++i];
      return true;
    };
    std::string v;
    long n = 0;
    if (arg == "--help" || arg == "-h") {
      o.help = true;
    } else if (arg == "--demo") {
      o.demo = true;
    } else if (arg == "--secure-cookies") {
      o.secure_cookies = true;
    } else if (arg == "--trusted-proxy") {
      if (!value(v) || !is_address_range(v)) {
        return {std::nullopt, "--trusted-proxy needs an IP address or a CIDR range"};
      }
      o.trusted_proxy = v;
    } else if (arg == "--tls-cert") {
      if (!value(v)) return {std::nullopt, "--tls-cert needs a PEM certificate file"};
      o.tls_cert = v;
    } else if (arg == "--tls-key") {
      if (!value(v)) return {std::nullopt, "--tls-key needs a PEM private key file"};
      o.tls_key = v;
    } else if (arg == "--host") {
      if (!value(o.host)) return {std::nullopt, "--host needs an address"};
    } else if (arg == "--port") {
      if (!value(v) || !parse_int(v, 0, 65535, n)) {
        return {std::nullopt, "--port needs a number from 0 to 65535"};
      }
      o.port = static_cast<unsigned short>(n);
    } else if (arg == "--threads") {
      if (!value(v) || !parse_int(v, 1, 64, n)) {
        return {std::nullopt, "--threads needs a number from 1 to 64"};
      }
      o.threads = static_cast<int>(n);
    } else if (arg == "--render-threads") {
      if (!value(v) || !parse_int(v, 1, 64, n)) {
        return {std::nullopt, "--render-threads needs a number from 1 to 64"};
      }
      o.render_threads = static_cast<int>(n);
    } else if (arg == "--data") {
      if (!value(v)) return {std::nullopt, "--data needs a directory"};
      o.data_dir = v;
    } else if (arg == "--database") {
      if (!value(v))
        return {std::nullopt, "--database needs a URL (sqlite:PATH or postgresql://...)"};
      try {
        db::DatabaseUrl::parse(v);
      } catch (const std::invalid_argument& e) {
        return {std::nullopt, std::string("--database: ") + e.what()};
      }
      o.database = v;
    } else if (arg == "--node-id") {
      if (!value(v) || !is_node_id(v)) {
        return {std::nullopt, "--node-id needs 1-64 characters of a-z, A-Z, 0-9, '.', '_' or '-'"};
      }
      o.node_id = v;
    } else if (arg == "--node-address") {
      if (!value(v) || !is_node_address(v)) {
        return {std::nullopt, "--node-address needs HOST:PORT (a name, an IPv4 address or [IPv6])"};
      }
      o.node_address = v;
    } else if (arg == "--node-timeout") {
      if (!value(v) || !parse_int(v, 3, 3600, n)) {
        return {std::nullopt, "--node-timeout needs a number of seconds from 3 to 3600"};
      }
      o.node_timeout_s = static_cast<int>(n);
    } else if (arg == "--web") {
      if (!value(v)) return {std::nullopt, "--web needs a directory"};
      o.web_root = v;
    } else {
      return {std::nullopt, "unknown option '" + arg + "'"};
    }
  }
  if (o.tls_cert.empty() != o.tls_key.empty()) {
    return {std::nullopt, "--tls-cert and --tls-key go together"};
  }
  return {o, ""};
}

}  // namespace incise::server
