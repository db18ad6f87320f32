#include "options.h"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <utility>

#include <CLI/CLI.hpp>

#include "realtime.h"
#include "sim/request_check.h"
#include "sim/string_limits.h"
#include "tumble/version.h"

namespace tumble::server {
namespace {

// A CLI11 check of --listen and --http: the empty string when `text` is an
// address to listen on, else why not.
std::string check_listen_address(const std::string& text) { return parse_endpoint(text, PortZero::allowed).error; }

Endpoint listen_address(const std::string& text) { return *parse_endpoint(text, PortZero::allowed).endpoint; }

// CLI11's messages, folded onto one line.
std::string one_line(std::string text) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

ParsedServerOptions usage_error(std::string reason) {
  ParsedServerOptions parsed;
  parsed.exit_code = kExitUsage;
  parsed.text = std::move(reason);
  return parsed;
}

}  // namespace

ParsedServerOptions parse_server_options(int argc, const char* const* argv) {
  CLI::App app{"tumbled: a networked rigid-body simulation server"};
  app.name("tumbled");
  ServerOptions options;

  std::string listen = to_string(options.listen);
  app.add_option("--listen", listen,
                 "Address to listen on, HOST:PORT (port 0 picks a free one), or none: no TCP or HTTP listener "
                 "(then --nats is required)")
      ->capture_default_str()
      ->check(CLI::Validator(
          [](std::string& text) { return text == "none" ? std::string() : check_listen_address(text); }, "ADDRESS"));
  app.add_option("--scene", options.scene_path, "Scene file (JSON) to load; an empty world without one");
  app.add_option("--tick-rate", options.tick_rate_hz, "Simulation steps per second, 1 to 10000")
      ->capture_default_str()
      ->check(CLI::Range(sim::kMinTickRateHz, sim::kMaxTickRateHz));
  app.add_option("--max-bodies", options.max_bodies, "Most bodies the world may hold; SpawnBody beyond it is refused")
      ->capture_default_str()
      ->check(CLI::Range(std::uint32_t{1}, std::uint32_t{10000000}));
  app.add_option("--log-level", options.log_level, "trace, debug, info, warn, error or off")
      ->capture_default_str()
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "critical", "off"}));
  app.add_option("--max-frame-bytes", options.max_frame_bytes, "Largest message a client may send")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t{64}, std::size_t{1} << 30));
  app.add_option("--port-file", options.port_file, "Write the bound port to this file once listening");
  // The HTTP endpoint: the viewer's page and WebSocket clients.
  std::string http;
  auto* http_option = app.add_option("--http", http,
                                     "Serve the viewer's page, and WebSocket clients at /ws, on HOST:PORT (port 0 "
                                     "picks a free one); off by default. No TLS: use loopback or a proxy")
                          ->check(check_listen_address);
  app.add_option("--http-port-file", options.http_port_file,
                 "Write the bound HTTP port to this file once listening (before --port-file is written)")
      ->needs(http_option);
  app.add_option("--max-http-connections", options.max_http_connections,
                 "HTTP connections served at once, apart from --max-connections; more are closed")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t{1}, std::size_t{1000000}))
      ->needs(http_option);
  app.add_option("--http-header-timeout", options.http_header_timeout_seconds,
                 "Seconds a request's header may take to arrive whole (else 408), and an idle connection may stay")
      ->capture_default_str()
      ->check(CLI::Range(0.001, 86400.0))
      ->needs(http_option);
  app.add_option("--http-allowed-hosts", options.http_allowed_hosts,
                 "Host header values served, comma-separated: NAME:PORT, NAME (any port) or * (any); others get "
                 "421. Default: the --http address, localhost, 127.0.0.1 and [::1], with its port")
      ->delimiter(',')
      ->check(CLI::Validator(
          [](std::string& entry) {
            // A URL is the likely mistake: "http://viewer.example:8080".
            return entry.find_first_of("/ \t") == std::string::npos
                       ? std::string()
                       : "'" + entry + "' is not a host name: give NAME, NAME:PORT or *";
          },
          "HOST"))
      ->needs(http_option);

  // Shared-server safety: limits on each client and access tokens.
  app.add_option("--max-connections", options.max_connections, "Clients served at once; more are refused")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t{1}, std::size_t{1000000}));
  app.add_option("--max-commands-per-second", options.max_commands_per_second,
                 "Requests per second a client may send (in bursts of as many); the excess gets RATE_LIMITED")
      ->capture_default_str()
      ->check(CLI::Range(std::uint32_t{1}, std::uint32_t{1000000000}));
  app.add_option("--max-errors-per-second", options.max_errors_per_second,
                 "Errors per second (in bursts of as many) a client's requests may draw; beyond, one "
                 "RESOURCE_EXHAUSTED and the connection is closed")
      ->capture_default_str()
      ->check(CLI::Range(std::uint32_t{1}, std::uint32_t{1000000000}));
  app.add_option("--handshake-timeout", options.handshake_timeout_seconds, "Seconds a new connection has to send Hello")
      ->capture_default_str()
      ->check(CLI::Range(0.001, 86400.0));
  app.add_option("--frame-timeout", options.frame_timeout_seconds,
                 "Seconds a frame may take to arrive whole once its first byte has (else MALFORMED_FRAME and a "
                 "close); a client idle between frames is not affected")
      ->capture_default_str()
      ->check(CLI::Range(0.001, 86400.0));
  app.add_option("--max-undelivered-seconds", options.max_undelivered_seconds,
                 "Seconds a reply or frame may wait for a client that does not read before it is disconnected")
      ->capture_default_str()
      ->check(CLI::Range(0.001, 86400.0));
  app.add_option("--max-pending-bytes", options.max_pending_bytes,
                 "Bytes of unsent replies a client may leave unread before it is disconnected")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t{4096}, std::size_t{1} << 34));
  app.add_option("--token", options.tokens.controller,
                 "Token that makes a client a controller; prefer $TUMBLE_TOKEN (command lines are visible)")
      ->envname("TUMBLE_TOKEN");
  app.add_option("--observer-token", options.tokens.observer,
                 "Token that makes a client an observer (reads only); or $TUMBLE_OBSERVER_TOKEN")
      ->envname("TUMBLE_OBSERVER_TOKEN");

  // Persistence: the world across restarts, and runs that can be replayed.
  app.add_option("--state", options.state_path,
                 "State file: the world is saved to it on SIGTERM/SIGINT and resumed from it at start when it "
                 "exists (then --scene is only used when it does not)");
  auto* checkpoint_option =
      app.add_option("--checkpoint-interval", options.checkpoint_interval_seconds,
                     "Also save the state file every this many seconds, so a crash loses at most that much")
          ->check(CLI::Range(0.01, 86400.0));
  auto* record_option =
      app.add_option("--record", options.record_path, "Journal every command with its tick to this file, for --replay");
  auto* replay_option = app.add_option("--replay", options.replay_path,
                                       "Replay a journal made by --record (from its start; --scene must be the "
                                       "recorded scene when given), then serve the world paused where it ended");
  app.add_option("--physics-threads", options.physics_threads,
                 "Threads that run the narrowphase and solve the world's contact groups, the sim thread included; "
                 "results are the same for any count. More help a world of many separate piles on a machine "
                 "with cores to spare")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));

  // Scheduling: on a shared machine, keeps ticks and frames on time.
  app.add_option("--realtime-priority", options.realtime_priority,
                 "Run the sim and network threads under SCHED_FIFO at this priority (1 to 99), ahead of every "
                 "ordinary process, so other work on the machine cannot delay a tick or a frame; needs "
                 "CAP_SYS_NICE or ulimit -r. 0: ordinary scheduling")
      ->capture_default_str()
      ->check(CLI::Range(0, kMaxRealtimePriority));
  app.add_flag("--keep-cpus-awake", options.keep_cpus_awake,
               "Keep every CPU of tumbled's affinity mask from halting: a thread on each spins under SCHED_IDLE, "
               "yielding to any other. On a virtual machine a halted CPU can resume milliseconds late; the CPUs "
               "then read as fully busy");
  // A world served over NATS.
  std::vector<std::string> nats_stream_specs;
  auto* nats_option = app.add_option("--nats", options.nats_urls,
                                     "Serve the world over NATS too: server URLs, comma-separated (nats:// or tls://; "
                                     "user:password@ or token@ in the URL); reconnects on its own")
                          ->delimiter(',');
  auto* world_option =
      app.add_option("--world", options.world,
                     "The world's name on NATS (subjects tumble.v1.NAME.*): 1 to 64 of A-Z a-z 0-9 _ -")
          ->needs(nats_option);
  nats_option->needs(world_option);
  app.add_option("--nats-stream", nats_stream_specs,
                 "A pose stream of every body on tumble.v1.WORLD.poses.NAME: NAME=ENCODING@HZ[:fields], ENCODING "
                 "full, quantized or delta, fields pose (default) or all; repeatable. Default q60=quantized@60")
      ->needs(nats_option);
  app.add_option("--nats-key-interval", options.nats_key_interval_seconds,
                 "Seconds of sim time between key frames of a delta stream over NATS")
      ->capture_default_str()
      ->check(CLI::Range(0.01, 3600.0))
      ->needs(nats_option);
  auto* rest_key_interval_option =
      app.add_option("--nats-rest-key-interval", options.nats_rest_key_interval_seconds,
                     "Seconds of sim time between key frames of a delta stream over NATS while nothing moves (a "
                     "reader that joins then asks for one); at least --nats-key-interval")
          ->capture_default_str()
          ->check(CLI::Range(0.01, 3600.0))
          ->needs(nats_option);
  app.add_option("--nats-creds", options.nats_creds_path, "A NATS .creds file (JWT and NKey seed) to connect with")
      ->needs(nats_option);
  auto* nats_state_option =
      app.add_flag("--nats-state", options.nats_state,
                   "Keep the world's checkpoints in a JetStream key-value bucket under the world's name, every "
                   "--checkpoint-interval (default 1 s here) and on SIGTERM/SIGINT, and resume from it at start "
                   "(--scene only seeds a world the bucket has not)")
          ->needs(nats_option);
  auto* bucket_option =
      app.add_option("--nats-bucket", options.nats_bucket, "The JetStream key-value bucket of --nats-state")
          ->capture_default_str();
  auto* replicas_option = app.add_option("--nats-replicas", options.nats_replicas,
                                         "Replicas of the bucket when tumbled makes it (1 to 5; default 3 on a "
                                         "cluster of three servers or more, else 1)")
                              ->check(CLI::Range(1, 5));
  auto* reset_option =
      app.add_flag("--nats-state-reset", options.nats_state_reset,
                   "Start from --scene when the bucket's value for the world is damaged or not a world (it is "
                   "replaced at the first checkpoint); without it tumbled refuses to start");
  app.add_flag("--standby", options.standby,
               "With --nats-state (implied): start as the world's standby, taking the lease only once it has gone "
               "unrenewed for --lease-timeout (a lease nobody held included)")
      ->needs(nats_option);
  auto* renew_option = app.add_option("--lease-renew", options.lease_renew_seconds,
                                      "Seconds between renewals of the world's lease by its leader (--nats-state)")
                           ->capture_default_str()
                           ->check(CLI::Range(0.05, 60.0));
  auto* timeout_option = app.add_option("--lease-timeout", options.lease_timeout_seconds,
                                        "Seconds a lease may go unrenewed before a standby takes it; the leader stops "
                                        "--lease-timeout minus --lease-renew after its last renewal that was taken")
                             ->capture_default_str()
                             ->check(CLI::Range(0.1, 600.0));
  app.add_flag("--nats-sleep-events", options.nats_sleep_events,
               "Also publish bodies falling asleep and waking on tumble.v1.WORLD.events (a scan of the bodies "
               "after every step)")
      ->needs(nats_option);
  nats_state_option->excludes("--state");
  record_option->excludes(replay_option);
  app.set_version_flag("--version", kVersion);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    std::ostringstream out;
    std::ostringstream err;
    // 0 after --help and --version, which CLI11 reports by throwing.
    if (app.exit(error, out, err) == kExitSuccess) {
      ParsedServerOptions parsed;
      parsed.text = out.str();
      return parsed;
    }
    return usage_error(one_line(error.what()));
  }

  // A longer token could never be matched: a Hello's is refused beyond the limit.
  for (const auto& [flag, token] :
       {std::pair{"--token", &options.tokens.controller}, std::pair{"--observer-token", &options.tokens.observer}}) {
    if (auto status = sim::check_text_length(*token, flag, sim::kMaxTokenBytes); !status.ok()) {
      return usage_error(status.message());
    }
  }
  if (!options.tokens.controller.empty() && options.tokens.controller == options.tokens.observer) {
    return usage_error("--token and --observer-token must differ: a client's role is told by its token");
  }
  if (options.standby) options.nats_state = true;  // before anything that asks for --nats-state
  if (checkpoint_option->count() > 0 && options.state_path.empty() && !options.nats_state) {
    return usage_error("--checkpoint-interval needs --state or --nats-state: somewhere to write the checkpoints");
  }
  if (listen == "none") {
    options.serve_tcp = false;
    if (options.nats_urls.empty()) return usage_error("--listen none needs --nats: the world would have no clients");
    if (http_option->count() > 0) return usage_error("--listen none turns every listener off; --http cannot be given");
  } else {
    options.listen = listen_address(listen);
  }
  if (http_option->count() > 0) options.http = listen_address(http);
  for (const CLI::Option* option : {bucket_option, replicas_option, reset_option, renew_option, timeout_option}) {
    if (option->count() > 0 && !options.nats_state) {
      return usage_error(option->get_name() + " needs --nats-state (or --standby)");
    }
  }
  if (!options.nats_urls.empty()) {
    if (auto problem = nats::check_world_name(options.world)) return usage_error(*problem);
    for (const std::string& url : options.nats_urls) {
      if (url.rfind("nats://", 0) != 0 && url.rfind("tls://", 0) != 0) {
        return usage_error("--nats: '" + url.substr(0, 120) + "' is not a nats:// or tls:// URL");
      }
    }
    if (nats_stream_specs.empty()) nats_stream_specs.emplace_back(nats::kDefaultStreamSpec);
    for (const std::string& text : nats_stream_specs) {
      auto spec = nats::parse_stream_spec(text);
      if (auto* problem = std::get_if<std::string>(&spec)) return usage_error(*problem);
      auto& stream = std::get<nats::StreamSpec>(spec);
      for (const nats::StreamSpec& other : options.nats_streams) {
        if (other.name == stream.name) return usage_error("--nats-stream: two streams are named '" + stream.name + "'");
      }
      options.nats_streams.push_back(std::move(stream));
    }
    if (rest_key_interval_option->count() == 0) {
      options.nats_rest_key_interval_seconds =
          std::max(options.nats_rest_key_interval_seconds, options.nats_key_interval_seconds);
    } else if (options.nats_rest_key_interval_seconds < options.nats_key_interval_seconds) {
      return usage_error(
          "--nats-rest-key-interval must be at least --nats-key-interval: at rest key frames come "
          "less often, not more");
    }
    if (options.lease_timeout_seconds <= options.lease_renew_seconds) {
      return usage_error("--lease-timeout must be longer than --lease-renew");
    }
    if (options.nats_state && !options.state_path.empty()) {
      return usage_error(
          "--nats-state (and --standby) keep the world in the NATS cluster, --state in a file: give one");
    }
    if (options.nats_state) {
      if (auto problem = nats::check_bucket_name(options.nats_bucket)) return usage_error(*problem);
      if (checkpoint_option->count() == 0) options.checkpoint_interval_seconds = 1;
    }
    if (!options.nats_creds_path.empty() && !std::ifstream(options.nats_creds_path)) {
      return usage_error("--nats-creds: cannot read '" + options.nats_creds_path + "'");
    }
  }
  ParsedServerOptions parsed;
  parsed.options = std::move(options);
  return parsed;
}

}  // namespace tumble::server
