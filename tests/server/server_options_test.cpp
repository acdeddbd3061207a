// The command line of incise-server: server/server_options.h.
#include "server/server_options.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace incise::server {
namespace {

TEST(ServerOptions, DefaultsWithoutArguments) {
  const auto parsed = parse_server_options({});
  ASSERT_TRUE(parsed.options) << parsed.error;
  EXPECT_EQ(parsed.error, "");
  const auto& o = *parsed.options;
  EXPECT_EQ(o.host, "127.0.0.1");
  EXPECT_EQ(o.port, 8080);
  EXPECT_EQ(o.data_dir, "data");
  EXPECT_EQ(o.web_root, "web/dist");
  EXPECT_FALSE(o.demo);
  EXPECT_EQ(o.threads, 2);
  EXPECT_EQ(o.render_threads, 0);  // the pool's own default
  EXPECT_FALSE(o.help);
}

TEST(ServerOptions, EveryFlag) {
  const auto parsed = parse_server_options({"--host", "0.0.0.0", "--port", "0", "--data",
                                            "/var/lib/incise", "--web", "/srv/web", "--demo",
                                            "--threads", "4", "--render-threads", "3"});
  ASSERT_TRUE(parsed.options) << parsed.error;
  const auto& o = *parsed.options;
  EXPECT_EQ(o.host, "0.0.0.0");
  EXPECT_EQ(o.port, 0);
  EXPECT_EQ(o.data_dir, "/var/lib/incise");
  EXPECT_EQ(o.web_root, "/srv/web");
  EXPECT_TRUE(o.demo);
  EXPECT_EQ(o.threads, 4);
  EXPECT_EQ(o.render_threads, 3);
  EXPECT_FALSE(o.help);
}

TEST(ServerOptions, RangeLimitsAreInclusive) {
  auto parsed = parse_server_options({"--port", "65535", "--threads", "64"});
  ASSERT_TRUE(parsed.options) << parsed.error;
  EXPECT_EQ(parsed.options->port, 65535);
  EXPECT_EQ(parsed.options->threads, 64);
  parsed = parse_server_options({"--threads", "1"});
  ASSERT_TRUE(parsed.options) << parsed.error;
  EXPECT_EQ(parsed.options->threads, 1);
}

TEST(ServerOptions, LaterFlagsWin) {
  const auto parsed = parse_server_options({"--port", "1", "--port", "2"});
  ASSERT_TRUE(parsed.options) << parsed.error;
  EXPECT_EQ(parsed.options->port, 2);
}

TEST(ServerOptions, Help) {
  for (const char* flag : {"--help", "-h"}) {
    const auto parsed = parse_server_options({flag});
    ASSERT_TRUE(parsed.options) << flag;
    EXPECT_TRUE(parsed.options->help) << flag;
  }
  for (const char* flag : {"--host", "--port", "--data", "--web", "--demo", "--threads",
                           "--render-threads", "--secure-cookies", "--trusted-proxy", "--help"}) {
    EXPECT_NE(std::string(kServerUsage).find(flag), std::string::npos) << flag;
  }
}

struct BadCommandLine {
  std::vector<std::string> args;
  std::string error;
};

TEST(ServerOptions, ErrorsNameTheProblem) {
  const std::string port = "--port needs a number from 0 to 65535";
  const std::string threads = "--threads needs a number from 1 to 64";
  const BadCommandLine cases[] = {
      {{"--port"}, port},
      {{"--port", "65536"}, port},
      {{"--port", "-1"}, port},
      {{"--port", "+80"}, port},
      {{"--port", "80x"}, port},
      {{"--port", ""}, port},
      {{"--port", "http"}, port},
      {{"--threads"}, threads},
      {{"--threads", "0"}, threads},
      {{"--threads", "65"}, threads},
      {{"--threads", "two"}, threads},
      {{"--render-threads", "0"}, "--render-threads needs a number from 1 to 64"},
      {{"--render-threads"}, "--render-threads needs a number from 1 to 64"},
      {{"--host"}, "--host needs an address"},
      {{"--data"}, "--data needs a directory"},
      {{"--web"}, "--web needs a directory"},
      {{"--bogus"}, "unknown option '--bogus'"},
      {{"serve"}, "unknown option 'serve'"},
      {{"--demo", "--port=80"}, "unknown option '--port=80'"},
  };
  for (const auto& c : cases) {
    const auto parsed = parse_server_options(c.args);
    std::string line;
    for (const auto& a : c.args)
      line += "[" + a + "]";
    EXPECT_FALSE(parsed.options) << line;
    EXPECT_EQ(parsed.error, c.error) << line;
  }
}

TEST(ServerOptions, DatabaseUrlNamesTheEngine) {
  EXPECT_EQ(parse_server_options({}).options->database, "") << "the default: sqlite:DATA/incise.db";
  for (const char* url : {"sqlite:/var/lib/incise/incise.db", "postgresql://incise@db/incise"}) {
    const auto parsed = parse_server_options({"--database", url});
    ASSERT_TRUE(parsed.options) << parsed.error;
    EXPECT_EQ(parsed.options->database, url);
  }
  const auto bad = parse_server_options({"--database", "mysql://db/incise"});
  EXPECT_FALSE(bad.options);
  EXPECT_EQ(bad.error.rfind("--database: database URL 'mysql://db/incise' is neither", 0), 0u)
      << bad.error;
  EXPECT_FALSE(parse_server_options({"--database"}).options) << "a URL is required";
}

TEST(ServerOptions, NodeIdAndTimeout) {
  const auto defaults = parse_server_options({});
  EXPECT_EQ(defaults.options->node_id, "") << "the environment's or the host's name";
  EXPECT_EQ(defaults.options->node_timeout_s, 30);
  const auto parsed =
      parse_server_options({"--node-id", "incise-server-0.incise", "--node-timeout", "3"});
  ASSERT_TRUE(parsed.options) << parsed.error;
  EXPECT_EQ(parsed.options->node_id, "incise-server-0.incise");
  EXPECT_EQ(parsed.options->node_timeout_s, 3);
  for (const char* bad : {"", "a b", "x/y", "ü"}) {
    EXPECT_FALSE(parse_server_options({"--node-id", bad}).options) << bad;
  }
  EXPECT_FALSE(parse_server_options({"--node-id", std::string(65, 'a')}).options);
  EXPECT_TRUE(parse_server_options({"--node-id", std::string(64, 'a')}).options);
  EXPECT_FALSE(parse_server_options({"--node-timeout", "2"}).options);
  EXPECT_FALSE(parse_server_options({"--node-timeout", "3601"}).options);
}

TEST(ServerOptions, BehindAProxy) {
  const auto parsed = parse_server_options({"--secure-cookies", "--trusted-proxy", "10.0.0.2"});
  ASSERT_TRUE(parsed.options) << parsed.error;
  EXPECT_TRUE(parsed.options->secure_cookies);
  EXPECT_EQ(parsed.options->trusted_proxy, "10.0.0.2");
  EXPECT_FALSE(parse_server_options({}).options->secure_cookies);
  EXPECT_EQ(parse_server_options({"--trusted-proxy", "proxy.local"}).error,
            "--trusted-proxy needs an IP address or a CIDR range");
  EXPECT_EQ(parse_server_options({"--trusted-proxy"}).error,
            "--trusted-proxy needs an IP address or a CIDR range");
  EXPECT_EQ(parse_server_options({"--trusted-proxy", "10.0.0.0/33"}).error,
            "--trusted-proxy needs an IP address or a CIDR range");
  EXPECT_EQ(parse_server_options({"--trusted-proxy", "10.244.0.0/16"}).options->trusted_proxy,
            "10.244.0.0/16");
}

TEST(ServerOptions, TlsNeedsBothTheCertificateAndTheKey) {
  const auto parsed = parse_server_options({"--tls-cert", "c.pem", "--tls-key", "k.pem"});
  ASSERT_TRUE(parsed.options) << parsed.error;
  EXPECT_EQ(parsed.options->tls_cert, "c.pem");
  EXPECT_EQ(parsed.options->tls_key, "k.pem");
  EXPECT_TRUE(parse_server_options({}).options->tls_cert.empty());
  EXPECT_EQ(parse_server_options({"--tls-cert", "c.pem"}).error,
            "--tls-cert and --tls-key go together");
  EXPECT_EQ(parse_server_options({"--tls-key", "k.pem"}).error,
            "--tls-cert and --tls-key go together");
  EXPECT_EQ(parse_server_options({"--tls-cert"}).error, "--tls-cert needs a PEM certificate file");
}

TEST(ReachedOverTls, ATlsConnectionOrTheTrustedProxySayingHttps) {
  EXPECT_TRUE(reached_over_tls(true, "192.0.2.7", "", ""));
  EXPECT_FALSE(reached_over_tls(false, "192.0.2.7", "", ""));
  // The header from anyone but the trusted proxy is the client's own claim.
  EXPECT_FALSE(reached_over_tls(false, "192.0.2.7", "https", ""));
  EXPECT_FALSE(reached_over_tls(false, "192.0.2.7", "https", "10.0.0.2"));
  EXPECT_TRUE(reached_over_tls(false, "10.0.0.2", "https", "10.0.0.2"));
  EXPECT_FALSE(reached_over_tls(false, "10.0.0.2", "http", "10.0.0.2"));
  EXPECT_FALSE(reached_over_tls(false, "10.0.0.2", "", "10.0.0.2"));
  // What the proxy nearest to us appended counts.
  EXPECT_TRUE(reached_over_tls(false, "10.0.0.2", "http, https", "10.0.0.2"));
  EXPECT_FALSE(reached_over_tls(false, "10.0.0.2", "https,http ", "10.0.0.2"));
}

TEST(RequestClient, OnlyTheTrustedProxysLastForwardedAddressIsBelieved) {
  // Directly connected: the header is the client's own claim and ignored.
  EXPECT_EQ(request_client("192.0.2.7", "203.0.113.1", ""), "192.0.2.7");
  EXPECT_EQ(request_client("192.0.2.7", "203.0.113.1", "10.0.0.2"), "192.0.2.7");
  // Through the proxy: the address it appended, not what the client put before it.
  EXPECT_EQ(request_client("10.0.0.2", "203.0.113.1", "10.0.0.2"), "203.0.113.1");
  EXPECT_EQ(request_client("10.0.0.2", "1.2.3.4, 203.0.113.1", "10.0.0.2"), "203.0.113.1");
  EXPECT_EQ(request_client("10.0.0.2", "1.2.3.4,2001:db8::5 ", "10.0.0.2"), "2001:db8::5");
  // A proxy that sent no usable address: the proxy it is.
  EXPECT_EQ(request_client("10.0.0.2", "", "10.0.0.2"), "10.0.0.2");
  EXPECT_EQ(request_client("10.0.0.2", "1.2.3.4, unknown", "10.0.0.2"), "10.0.0.2");
}

TEST(FromTrustedProxy, AnAddressOrARange) {
  EXPECT_FALSE(from_trusted_proxy("10.0.0.2", ""));
  EXPECT_TRUE(from_trusted_proxy("10.0.0.2", "10.0.0.2"));
  EXPECT_FALSE(from_trusted_proxy("10.0.0.3", "10.0.0.2"));
  // A pod network: the Ingress's pods and the other nodes, wherever they are scheduled.
  EXPECT_TRUE(from_trusted_proxy("10.244.7.19", "10.244.0.0/16"));
  EXPECT_TRUE(from_trusted_proxy("10.244.0.0", "10.244.0.0/16"));
  EXPECT_TRUE(from_trusted_proxy("10.244.255.255", "10.244.0.0/16"));
  EXPECT_FALSE(from_trusted_proxy("10.245.0.1", "10.244.0.0/16"));
  EXPECT_FALSE(from_trusted_proxy("10.243.255.255", "10.244.0.0/16"));
  EXPECT_TRUE(from_trusted_proxy("10.0.0.2", "10.0.0.2/32"));
  EXPECT_FALSE(from_trusted_proxy("10.0.0.3", "10.0.0.2/32"));
  EXPECT_TRUE(from_trusted_proxy("192.0.2.1", "0.0.0.0/0"));
  EXPECT_TRUE(from_trusted_proxy("fd00:10:244::1f", "fd00:10:244::/56"));
  EXPECT_FALSE(from_trusted_proxy("fd00:10:245::1f", "fd00:10:244::/56"));
  EXPECT_FALSE(from_trusted_proxy("10.244.0.1", "fd00:10:244::/56")) << "another family";
  EXPECT_FALSE(from_trusted_proxy("fd00:10:244::1", "10.244.0.0/16"));
  EXPECT_FALSE(from_trusted_proxy("not an address", "10.244.0.0/16"));
  // An IPv4 client of a dual-stack listener, and another spelling of the same address.
  EXPECT_TRUE(from_trusted_proxy("::ffff:10.244.1.2", "10.244.0.0/16"));
  EXPECT_TRUE(from_trusted_proxy("::ffff:10.0.0.2", "10.0.0.2"));
  EXPECT_TRUE(from_trusted_proxy("2001:db8:0:0::1", "2001:db8::1"));
  EXPECT_EQ(request_client("10.244.3.4", "203.0.113.1", "10.244.0.0/16"), "203.0.113.1");
  EXPECT_TRUE(reached_over_tls(false, "10.244.3.4", "https", "10.244.0.0/16"));
}

}  // namespace
}  // namespace incise::server
