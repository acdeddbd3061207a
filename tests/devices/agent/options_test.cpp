// The agent's configuration file and its merge with the command line: config_file_args,
// config_path and parse_agent_options in devices/agent/options.h.

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include <array>
#include <string>
#include <vector>

#include "devices/agent/options.h"

namespace incise::devices::agent {
namespace {

using Args = std::vector<const char*>;

// The configuration's arguments; fails the test on a parse error.
std::vector<std::string> config(std::string_view text) {
  auto parsed = config_file_args(text, "agent.conf");
  EXPECT_TRUE(parsed) << parsed.error;
  return parsed ? *parsed.value : std::vector<std::string>{};
}

std::string config_error(std::string_view text) {
  return config_file_args(text, "/etc/incise/agent.conf").error;
}

// Options from a configuration text and a command line, with a token in the environment.
ParseResult<AgentOptions> parse(std::string_view config_text, Args args) {
  const std::vector<std::string> from_file = config(config_text);
  return parse_agent_options(args, "env-token", from_file);
}

TEST(ConfigFile, CommentsAndBlankLinesAreIgnoredAndValuesTrimmed) {
  const std::string text =
      "# Station 3, left bench\n"
      "\n"
      "   \t \n"
      "server = ws://10.0.0.5:8080/agent   # the lab server\n"
      "  rate=750\r\n"
      "device\t=  evdev:/dev/input/event3  \n"
      "token = a=b==c\n"  // only the first '=' separates
      "# device = simulated\n"
      "passivity = on";  // no final newline
  EXPECT_EQ(config(text),
            (std::vector<std::string>{"--server=ws://10.0.0.5:8080/agent", "--rate=750",
                                      "--device=evdev:/dev/input/event3", "--token=a=b==c",
                                      "--passivity=on"}));
  EXPECT_TRUE(config("").empty());
  EXPECT_TRUE(config("# only a comment\n\n").empty());
}

TEST(ConfigFile, EachBadLineIsNamedByFileAndLine) {
  EXPECT_EQ(config_error("rate = 500\n\nthis line has no equals sign\n"),
            "/etc/incise/agent.conf:3: expected key = value");
  EXPECT_EQ(config_error("# header\nspeed = 3\n"), "/etc/incise/agent.conf:2: unknown key 'speed'");
  EXPECT_EQ(config_error("rate =   # forgot it\n"),
            "/etc/incise/agent.conf:1: 'rate' has no value");
  // A file cannot name another file, and switches are spelt "deadband = off", not as flags.
  EXPECT_EQ(config_error("config = other.conf\n"),
            "/etc/incise/agent.conf:1: unknown key 'config'");
  EXPECT_EQ(config_error("no-deadband = yes\n"),
            "/etc/incise/agent.conf:1: unknown key 'no-deadband'");
  EXPECT_EQ(config_error("--rate = 500\n"), "/etc/incise/agent.conf:1: unknown key '--rate'");
  EXPECT_EQ(config_error(" = 500\n"), "/etc/incise/agent.conf:1: unknown key ''");
  // The first bad line is reported, however many follow.
  EXPECT_EQ(config_error("rate = 500\r\nfoo\r\nbar = 1\r\n"),
            "/etc/incise/agent.conf:2: expected key = value");
}

TEST(ConfigFile, ConfigPathIsFoundInEitherSpelling) {
  EXPECT_EQ(*config_path(Args{"--rate", "500"}).value, "");
  EXPECT_EQ(*config_path(Args{"--config", "a.conf", "--rate=500"}).value, "a.conf");
  EXPECT_EQ(*config_path(Args{"--rate=500", "--config=b.conf"}).value, "b.conf");
  EXPECT_EQ(config_path(Args{"--rate=500", "--config"}).error, "--config needs a value");
}

TEST(AgentOptions, TheCommandLineOverridesTheFile) {
  const std::string file =
      "server = ws://file-host:9000/agent\n"
      "token = file-token\n"
      "rate = 750\n"
      "record-states = /var/log/file.states\n";
  const auto from_file = parse(file, {});
  ASSERT_TRUE(from_file) << from_file.error;
  EXPECT_EQ(from_file.value->server.url(), "ws://file-host:9000/agent");
  EXPECT_EQ(from_file.value->token, "file-token");  // the file's token wins over the environment
  EXPECT_EQ(from_file.value->rate_hz, 750.0);
  EXPECT_EQ(from_file.value->record_states, "/var/log/file.states");

  const auto overridden =
      parse(file, {"--server", "ws://cli-host/x", "--rate", "300", "--record-states=cli.states"});
  ASSERT_TRUE(overridden) << overridden.error;
  EXPECT_EQ(overridden.value->server.url(), "ws://cli-host:80/x");
  EXPECT_EQ(overridden.value->token, "file-token");
  EXPECT_EQ(overridden.value->rate_hz, 300.0);
  EXPECT_EQ(overridden.value->record_states, "cli.states");
  // The file is still checked: a bad value there is an error even if the command line has one.
  const auto bad = parse("rate = 5000\n", {"--rate", "500"});
  EXPECT_EQ(bad.error, "--rate 5000: must be a number of Hz in [250, 1000]");
}

TEST(AgentOptions, DevicesOnTheCommandLineReplaceTheFilesAndAccumulateUpToTwo) {
  const std::string two = "device = evdev:/dev/input/event3\ndevice = replay:left.states\n";
  const auto from_file = parse(two, {});
  ASSERT_TRUE(from_file) << from_file.error;
  EXPECT_EQ(from_file.value->devices,
            (std::vector<std::string>{"evdev:/dev/input/event3", "replay:left.states"}));

  const auto replaced = parse(two, {"--device", "simulated"});
  ASSERT_TRUE(replaced) << replaced.error;
  EXPECT_EQ(replaced.value->devices, (std::vector<std::string>{"simulated"}));

  const auto both = parse(two, {"--device=simulated", "--script", "right.json"});
  ASSERT_TRUE(both) << both.error;
  EXPECT_EQ(both.value->devices, (std::vector<std::string>{"simulated", "simulated:right.json"}));

  EXPECT_EQ(parse(two + "device = simulated\n", {}).error,
            "--device simulated: a station has at most 2 devices");
  EXPECT_EQ(parse("", {"--device", "a", "--device", "b", "--script", "c.json"}).error,
            "--script c.json: a station has at most 2 devices");
}

TEST(AgentOptions, ScriptIsShortForASimulatedDeviceAndSimulatedIsTheDefault) {
  const auto defaults = parse("", {});
  ASSERT_TRUE(defaults) << defaults.error;
  EXPECT_EQ(defaults.value->devices, (std::vector<std::string>{"simulated"}));
  EXPECT_EQ(defaults.value->token, "env-token");
  EXPECT_TRUE(defaults.value->deadband);
  EXPECT_TRUE(defaults.value->guard.passivity);

  const auto script = parse("script = /srv/left.json\n", {});
  ASSERT_TRUE(script) << script.error;
  EXPECT_EQ(script.value->devices, (std::vector<std::string>{"simulated:/srv/left.json"}));
}

TEST(AgentOptions, SwitchesFromTheFileAndTheCommandLine) {
  struct Case {
    std::string file;
    Args args;
    bool deadband;
    bool passivity;
  };
  const Case cases[] = {
      {"", {"--no-deadband"}, false, true},
      {"", {"--no-passivity"}, true, false},
      {"deadband = off\n", {}, false, true},
      {"deadband = no\npassivity = false\n", {}, false, false},
      {"deadband = off\n", {"--deadband=on"}, true, true},
      {"passivity = 0\n", {"--passivity", "yes"}, true, true},
      {"deadband = true\n", {"--no-deadband"}, false, true},
  };
  for (const Case& c : cases) {
    const auto parsed = parse(c.file, c.args);
    ASSERT_TRUE(parsed) << c.file << ": " << parsed.error;
    EXPECT_EQ(parsed.value->deadband, c.deadband) << c.file;
    EXPECT_EQ(parsed.value->guard.passivity, c.passivity) << c.file;
  }
  EXPECT_EQ(parse("deadband = maybe\n", {}).error, "--deadband maybe: must be on or off");
  EXPECT_EQ(parse("", {"--passivity=OFF"}).error, "--passivity OFF: must be on or off");
}

TEST(AgentOptions, MaxForceAndCouplingSetTheGuardWithinTheirRanges) {
  const auto defaults = parse("", {});
  ASSERT_TRUE(defaults);
  const ForceGuardSettings stock;
  EXPECT_EQ(defaults.value->guard.max_force_n, stock.max_force_n);
  EXPECT_EQ(defaults.value->guard.coupling_stiffness, stock.coupling_stiffness);

  const auto set = parse("max-force = 4.5\ncoupling = 800\n", {});
  ASSERT_TRUE(set) << set.error;
  EXPECT_EQ(set.value->guard.max_force_n, (std::array<double, 3>{4.5, 4.5, 4.5}));
  EXPECT_EQ(set.value->guard.coupling_stiffness, 800.0);
  // The rest of the guard keeps its defaults.
  EXPECT_EQ(set.value->guard.coupling_damping, stock.coupling_damping);
  EXPECT_EQ(set.value->guard.max_force_rate_n_s, stock.max_force_rate_n_s);

  // The ends of the ranges: (0, 40] N and [10, 20000] N/m.
  EXPECT_TRUE(parse("", {"--max-force", "40"}));
  EXPECT_TRUE(parse("", {"--coupling", "10"}));
  EXPECT_TRUE(parse("", {"--coupling", "20000"}));
  for (const char* bad : {"0", "-1", "40.5", "nan", "inf", "8N", ""}) {
    EXPECT_EQ(parse("", {"--max-force", bad}).error,
              std::string("--max-force ") + bad + ": must be a number of N in (0, 40]");
  }
  for (const char* bad : {"9.99", "20001", "stiff", "1e9"}) {
    EXPECT_EQ(parse("", {"--coupling", bad}).error,
              std::string("--coupling ") + bad + ": must be a number of N/m in [10, 20000]");
  }
}

TEST(AgentOptions, TokenAndUnknownFlags) {
  // The token never comes from the command line (ps shows it to every local user), in either
  // form; it comes from the environment or the configuration file, and without either it is an
  // error.
  const std::string refused =
      "--token on the command line is refused (any local user can read it in ps): set "
      "INCISE_STATION_TOKEN or put token = ... in the --config file";
  EXPECT_EQ(parse("", {"--token", "cli"}).error, refused);
  EXPECT_EQ(parse("", {"--token=cli"}).error, refused);
  const auto env = parse("", {});
  ASSERT_TRUE(env) << env.error;
  EXPECT_EQ(env.value->token, "env-token");
  EXPECT_EQ(parse_agent_options(Args{}, nullptr).error,
            "no station token: set INCISE_STATION_TOKEN or put token = ... in the --config file");
  EXPECT_EQ(parse("", {"--frobnicate"}).error, "unknown option '--frobnicate'");
  EXPECT_EQ(parse("", {"--rate"}).error, "--rate needs a value");
  // --config is read by the caller, and accepted (and skipped) here.
  const auto with_config = parse("", {"--config", "agent.conf", "--rate=250"});
  ASSERT_TRUE(with_config) << with_config.error;
  EXPECT_EQ(with_config.value->rate_hz, 250.0);
}

// The example shipped for the systemd unit parses and says what its comments say.
TEST(AgentOptions, WssUrlsAskForTlsOnPort443AndTheCaComesFromTheFileOrCommandLine) {
  const auto secure = parse_server_url("wss://lab.example:8443/agent");
  ASSERT_TRUE(secure) << secure.error;
  EXPECT_TRUE(secure.value->tls);
  EXPECT_EQ(secure.value->port, "8443");
  EXPECT_EQ(secure.value->url(), "wss://lab.example:8443/agent");
  EXPECT_EQ(parse_server_url("wss://lab.example/agent").value->port, "443");
  EXPECT_EQ(parse_server_url("ws://lab.example/agent").value->port, "80");
  EXPECT_FALSE(parse_server_url("ws://lab.example/agent").value->tls);
  EXPECT_EQ(parse_server_url("https://lab.example/agent").error,
            "--server https://lab.example/agent: must start with ws:// or wss://");

  const auto from_file = parse("server = wss://lab.example/agent\nca = /etc/incise/ca.pem\n", {});
  ASSERT_TRUE(from_file) << from_file.error;
  EXPECT_EQ(from_file.value->ca_file, "/etc/incise/ca.pem");
  EXPECT_TRUE(from_file.value->server.tls);
  const auto overridden = parse("ca = /etc/incise/ca.pem\n", {"--ca", "/tmp/site.pem"});
  ASSERT_TRUE(overridden) << overridden.error;
  EXPECT_EQ(overridden.value->ca_file, "/tmp/site.pem");
}

TEST(ConfigFile, TheDeployedExampleParses) {
  std::ifstream file(INCISE_AGENT_CONF);
  ASSERT_TRUE(file) << INCISE_AGENT_CONF;
  const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const auto config = config_file_args(text, INCISE_AGENT_CONF);
  ASSERT_TRUE(config) << config.error;
  const auto options = parse_agent_options({}, "token-from-env", *config.value);
  ASSERT_TRUE(options) << options.error;
  EXPECT_EQ(options.value->server.host, "incise.example.org");
  EXPECT_TRUE(options.value->server.tls);
  EXPECT_EQ(options.value->devices, std::vector<std::string>{"simulated"});
  EXPECT_EQ(options.value->rate_hz, 500.0);
  EXPECT_TRUE(options.value->deadband);
  EXPECT_TRUE(options.value->guard.passivity);
  EXPECT_EQ(options.value->guard.max_force_n[0], 8.0);
  EXPECT_EQ(options.value->token, "token-from-env");
}

}  // namespace
}  // namespace incise::devices::agent
