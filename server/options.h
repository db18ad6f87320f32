// tumbled's command line, parsed into plain values.
//
//   tumbled [--listen HOST:PORT] [--port-file PATH] [--http HOST:PORT [--http-port-file PATH]
//           [--max-http-connections N] [--http-header-timeout S] [--http-allowed-hosts HOST,...]]
//           [--scene PATH] [--tick-rate HZ] [--max-bodies N] [--physics-threads N]
//           [--max-frame-bytes N] [--max-pending-bytes N] [--max-connections N] [--max-commands-per-second N]
//           [--max-errors-per-second N] [--handshake-timeout S] [--frame-timeout S]
//           [--max-undelivered-seconds S] [--token TOKEN] [--observer-token TOKEN]
//           [--state PATH [--checkpoint-interval S]] [--record PATH | --replay PATH]
//           [--realtime-priority N] [--keep-cpus-awake] [--log-level LEVEL]
//           [--nats URL[,URL...] --world NAME [--nats-stream NAME=ENCODING@HZ[:fields]]...
//            [--nats-key-interval S] [--nats-creds FILE] [--nats-sleep-events]]
//
// Every range and every rule between flags is checked here, so a usage
// error is reported before anything starts. Files are only named here:
// opening and judging them is startup's job (startup.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "nats/stream_spec.h"
#include "net/access.h"
#include "net/http_connection.h"
#include "net/session.h"
#include "sim/simulation.h"
#include "tumble/endpoint.h"
#include "wire/frame.h"

namespace tumble::server {

// tumbled's exit statuses: 0 after a clean stop (and after --help or
// --version), 1 when the world or the network cannot start or the world
// cannot be saved, 2 for a usage error.
inline constexpr int kExitSuccess = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;

// Every flag of tumbled, with its default.
struct ServerOptions {
  // Where clients reach the server.
  Endpoint listen = default_endpoint();  // --listen; port 0 picks a free one
  bool serve_tcp = true;                 // false after --listen none (then --nats is required)
  std::string port_file;                 // --port-file: the bound port is written here; empty: none
  std::optional<Endpoint> http;          // --http: the viewer's page and WebSocket clients; none: off
  std::string http_port_file;            // --http-port-file: the bound HTTP port; only with --http
  // The HTTP endpoint's own limits; each only with --http.
  std::size_t max_http_connections = net::HttpLimits{}.max_connections;  // 1 to 10^6
  double http_header_timeout_seconds = 10;                               // --http-header-timeout, s: 0.001 to 86400
  std::vector<std::string> http_allowed_hosts;  // --http-allowed-hosts; empty: the defaults (net/allowed_hosts.h)

  // The world.
  std::string scene_path;                                  // --scene: a JSON scene; empty: an empty world
  double tick_rate_hz = sim::SimConfig{}.tick_rate_hz;     // --tick-rate, Hz: 1 to 10000
  std::uint32_t max_bodies = sim::SimConfig{}.max_bodies;  // --max-bodies: 1 to 10^7
  int physics_threads = sim::SimConfig{}.physics_threads;  // --physics-threads, the sim thread included: 1 to 64

  // Limits on each client, and access.
  std::size_t max_frame_bytes = wire::kDefaultMaxFrameBytes;               // bytes: 64 to 2^30
  std::size_t max_pending_bytes = net::SessionLimits{}.max_pending_bytes;  // bytes: 4096 to 2^34
  std::size_t max_connections = 1024;                                      // clients at once: 1 to 10^6
  std::uint32_t max_commands_per_second = 1000;  // requests per second, and per burst: 1 to 10^9
  std::uint32_t max_errors_per_second = 100;     // Errors per second, and per burst, before a close: 1 to 10^9
  double handshake_timeout_seconds = 10;         // --handshake-timeout, s: 0.001 to 86400
  double frame_timeout_seconds = 10;             // --frame-timeout, s: 0.001 to 86400
  double max_undelivered_seconds = 10;           // s: 0.001 to 86400
  // --token (else $TUMBLE_TOKEN) and --observer-token (else
  // $TUMBLE_OBSERVER_TOKEN); a controller token never equals the observer's.
  net::AccessTokens tokens;

  // Persistence.
  std::string state_path;  // --state: resumed from when it exists, saved to on exit
  // --checkpoint-interval, s: 0.01 to 86400, with --state (default 0: off)
  // or --nats-state (default 1)
  double checkpoint_interval_seconds = 0;
  std::string record_path;  // --record: the journal to write; never with --replay
  std::string replay_path;  // --replay: the journal to replay

  // A world served over NATS (off without --nats).
  std::vector<std::string> nats_urls;          // --nats URL[,URL...]: nats:// or tls://, credentials may be in the URL
  std::string world;                           // --world: required with --nats (nats/stream_spec.h)
  std::vector<nats::StreamSpec> nats_streams;  // --nats-stream, repeatable; default q60=quantized@60
  double nats_key_interval_seconds = 1;        // --nats-key-interval, s: 0.01 to 3600
  double nats_rest_key_interval_seconds = 30;  // --nats-rest-key-interval, s: key interval to 3600
  std::string nats_creds_path;                 // --nats-creds: a .creds file, readable
  bool nats_sleep_events = false;              // --nats-sleep-events
  // The world's checkpoints in a JetStream bucket (nats/nats_state_store.h).
  bool nats_state = false;                    // --nats-state; never with --state
  std::string nats_bucket = "tumble_worlds";  // --nats-bucket: 1 to 64 of A-Z a-z 0-9 _ -
  int nats_replicas = 0;                      // --nats-replicas: 1 to 5; 0: by the cluster's size
  bool nats_state_reset = false;              // --nats-state-reset: a damaged value gives way to the scene
  // Leadership of the world among the servers that keep it (nats/world_lease.h).
  bool standby = false;              // --standby (implies --nats-state): take no lease nobody held before the timeout
  double lease_renew_seconds = 0.5;  // --lease-renew, s: 0.05 to 60
  double lease_timeout_seconds = 2;  // --lease-timeout, s: more than --lease-renew, at most 600

  // Scheduling and logging.
  int realtime_priority = 0;       // SCHED_FIFO priority, 1 to 99; 0: ordinary scheduling
  bool keep_cpus_awake = false;    // --keep-cpus-awake
  std::string log_level = "info";  // trace, debug, info, warn, error, critical or off
};

// What the command line came to: options to run with, or an exit.
struct ParsedServerOptions {
  std::optional<ServerOptions> options;
  // Without options: kExitSuccess after --help or --version, with `text`
  // for standard output; kExitUsage for a usage error, with `text` the
  // one-line reason (no "tumbled: " prefix, no newline).
  int exit_code = kExitSuccess;
  std::string text;
};

// Parses argv (argv[0] is the program). Reads $TUMBLE_TOKEN and
// $TUMBLE_OBSERVER_TOKEN for tokens not given. Never prints and never exits.
ParsedServerOptions parse_server_options(int argc, const char* const* argv);

}  // namespace tumble::server
