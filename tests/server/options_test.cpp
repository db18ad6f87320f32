// tumbled's command line: every flag, its default, and every check with
// the sentence a user reads.
#include "options.h"

#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/scoped_env.h"
#include "tumble/version.h"

namespace tumble::server {
namespace {

using tumble::test::ScopedEnv;

// Clears the token variables for one test, so the machine's cannot leak in.
class ServerOptionsTest : public ::testing::Test {
 private:
  ScopedEnv token_{"TUMBLE_TOKEN", nullptr};
  ScopedEnv observer_token_{"TUMBLE_OBSERVER_TOKEN", nullptr};
};

// Parses `args` as the words after "tumbled".
ParsedServerOptions parse(std::vector<std::string> args) {
  args.insert(args.begin(), "tumbled");
  std::vector<const char*> argv;
  for (const std::string& arg : args) argv.push_back(arg.c_str());
  return parse_server_options(static_cast<int>(argv.size()), argv.data());
}

// Parses a command line that must be valid.
ServerOptions options_of(std::vector<std::string> args) {
  ParsedServerOptions parsed = parse(std::move(args));
  EXPECT_TRUE(parsed.options.has_value()) << parsed.text;
  return parsed.options.value_or(ServerOptions{});
}

// The one-line reason a command line is refused, after checking that it is
// a usage error.
std::string usage_error(std::vector<std::string> args) {
  std::string joined;
  for (const std::string& arg : args) joined += arg + " ";
  ParsedServerOptions parsed = parse(std::move(args));
  EXPECT_FALSE(parsed.options.has_value()) << joined;
  EXPECT_EQ(parsed.exit_code, kExitUsage) << joined;
  EXPECT_EQ(parsed.text.find('\n'), std::string::npos) << parsed.text;
  return parsed.text;
}

TEST_F(ServerOptionsTest, Defaults) {
  const ServerOptions options = options_of({});
  EXPECT_EQ(options.listen.host, "127.0.0.1");
  EXPECT_EQ(options.listen.port, 7400);
  EXPECT_EQ(options.port_file, "");
  EXPECT_FALSE(options.http.has_value());
  EXPECT_EQ(options.http_port_file, "");
  EXPECT_EQ(options.max_http_connections, 64u);
  EXPECT_EQ(options.http_header_timeout_seconds, 10);
  EXPECT_TRUE(options.http_allowed_hosts.empty());
  EXPECT_EQ(options.scene_path, "");
  EXPECT_EQ(options.tick_rate_hz, 240);
  EXPECT_EQ(options.max_bodies, 100000u);
  EXPECT_EQ(options.physics_threads, 1);
  EXPECT_EQ(options.max_frame_bytes, std::size_t{1} << 20);
  EXPECT_EQ(options.max_pending_bytes, std::size_t{8} << 20);
  EXPECT_EQ(options.max_connections, 1024u);
  EXPECT_EQ(options.max_commands_per_second, 1000u);
  EXPECT_EQ(options.max_errors_per_second, 100u);
  EXPECT_EQ(options.handshake_timeout_seconds, 10);
  EXPECT_EQ(options.frame_timeout_seconds, 10);
  EXPECT_EQ(options.max_undelivered_seconds, 10);
  EXPECT_EQ(options.tokens.controller, "");
  EXPECT_EQ(options.tokens.observer, "");
  EXPECT_EQ(options.state_path, "");
  EXPECT_EQ(options.checkpoint_interval_seconds, 0);
  EXPECT_EQ(options.record_path, "");
  EXPECT_EQ(options.replay_path, "");
  EXPECT_EQ(options.realtime_priority, 0);
  EXPECT_FALSE(options.keep_cpus_awake);
  EXPECT_EQ(options.log_level, "info");
}

TEST_F(ServerOptionsTest, EveryFlagIsRead) {
  const ServerOptions options = options_of({"--listen",
                                            "[::1]:7500",
                                            "--port-file",
                                            "/run/port",
                                            "--http",
                                            "0.0.0.0:8081",
                                            "--http-port-file",
                                            "/run/http-port",
                                            "--max-http-connections",
                                            "16",
                                            "--http-header-timeout",
                                            "2.5",
                                            "--http-allowed-hosts",
                                            "viewer.example,lab.example:9000",
                                            "--scene",
                                            "scenes/pile.json",
                                            "--tick-rate",
                                            "120.5",
                                            "--max-bodies",
                                            "50",
                                            "--physics-threads",
                                            "4",
                                            "--max-frame-bytes",
                                            "4096",
                                            "--max-pending-bytes",
                                            "65536",
                                            "--max-connections",
                                            "8",
                                            "--max-commands-per-second",
                                            "20",
                                            "--max-errors-per-second",
                                            "7",
                                            "--handshake-timeout",
                                            "0.5",
                                            "--frame-timeout",
                                            "1.5",
                                            "--max-undelivered-seconds",
                                            "2.5",
                                            "--token",
                                            "ctl",
                                            "--observer-token",
                                            "obs",
                                            "--state",
                                            "/var/world.state",
                                            "--checkpoint-interval",
                                            "30",
                                            "--record",
                                            "/var/run.journal",
                                            "--realtime-priority",
                                            "5",
                                            "--keep-cpus-awake",
                                            "--log-level",
                                            "debug"});
  EXPECT_EQ(options.listen.host, "::1");
  EXPECT_EQ(options.listen.port, 7500);
  EXPECT_EQ(options.port_file, "/run/port");
  ASSERT_TRUE(options.http.has_value());
  EXPECT_EQ(options.http->host, "0.0.0.0");
  EXPECT_EQ(options.http->port, 8081);
  EXPECT_EQ(options.http_port_file, "/run/http-port");
  EXPECT_EQ(options.max_http_connections, 16u);
  EXPECT_EQ(options.http_header_timeout_seconds, 2.5);
  EXPECT_EQ(options.http_allowed_hosts, (std::vector<std::string>{"viewer.example", "lab.example:9000"}));
  EXPECT_EQ(options.scene_path, "scenes/pile.json");
  EXPECT_EQ(options.tick_rate_hz, 120.5);
  EXPECT_EQ(options.max_bodies, 50u);
  EXPECT_EQ(options.physics_threads, 4);
  EXPECT_EQ(options.max_frame_bytes, 4096u);
  EXPECT_EQ(options.max_pending_bytes, 65536u);
  EXPECT_EQ(options.max_connections, 8u);
  EXPECT_EQ(options.max_commands_per_second, 20u);
  EXPECT_EQ(options.max_errors_per_second, 7u);
  EXPECT_EQ(options.handshake_timeout_seconds, 0.5);
  EXPECT_EQ(options.frame_timeout_seconds, 1.5);
  EXPECT_EQ(options.max_undelivered_seconds, 2.5);
  EXPECT_EQ(options.tokens.controller, "ctl");
  EXPECT_EQ(options.tokens.observer, "obs");
  EXPECT_EQ(options.state_path, "/var/world.state");
  EXPECT_EQ(options.checkpoint_interval_seconds, 30);
  EXPECT_EQ(options.record_path, "/var/run.journal");
  EXPECT_EQ(options.realtime_priority, 5);
  EXPECT_TRUE(options.keep_cpus_awake);
  EXPECT_EQ(options.log_level, "debug");

  EXPECT_EQ(options_of({"--replay", "/var/run.journal"}).replay_path, "/var/run.journal");
}

TEST_F(ServerOptionsTest, PortZeroAsksForAFreePort) {
  const ServerOptions options = options_of({"--listen", "127.0.0.1:0", "--http", "[::1]:0"});
  EXPECT_EQ(options.listen.host, "127.0.0.1");
  EXPECT_EQ(options.listen.port, 0);
  ASSERT_TRUE(options.http.has_value());
  EXPECT_EQ(options.http->host, "::1");
  EXPECT_EQ(options.http->port, 0);
}

TEST_F(ServerOptionsTest, AddressesThatAreNotHostPort) {
  EXPECT_EQ(usage_error({"--listen", "no-port"}), "--listen: 'no-port' is not HOST:PORT: the port is missing");
  EXPECT_EQ(usage_error({"--listen", "localhost:65536"}),
            "--listen: 'localhost:65536' is not HOST:PORT: the port must be a number from 0 to 65535");
  EXPECT_EQ(usage_error({"--listen", "::1:7400"}),
            "--listen: '::1:7400' is not HOST:PORT: write an IPv6 address in brackets, as in [::1]:7400");
  EXPECT_EQ(usage_error({"--listen", ":7400"}), "--listen: ':7400' is not HOST:PORT: the host is missing");
  EXPECT_EQ(usage_error({"--http", "no-port"}), "--http: 'no-port' is not HOST:PORT: the port is missing");
  EXPECT_EQ(usage_error({"--http", "[::1:8080"}), "--http: '[::1:8080' is not HOST:PORT: unbalanced '['");
}

TEST_F(ServerOptionsTest, NumbersOutOfRange) {
  EXPECT_EQ(usage_error({"--tick-rate", "0"}), "--tick-rate: Value 0 not in range 1.000000 to 10000.000000");
  EXPECT_EQ(usage_error({"--tick-rate", "10001"}), "--tick-rate: Value 10001 not in range 1.000000 to 10000.000000");
  EXPECT_EQ(usage_error({"--max-bodies", "0"}), "--max-bodies: Value 0 not in range 1 to 10000000");
  EXPECT_EQ(usage_error({"--physics-threads", "65"}), "--physics-threads: Value 65 not in range 1 to 64");
  EXPECT_EQ(usage_error({"--max-frame-bytes", "63"}), "--max-frame-bytes: Value 63 not in range 64 to 1073741824");
  EXPECT_EQ(usage_error({"--max-pending-bytes", "4095"}),
            "--max-pending-bytes: Value 4095 not in range 4096 to 17179869184");
  EXPECT_EQ(usage_error({"--max-connections", "0"}), "--max-connections: Value 0 not in range 1 to 1000000");
  EXPECT_EQ(usage_error({"--max-commands-per-second", "0"}),
            "--max-commands-per-second: Value 0 not in range 1 to 1000000000");
  EXPECT_EQ(usage_error({"--max-errors-per-second", "0"}),
            "--max-errors-per-second: Value 0 not in range 1 to 1000000000");
  EXPECT_EQ(usage_error({"--frame-timeout", "0"}), "--frame-timeout: Value 0 not in range 0.001000 to 86400.000000");
  EXPECT_EQ(usage_error({"--http", "127.0.0.1:0", "--max-http-connections", "0"}),
            "--max-http-connections: Value 0 not in range 1 to 1000000");
  EXPECT_EQ(usage_error({"--http", "127.0.0.1:0", "--http-header-timeout", "86401"}),
            "--http-header-timeout: Value 86401 not in range 0.001000 to 86400.000000");
  EXPECT_EQ(usage_error({"--http", "127.0.0.1:0", "--http-allowed-hosts", "a,http://b:8080"}),
            "--http-allowed-hosts: 'http://b:8080' is not a host name: give NAME, NAME:PORT or *");
  EXPECT_EQ(usage_error({"--handshake-timeout", "0"}),
            "--handshake-timeout: Value 0 not in range 0.001000 to 86400.000000");
  EXPECT_EQ(usage_error({"--max-undelivered-seconds", "86401"}),
            "--max-undelivered-seconds: Value 86401 not in range 0.001000 to 86400.000000");
  EXPECT_EQ(usage_error({"--state", "s", "--checkpoint-interval", "0.001"}),
            "--checkpoint-interval: Value 0.001 not in range 0.010000 to 86400.000000");
  EXPECT_EQ(usage_error({"--realtime-priority", "100"}), "--realtime-priority: Value 100 not in range 0 to 99");
  EXPECT_EQ(usage_error({"--realtime-priority", "-1"}), "--realtime-priority: Value -1 not in range 0 to 99");
}

TEST_F(ServerOptionsTest, WordsWhereNumbersOrLevelsBelong) {
  // CLI11 checks the range before it converts: a word is out of range.
  EXPECT_EQ(usage_error({"--tick-rate", "fast"}), "--tick-rate: Value fast not in range 1.000000 to 10000.000000");
  EXPECT_EQ(usage_error({"--max-connections", "many"}), "--max-connections: Value many not in range 1 to 1000000");
  EXPECT_EQ(usage_error({"--log-level", "loud"}),
            "--log-level: loud not in {trace,debug,info,warn,error,critical,off}");
  EXPECT_EQ(usage_error({"--no-such-flag"}), "The following argument was not expected: --no-such-flag");
}

TEST_F(ServerOptionsTest, FlagsThatNeedOrExcludeOthers) {
  EXPECT_EQ(usage_error({"--checkpoint-interval", "1"}),
            "--checkpoint-interval needs --state or --nats-state: somewhere to write the checkpoints");
  EXPECT_EQ(usage_error({"--http-port-file", "/tmp/x"}), "--http-port-file requires --http");
  EXPECT_EQ(usage_error({"--max-http-connections", "8"}), "--max-http-connections requires --http");
  EXPECT_EQ(usage_error({"--http-header-timeout", "5"}), "--http-header-timeout requires --http");
  EXPECT_EQ(usage_error({"--http-allowed-hosts", "viewer.example"}), "--http-allowed-hosts requires --http");
  EXPECT_EQ(usage_error({"--record", "a.journal", "--replay", "b.journal"}), "--record excludes --replay");
}

TEST_F(ServerOptionsTest, TokensMustDiffer) {
  EXPECT_EQ(usage_error({"--token", "same", "--observer-token", "same"}),
            "--token and --observer-token must differ: a client's role is told by its token");
  ScopedEnv observer("TUMBLE_OBSERVER_TOKEN", "same");
  EXPECT_EQ(usage_error({"--token", "same"}),
            "--token and --observer-token must differ: a client's role is told by its token");
}

TEST_F(ServerOptionsTest, OnlyAnObserverTokenIsAllowed) {
  const ServerOptions options = options_of({"--observer-token", "obs"});
  EXPECT_EQ(options.tokens.controller, "");
  EXPECT_EQ(options.tokens.observer, "obs");
}

TEST_F(ServerOptionsTest, EnvironmentStandsInForTokens) {
  ScopedEnv token("TUMBLE_TOKEN", "ctl-env");
  ScopedEnv observer("TUMBLE_OBSERVER_TOKEN", "obs-env");
  ServerOptions options = options_of({});
  EXPECT_EQ(options.tokens.controller, "ctl-env");
  EXPECT_EQ(options.tokens.observer, "obs-env");

  options = options_of({"--token", "ctl-flag", "--observer-token", "obs-flag"});
  EXPECT_EQ(options.tokens.controller, "ctl-flag");
  EXPECT_EQ(options.tokens.observer, "obs-flag");
}

TEST_F(ServerOptionsTest, HelpAndVersionExitZeroWithTextForStandardOutput) {
  ParsedServerOptions help = parse({"--help"});
  EXPECT_FALSE(help.options.has_value());
  EXPECT_EQ(help.exit_code, kExitSuccess);
  EXPECT_NE(help.text.find("tumbled: a networked rigid-body simulation server"), std::string::npos) << help.text;
  EXPECT_NE(help.text.find("--checkpoint-interval"), std::string::npos) << help.text;

  ParsedServerOptions version = parse({"--version"});
  EXPECT_FALSE(version.options.has_value());
  EXPECT_EQ(version.exit_code, kExitSuccess);
  EXPECT_EQ(version.text, std::string(kVersion) + "\n");
}

TEST_F(ServerOptionsTest, NatsFlagsParseWithTheirDefaults) {
  const ServerOptions options = options_of({"--nats", "nats://a:4222,tls://u:p@b:4443", "--world", "demo"});
  EXPECT_EQ(options.nats_urls, (std::vector<std::string>{"nats://a:4222", "tls://u:p@b:4443"}));
  EXPECT_EQ(options.world, "demo");
  ASSERT_EQ(options.nats_streams.size(), 1u);
  EXPECT_EQ(options.nats_streams[0].name, "q60");
  EXPECT_EQ(options.nats_streams[0].encoding, tumble::v1::POSE_ENCODING_QUANTIZED);
  EXPECT_DOUBLE_EQ(options.nats_key_interval_seconds, 1);
  EXPECT_DOUBLE_EQ(options.nats_rest_key_interval_seconds, 30);
  const ServerOptions many =
      options_of({"--nats", "nats://a:4222", "--world", "w", "--nats-stream", "f=full@30:all", "--nats-stream",
                  "d=delta@60", "--nats-key-interval", "0.5", "--listen", "none"});
  ASSERT_EQ(many.nats_streams.size(), 2u);
  EXPECT_EQ(many.nats_streams[1].encoding, tumble::v1::POSE_ENCODING_DELTA);
  EXPECT_DOUBLE_EQ(many.nats_key_interval_seconds, 0.5);
  EXPECT_FALSE(many.serve_tcp);
  // A key interval longer than the default rest interval carries it along.
  EXPECT_DOUBLE_EQ(options_of({"--nats", "nats://a:4222", "--world", "w", "--nats-key-interval", "60"})
                       .nats_rest_key_interval_seconds,
                   60);
  EXPECT_DOUBLE_EQ(options_of({"--nats", "nats://a:4222", "--world", "w", "--nats-rest-key-interval", "5"})
                       .nats_rest_key_interval_seconds,
                   5);
}

TEST_F(ServerOptionsTest, NatsStateCheckpointsEverySecondUnlessToldAndNeedsNoStateFile) {
  const ServerOptions options = options_of({"--nats", "nats://a:4222", "--world", "w", "--nats-state"});
  EXPECT_TRUE(options.nats_state);
  EXPECT_EQ(options.nats_bucket, "tumble_worlds");
  EXPECT_EQ(options.nats_replicas, 0);
  EXPECT_DOUBLE_EQ(options.checkpoint_interval_seconds, 1);
  const ServerOptions told =
      options_of({"--nats", "nats://a:4222", "--world", "w", "--nats-state", "--checkpoint-interval", "5",
                  "--nats-bucket", "lab_worlds", "--nats-replicas", "3", "--nats-state-reset"});
  EXPECT_DOUBLE_EQ(told.checkpoint_interval_seconds, 5);
  EXPECT_EQ(told.nats_bucket, "lab_worlds");
  EXPECT_EQ(told.nats_replicas, 3);
  EXPECT_TRUE(told.nats_state_reset);
  // --standby implies --nats-state, for every option that needs it.
  const ServerOptions standby =
      options_of({"--nats", "nats://a:4222", "--world", "w", "--standby", "--checkpoint-interval", "0.5"});
  EXPECT_TRUE(standby.nats_state);
  EXPECT_DOUBLE_EQ(standby.checkpoint_interval_seconds, 0.5);
  EXPECT_NE(usage_error({"--nats", "nats://a:4222", "--world", "w", "--nats-state", "--nats-bucket", "a.b"})
                .find("--nats-bucket: bucket name 'a.b' must be"),
            std::string::npos);
  EXPECT_NE(usage_error({"--nats", "nats://a:4222", "--world", "w", "--nats-state", "--state", "s"}).find("excludes"),
            std::string::npos);
  EXPECT_NE(usage_error({"--nats", "nats://a:4222", "--world", "w", "--nats-replicas", "3"}).find("--nats-state"),
            std::string::npos);
  EXPECT_NE(usage_error({"--nats", "nats://a:4222", "--world", "w", "--nats-state", "--nats-replicas", "7"})
                .find("--nats-replicas"),
            std::string::npos);
}

TEST_F(ServerOptionsTest, BadNatsValuesAreOneLineNamingTheFlag) {
  EXPECT_NE(usage_error({"--nats", "nats://a:4222", "--world", "a.b"}).find("--world"), std::string::npos);
  EXPECT_NE(usage_error({"--nats", "nats://a:4222", "--world", "a*"}).find("--world"), std::string::npos);
  EXPECT_NE(usage_error({"--nats", "nats://a:4222"}).find("--world"), std::string::npos);
  EXPECT_NE(usage_error({"--nats", "nats://a:4222", "--world", "w", "--nats-stream", "q=zip@5"}).find("--nats-stream"),
            std::string::npos);
  EXPECT_NE(usage_error(
                {"--nats", "nats://a:4222", "--world", "w", "--nats-stream", "q=full@5", "--nats-stream", "q=delta@5"})
                .find("two streams are named 'q'"),
            std::string::npos);
  EXPECT_NE(usage_error({"--nats", "nats://a:4222", "--world", "w", "--nats-creds", "/nonexistent/x.creds"})
                .find("--nats-creds"),
            std::string::npos);
  EXPECT_NE(usage_error({"--nats", "http://a:4222", "--world", "w"}).find("--nats"), std::string::npos);
  EXPECT_NE(usage_error({"--nats", "nats://a:4222", "--world", "w", "--nats-key-interval", "2",
                         "--nats-rest-key-interval", "1"})
                .find("--nats-rest-key-interval must be at least --nats-key-interval"),
            std::string::npos);
  EXPECT_NE(usage_error({"--listen", "none"}).find("--nats"), std::string::npos);
  EXPECT_NE(usage_error({"--world", "w"}).find("--nats"), std::string::npos);
}

}  // namespace
}  // namespace tumble::server
