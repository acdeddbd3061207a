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
  EXPECT_FALSE(o.help);
}

TEST(ServerOptions, EveryFlag) {
  const auto parsed =
      parse_server_options({"--host", "0.0.0.0", "--port", "0", "--data", "/var/lib/incise",
                            "--web", "/srv/web", "--demo", "--threads", "4"});
  ASSERT_TRUE(parsed.options) << parsed.error;
  const auto& o = *parsed.options;
  EXPECT_EQ(o.host, "0.0.0.0");
  EXPECT_EQ(o.port, 0);
  EXPECT_EQ(o.data_dir, "/var/lib/incise");
  EXPECT_EQ(o.web_root, "/srv/web");
  EXPECT_TRUE(o.demo);
  EXPECT_EQ(o.threads, 4);
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
  for (const char* flag :
       {"--host", "--port", "--data", "--web", "--demo", "--threads", "--help"}) {
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

}  // namespace
}  // namespace incise::server
