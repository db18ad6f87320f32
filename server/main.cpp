// tumbled: the tumble simulation server. Flags -> config -> run.
#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>

#include <CLI/CLI.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "cpu_keep_awake.h"
#include "net/asio.h"
#include "net/server.h"
#include "realtime.h"
#include "sim/journal.h"
#include "sim/replay.h"
#include "sim/request_check.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"
#include "sim/state_file.h"
#include "sim/state_saver.h"
#include "tumble/version.h"

namespace {

using tumble::kVersion;

// HOST:PORT, with the host in brackets for IPv6 ("[::1]:7400").
bool split_host_port(const std::string& text, std::string& host, std::uint16_t& port) {
  const std::size_t colon = text.rfind(':');
  if (colon == std::string::npos || colon + 1 == text.size()) return false;
  host = text.substr(0, colon);
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
  try {
    std::size_t used = 0;
    const unsigned long value = std::stoul(text.substr(colon + 1), &used);
    if (used != text.size() - colon - 1 || value > 65535) return false;
    port = static_cast<std::uint16_t>(value);
  } catch (const std::exception&) {
    return false;
  }
  return !host.empty();
}

// Writes `port` to `path`, through a temporary name and a rename, so a
// reader never sees half a number.
void write_port_file(const std::string& path, std::uint16_t port) {
  const std::string temporary = path + ".tmp";
  std::ofstream(temporary) << port << "\n";
  std::rename(temporary.c_str(), path.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"tumbled: a networked rigid-body simulation server"};
  std::string listen = "127.0.0.1:7400";
  std::string scene_path;
  std::string port_file;
  double tick_rate = 240;
  std::string log_level = "info";
  std::size_t max_frame_bytes = tumble::wire::kDefaultMaxFrameBytes;
  app.add_option("--listen", listen, "Address to listen on, HOST:PORT (port 0 picks a free one)")
      ->capture_default_str();
  app.add_option("--scene", scene_path, "Scene file (JSON) to load; an empty world without one");
  app.add_option("--tick-rate", tick_rate, "Simulation steps per second, 1 to 10000")
      ->capture_default_str()
      ->check(CLI::Range(tumble::sim::kMinTickRateHz, tumble::sim::kMaxTickRateHz));
  std::uint32_t max_bodies = tumble::sim::SimConfig{}.max_bodies;
  app.add_option("--max-bodies", max_bodies, "Most bodies the world may hold; SpawnBody beyond it is refused")
      ->capture_default_str()
      ->check(CLI::Range(std::uint32_t{1}, std::uint32_t{10000000}));
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error or off")
      ->capture_default_str()
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "critical", "off"}));
  app.add_option("--max-frame-bytes", max_frame_bytes, "Largest message a client may send")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t{64}, std::size_t{1} << 30));
  app.add_option("--port-file", port_file, "Write the bound port to this file once listening");
  // The HTTP endpoint: the viewer's page and WebSocket clients.
  std::string http;
  std::string http_port_file;
  auto* http_option = app.add_option("--http", http,
                                     "Serve the viewer's page, and WebSocket clients at /ws, on HOST:PORT (port 0 "
                                     "picks a free one); off by default. No TLS: use loopback or a proxy");
  app.add_option("--http-port-file", http_port_file,
                 "Write the bound HTTP port to this file once listening (before --port-file is written)")
      ->needs(http_option);

  // Shared-server safety: limits on each client and access tokens.
  std::size_t max_connections = 1024;
  std::uint32_t max_commands_per_second = 1000;
  double handshake_timeout = 10;
  double max_undelivered_seconds = 10;
  std::size_t max_pending_bytes = tumble::net::SessionLimits{}.max_pending_bytes;
  tumble::net::AccessTokens tokens;
  app.add_option("--max-connections", max_connections, "Clients served at once; more are refused")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t{1}, std::size_t{1000000}));
  app.add_option("--max-commands-per-second", max_commands_per_second,
                 "Requests per second a client may send (in bursts of as many); the excess gets RATE_LIMITED")
      ->capture_default_str()
      ->check(CLI::Range(std::uint32_t{1}, std::uint32_t{1000000000}));
  app.add_option("--handshake-timeout", handshake_timeout, "Seconds a new connection has to send Hello")
      ->capture_default_str()
      ->check(CLI::Range(0.001, 86400.0));
  app.add_option("--max-undelivered-seconds", max_undelivered_seconds,
                 "Seconds a reply or frame may wait for a client that does not read before it is disconnected")
      ->capture_default_str()
      ->check(CLI::Range(0.001, 86400.0));
  app.add_option("--max-pending-bytes", max_pending_bytes,
                 "Bytes of unsent replies a client may leave unread before it is disconnected")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t{4096}, std::size_t{1} << 34));
  app.add_option("--token", tokens.controller,
                 "Token that makes a client a controller; prefer $TUMBLE_TOKEN (command lines are visible)")
      ->envname("TUMBLE_TOKEN");
  app.add_option("--observer-token", tokens.observer,
                 "Token that makes a client an observer (reads only); or $TUMBLE_OBSERVER_TOKEN")
      ->envname("TUMBLE_OBSERVER_TOKEN");
  // Persistence: the world across restarts, and runs that can be replayed.
  std::string state_path;
  double checkpoint_interval = 0;
  std::string record_path;
  std::string replay_path;
  app.add_option("--state", state_path,
                 "State file: the world is saved to it on SIGTERM/SIGINT and resumed from it at start when it "
                 "exists (then --scene is only used when it does not)");
  auto* checkpoint_option =
      app.add_option("--checkpoint-interval", checkpoint_interval,
                     "Also save the state file every this many seconds, so a crash loses at most that much")
          ->check(CLI::Range(0.01, 86400.0));
  auto* record_option =
      app.add_option("--record", record_path, "Journal every command with its tick to this file, for --replay");
  auto* replay_option = app.add_option("--replay", replay_path,
                                       "Replay a journal made by --record (from its start; --scene must be the "
                                       "recorded scene when given), then serve the world paused where it ended");
  int physics_threads = 1;
  app.add_option("--physics-threads", physics_threads,
                 "Threads that run the narrowphase and solve the world's contact groups, the sim thread included; "
                 "results are the same for any count. More help a world of many separate piles on a machine "
                 "with cores to spare")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  // Scheduling: on a shared machine, keeps ticks and frames on time.
  int realtime_priority = 0;
  app.add_option("--realtime-priority", realtime_priority,
                 "Run the sim and network threads under SCHED_FIFO at this priority (1 to 99), ahead of every "
                 "ordinary process, so other work on the machine cannot delay a tick or a frame; needs "
                 "CAP_SYS_NICE or ulimit -r. 0: ordinary scheduling")
      ->capture_default_str()
      ->check(CLI::Range(0, tumble::kMaxRealtimePriority));
  bool keep_cpus_awake = false;
  app.add_flag("--keep-cpus-awake", keep_cpus_awake,
               "Keep every CPU of tumbled's affinity mask from halting: a thread on each spins under SCHED_IDLE, "
               "yielding to any other. On a virtual machine a halted CPU can resume milliseconds late; the CPUs "
               "then read as fully busy");
  checkpoint_option->needs("--state");
  record_option->excludes(replay_option);
  app.set_version_flag("--version", kVersion);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    // --help and --version end here with 0; a usage error is 2, like tumble's.
    return app.exit(error) == 0 ? 0 : 2;
  }

  spdlog::set_level(spdlog::level::from_str(log_level));
  spdlog::set_pattern("%Y-%m-%dT%H:%M:%S.%e %^%-5l%$ [%n] %v");
  auto log = spdlog::stderr_color_mt("tumbled");

  std::string host;
  std::uint16_t port = 0;
  if (!split_host_port(listen, host, port)) {
    log->error("--listen: '{}' is not HOST:PORT", listen);
    return 2;
  }
  std::string http_host;
  std::uint16_t http_port = 0;
  if (!http.empty() && !split_host_port(http, http_host, http_port)) {
    log->error("--http: '{}' is not HOST:PORT", http);
    return 2;
  }
  if (!tokens.controller.empty() && tokens.controller == tokens.observer) {
    log->error("--token and --observer-token must differ: a client's role is told by its token");
    return 2;
  }
  if (!tokens.required()) {
    log->warn("no --token or --observer-token (nor TUMBLE_TOKEN, TUMBLE_OBSERVER_TOKEN): "
              "every client that connects may control the world");
  } else if (tokens.controller.empty()) {
    log->info("only an observer token is set: clients may watch the world but none may control it");
  }

  tumble::sim::SimConfig sim_config;
  sim_config.tick_rate_hz = tick_rate;
  sim_config.max_bodies = max_bodies;
  sim_config.physics_threads = physics_threads;

  // Where the world starts: a journal's start, the state file, or the scene.
  tumble::v1::Scene scene;
  if (!scene_path.empty()) {
    if (auto status = tumble::sim::load_scene_file(scene_path, &scene); !status.ok()) {
      log->error("cannot load the scene: {}", status.message());
      return 1;
    }
  } else {
    scene.mutable_gravity()->set_y(-9.81);
  }
  tumble::sim::JournalReader replay;
  tumble::v1::WorldState saved;
  bool resume = false;
  std::string origin = scene_path.empty() ? std::string("no scene") : scene_path;
  if (!replay_path.empty()) {
    if (auto status = replay.open(replay_path); !status.ok()) {
      log->error("cannot replay: {}", status.message());
      return 1;
    }
    const tumble::v1::JournalHeader& header = replay.header();
    if (header.has_state()) {
      saved = header.state();
      resume = true;
    } else {
      if (!scene_path.empty() && header.scene().SerializeAsString() != scene.SerializeAsString()) {
        log->error("cannot replay {}: it was recorded with another scene than {}", replay_path, scene_path);
        return 1;
      }
      scene = header.scene();
      sim_config.tick_rate_hz = header.tick_rate_hz();
    }
    origin = "the start of " + replay_path;
  } else if (!state_path.empty()) {
    bool exists = false;
    if (auto status = tumble::sim::read_state_file(state_path, &saved, &exists); !status.ok()) {
      log->error("cannot resume: {}", status.message());
      return 1;
    }
    resume = exists;
    if (exists) origin = state_path;
  }
  if (!resume && scene_path.empty() && replay_path.empty()) log->warn("no --scene given: starting with an empty world");

  // Declared before the sim, which writes its last entry when it stops:
  // the sim is destroyed (and stopped) first.
  tumble::sim::JournalWriter journal;
  std::unique_ptr<tumble::sim::Simulation> sim;
  if (resume) {
    if (auto status = tumble::sim::Simulation::create_from_state(saved, sim_config, &sim); !status.ok()) {
      log->error("cannot resume from {}: {}", origin, status.message());
      return 1;
    }
  } else if (auto status = tumble::sim::Simulation::create(scene, sim_config, &sim); !status.ok()) {
    log->error("invalid scene {}: {}", scene_path, status.message());
    return 1;
  }
  log->info("tumbled {}: {} bodies from {}, at tick {}{}", kVersion, sim->body_count(), origin, sim->tick(),
            sim->paused() ? ", paused" : "");

  if (!replay_path.empty()) {
    tumble::sim::ReplaySummary summary;
    if (auto status = tumble::sim::replay_journal(replay, *sim, &summary); !status.ok()) {
      log->error("replay of {} failed after {} commands: {}", replay_path, summary.commands, status.message());
      return 1;
    }
    log->info("replayed {} commands of {} to tick {}{}; paused there", summary.commands, replay_path,
              summary.end_tick, summary.complete ? "" : " (the journal was cut short: its run was killed)");
  }

  if (!record_path.empty()) {
    tumble::v1::JournalHeader header;
    header.set_format_version(tumble::sim::kJournalFormat);
    header.set_server_version(kVersion);
    header.set_tick_rate_hz(sim->tick_rate_hz());
    if (resume) {
      sim->capture(header.mutable_state());
    } else {
      *header.mutable_scene() = scene;
    }
    if (auto status = journal.open(record_path, header); !status.ok()) {
      log->error("cannot record: {}", status.message());
      return 1;
    }
    sim->set_journal(&journal);
    log->info("recording commands to {}", record_path);
  }

  std::unique_ptr<tumble::sim::StateSaver> saver;
  if (!state_path.empty() && checkpoint_interval > 0) {
    saver = std::make_unique<tumble::sim::StateSaver>(state_path);
    sim->set_checkpoints(std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                             std::chrono::duration<double>(checkpoint_interval)),
                         [&saver](std::shared_ptr<const tumble::v1::WorldState> state) { saver->offer(std::move(state)); });
    log->info("checkpointing the world to {} every {} s", state_path, checkpoint_interval);
  }

  // The spinners start before this thread changes its scheduling, so none
  // of them ever spins under what the sim and I/O threads get.
  tumble::CpuKeepAwake keep_awake;
  if (keep_cpus_awake) {
    if (auto status = keep_awake.start(); !status.ok()) {
      log->error("--keep-cpus-awake: {}", status.message());
      return 1;
    }
    log->info("keeping {} CPUs awake (a SCHED_IDLE spinner on each)", keep_awake.spinner_count());
  }

  // This thread becomes the I/O thread (io.run() below); the sim thread,
  // started after it, inherits its scheduling: a short slice of the fair
  // scheduler, or SCHED_FIFO. The checkpoint writer, started above, keeps
  // ordinary scheduling: it writes files.
  if (auto status = tumble::request_short_slice(); !status.ok()) {
    log->warn("{}; ticks may start late on a busy machine", status.message());
  }
  if (realtime_priority > 0) {
    if (auto status = tumble::enter_realtime(realtime_priority); !status.ok()) {
      log->error("--realtime-priority {}: {}", realtime_priority, status.message());
      return 1;
    }
    log->info("sim and network threads run under SCHED_FIFO at priority {}", realtime_priority);
  }

  boost::asio::io_context io;
  tumble::net::ServerConfig server_config;
  server_config.host = host;
  server_config.port = port;
  server_config.limits.max_frame_bytes = max_frame_bytes;
  server_config.limits.max_pending_bytes = max_pending_bytes;
  server_config.limits.commands_per_second = max_commands_per_second;
  server_config.limits.command_burst = max_commands_per_second;
  server_config.limits.handshake_timeout = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(handshake_timeout));
  server_config.limits.max_undelivered = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(max_undelivered_seconds));
  server_config.max_connections = max_connections;
  server_config.access = tokens;
  server_config.server_version = kVersion;
  server_config.serve_http = !http.empty();
  server_config.http_host = http_host;
  server_config.http_port = http_port;
  tumble::net::Server server(io, *sim, server_config);
  // The handlers are in place before anyone can learn the port: a SIGINT
  // or SIGTERM sent as soon as the port file appears stops the server
  // cleanly (saving the world) instead of killing it. One that comes
  // before io.run() waits in the signal set until then.
  boost::asio::signal_set signals(io, SIGINT, SIGTERM);
  signals.async_wait([&](const boost::system::error_code& error, int signal) {
    if (error) return;
    log->info("received {}: shutting down", signal == SIGINT ? "SIGINT" : "SIGTERM");
    server.stop();
    io.stop();
  });
  if (auto status = server.start(); !status.ok()) {
    log->error("{}", status.message());
    return 1;
  }
  // The HTTP port first: whoever waits for --port-file then finds both.
  if (!http_port_file.empty()) write_port_file(http_port_file, server.http_port());
  if (!port_file.empty()) write_port_file(port_file, server.port());

  sim->start();
  io.run();
  sim->stop();
  if (saver) saver->stop();  // a late checkpoint must not land after the final save
  log->info("stopped at tick {} ({} overruns)", sim->tick(), sim->overruns());
  if (!journal.status().ok()) log->error("the journal is incomplete: {}", journal.status().message());
  if (!state_path.empty()) {
    tumble::v1::WorldState state;
    sim->capture(&state);
    if (auto status = tumble::sim::write_state_file(state_path, state); !status.ok()) {
      log->error("the world was not saved: {}", status.message());
      return 1;
    }
    log->info("saved the world at tick {} to {}", state.tick(), state_path);
  }
  return 0;
}
