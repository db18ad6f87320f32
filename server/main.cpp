// tumbled: the tumble simulation server. Options -> a ready world -> run
// until SIGINT or SIGTERM -> save the world.
#include <linux/close_range.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "cpu_keep_awake.h"
#include "nats/nats_link.h"
#include "nats/nats_state_store.h"
#include "nats/nats_world.h"
#include "nats/stream_spec.h"
#include "nats/world_lease.h"
#include "net/asio.h"
#include "net/server.h"
#include "options.h"
#include "realtime.h"
#include "sim/log_text.h"
#include "sim/state_file.h"
#include "startup.h"
#include "tumble/v1/world_info.pb.h"
#include "tumble/version.h"

namespace {

using tumble::server::kExitFailure;
using tumble::server::kExitSuccess;
using tumble::server::ServerOptions;

// Writes `port` to `path`, through a temporary name and a rename, so a
// reader never sees half a number.
void write_port_file(const std::string& path, std::uint16_t port) {
  const std::string temporary = path + ".tmp";
  std::ofstream(temporary) << port << "\n";
  std::rename(temporary.c_str(), path.c_str());
}

std::chrono::steady_clock::duration from_seconds(double seconds) {
  return std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(seconds));
}

// The network front's settings from the options.
tumble::net::ServerConfig server_config(const ServerOptions& options) {
  tumble::net::ServerConfig config;
  config.host = options.listen.host;
  config.port = options.listen.port;
  config.limits.max_frame_bytes = options.max_frame_bytes;
  config.limits.max_pending_bytes = options.max_pending_bytes;
  config.limits.commands_per_second = options.max_commands_per_second;
  config.limits.command_burst = options.max_commands_per_second;
  config.limits.handshake_timeout = from_seconds(options.handshake_timeout_seconds);
  config.limits.max_undelivered = from_seconds(options.max_undelivered_seconds);
  config.limits.frame_timeout = from_seconds(options.frame_timeout_seconds);
  config.limits.errors_per_second = options.max_errors_per_second;
  config.limits.error_burst = options.max_errors_per_second;
  config.max_connections = options.max_connections;
  config.access = options.tokens;
  config.server_version = tumble::kVersion;
  config.serve_http = options.http.has_value();
  if (options.http) {
    config.http_host = options.http->host;
    config.http_port = options.http->port;
  }
  config.http_limits.max_connections = options.max_http_connections;
  config.http_limits.header_timeout = from_seconds(options.http_header_timeout_seconds);
  config.http_limits.allowed_hosts = options.http_allowed_hosts;
  return config;
}

// Says who may do what when no token, or only an observer's, is set.
void log_access(const tumble::net::AccessTokens& tokens, spdlog::logger& log) {
  if (!tokens.required()) {
    log.warn(
        "no --token or --observer-token (nor TUMBLE_TOKEN, TUMBLE_OBSERVER_TOKEN): "
        "every client that connects may control the world");
  } else if (tokens.controller.empty()) {
    log.info("only an observer token is set: clients may watch the world but none may control it");
  }
}

// A leader that lost its world's lease becomes a standby by starting over
// as one: the same program and arguments, with --standby. Replacing the
// process ends every thread at once, so nothing of the old world is
// stepped or published after this; every descriptor is closed on the way
// (marked close-on-exec), so the listeners and the NATS connection go too.
[[noreturn]] void restart_as_standby(int argc, char** argv) {
  std::vector<char*> args(argv, argv + argc);
  bool standby = false;
  for (char* arg : args) standby = standby || std::strcmp(arg, "--standby") == 0;
  static char kStandby[] = "--standby";
  if (!standby) args.push_back(kStandby);
  args.push_back(nullptr);
  std::fflush(nullptr);
  ::syscall(SYS_close_range, 3U, ~0U, CLOSE_RANGE_CLOEXEC);
  ::execv("/proc/self/exe", args.data());
  std::_Exit(kExitFailure);  // could not start again: a supervisor restarts tumbled
}

// Closes a NATS link, if there is one by then, when it goes out of scope.
class LinkCloser {
 public:
  explicit LinkCloser(const std::unique_ptr<tumble::nats::NatsLink>& link) : link_(link) {}
  ~LinkCloser() {
    if (link_) link_->close();
  }
  LinkCloser(const LinkCloser&) = delete;
  LinkCloser& operator=(const LinkCloser&) = delete;

 private:
  const std::unique_ptr<tumble::nats::NatsLink>& link_;
};

}  // namespace

int main(int argc, char** argv) {
  const tumble::server::ParsedServerOptions parsed = tumble::server::parse_server_options(argc, argv);
  if (!parsed.options) {
    if (parsed.exit_code == kExitSuccess) {
      std::fputs(parsed.text.c_str(), stdout);
    } else {
      std::fprintf(stderr, "tumbled: %s\nRun with --help for more information.\n", parsed.text.c_str());
    }
    return parsed.exit_code;
  }
  const ServerOptions& options = *parsed.options;

  spdlog::set_level(spdlog::level::from_str(options.log_level));
  spdlog::set_pattern("%Y-%m-%dT%H:%M:%S.%e %^%-5l%$ [%n] %v");
  auto log = spdlog::stderr_color_mt("tumbled");
  log_access(options.tokens, *log);

  // The NATS link comes up before the world: with --nats-state the world's
  // checkpoint is in the cluster. It connects (or keeps trying) in the
  // background.
  std::optional<tumble::nats::NatsLibraryScope> nats_library;
  std::unique_ptr<tumble::nats::NatsLink> nats_link;
  std::unique_ptr<tumble::nats::NatsStateStore> state_store;
  std::unique_ptr<tumble::nats::WorldLease> lease;
  // nats.c runs the link's handlers on threads of its own until the link is
  // closed, and they reach the lease (and the NATS world, below): closed
  // before those go, on every way out of main.
  const LinkCloser close_link_before_the_lease{nats_link};
  const std::string server_id = tumble::nats::make_server_id();
  tumble::server::KeptState kept;
  if (!options.nats_urls.empty()) {
    nats_library.emplace();
    tumble::nats::NatsLinkConfig link_config;
    link_config.urls = options.nats_urls;
    link_config.creds_file = options.nats_creds_path;
    link_config.name = "tumbled " + options.world;
    nats_link = std::make_unique<tumble::nats::NatsLink>(link_config, *log);
    if (auto status = nats_link->start(); !status.ok()) {
      log->error("{}", status.message());
      return kExitFailure;
    }
  }
  if (options.nats_state) {
    tumble::nats::NatsStateStoreConfig store_config;
    store_config.bucket = options.nats_bucket;
    store_config.key = options.world;
    store_config.replicas = options.nats_replicas;
    // A standby (one that lost the lease, too) waits for the cluster as long as it takes.
    if (options.standby) store_config.wait = std::chrono::hours(24 * 365);
    state_store = std::make_unique<tumble::nats::NatsStateStore>(*nats_link, store_config, *log);
    if (auto status = state_store->open(); !status.ok()) {
      log->error("{}", status.message());
      return kExitFailure;
    }
    // One server leads the world; the others wait as standbys, answering
    // tumble.v1.worlds as such, and the leader's NatsWorld answers for it.
    tumble::nats::WorldLeaseConfig lease_config;
    lease_config.bucket = options.nats_bucket;
    lease_config.world = options.world;
    lease_config.id = server_id;
    lease_config.renew = std::chrono::milliseconds(std::llround(options.lease_renew_seconds * 1000));
    lease_config.timeout = std::chrono::milliseconds(std::llround(options.lease_timeout_seconds * 1000));
    lease_config.defer = options.standby;
    lease = std::make_unique<tumble::nats::WorldLease>(*nats_link, lease_config, *log);
    tumble::nats::WorldLease* standing = lease.get();
    tumble::nats::NatsLink* link = nats_link.get();
    const auto answer_as_standby = [standing, link, world = options.world,
                                    server_id](tumble::nats::NatsRequest request) {
      if (standing->held() || request.reply.empty()) return;
      tumble::v1::WorldInfo info;
      info.set_world(world);
      info.set_server_id(server_id);
      info.set_version(tumble::kVersion);
      info.set_standby(true);
      info.set_leader_id(standing->observed_leader());
      info.set_epoch(standing->observed_epoch());
      link->publish(request.reply, info.SerializeAsString());
    };
    if (auto status = nats_link->subscribe(std::string(tumble::nats::kWorldsSubject), "", answer_as_standby);
        !status.ok()) {
      log->error("{}", status.message());
      return kExitFailure;
    }
    if (auto status = lease->acquire(); !status.ok()) {
      log->error("{}", status.message());
      return kExitFailure;
    }
    lease->start_renewing([argc, argv, &log](const std::string& reason) {
      log->warn("{}: no longer stepping or publishing the world; starting again as a standby", reason);
      restart_as_standby(argc, argv);
    });
    tumble::nats::StoredState stored;
    if (auto status = state_store->load(&stored); !status.ok()) {
      if (!options.nats_state_reset) {
        log->error(
            "{}; tumbled does not start the world empty in its place: --nats-state-reset starts it from the "
            "scene and replaces the value at the first checkpoint",
            tumble::sim::log_text(status.message(), tumble::sim::kLogMessageBytes));
        return kExitFailure;
      }
      log->warn("{}; --nats-state-reset: starting from the scene",
                tumble::sim::log_text(status.message(), tumble::sim::kLogMessageBytes));
    } else if (stored.found) {
      kept.saved = std::move(stored.state);
      kept.from = state_store->where() + " (revision " + std::to_string(stored.revision) + ")";
    }
    kept.destination = state_store->where();
    tumble::nats::NatsStateStore* store = state_store.get();
    // Only the leader writes the world's checkpoints.
    kept.write = [store, standing](const tumble::v1::WorldState& state) {
      if (!standing->held()) return tumble::sim::Status::error("not written: this server no longer leads the world");
      return store->put(state);
    };
  }

  tumble::server::ReadyWorld world;
  if (auto status = tumble::server::start_world(options, *log, &world, options.nats_state ? &kept : nullptr);
      !status.ok()) {
    // The message may quote a scene, state or journal file.
    log->error("{}", tumble::sim::log_text(status.message(), tumble::sim::kLogMessageBytes));
    return kExitFailure;
  }
  tumble::sim::Simulation& sim = *world.sim;

  // The spinners start before this thread changes its scheduling, so none
  // of them ever spins under what the sim and I/O threads get.
  tumble::CpuKeepAwake keep_awake;
  if (options.keep_cpus_awake) {
    if (auto status = keep_awake.start(); !status.ok()) {
      log->error("--keep-cpus-awake: {}", status.message());
      return kExitFailure;
    }
    log->info("keeping {} CPUs awake (a SCHED_IDLE spinner on each)", keep_awake.spinner_count());
  }

  // This thread becomes the I/O thread (io.run() below); the sim thread,
  // started after it, inherits its scheduling: a short slice of the fair
  // scheduler, or SCHED_FIFO. The checkpoint writer, started by
  // start_world(), keeps ordinary scheduling: it writes files.
  if (auto status = tumble::request_short_slice(); !status.ok()) {
    log->warn("{}; ticks may start late on a busy machine", status.message());
  }
  if (options.realtime_priority > 0) {
    if (auto status = tumble::enter_realtime(options.realtime_priority); !status.ok()) {
      log->error("--realtime-priority {}: {}", options.realtime_priority, status.message());
      return kExitFailure;
    }
    log->info("sim and network threads run under SCHED_FIFO at priority {}", options.realtime_priority);
  }

  boost::asio::io_context io;
  std::optional<tumble::net::Server> server;
  if (options.serve_tcp) server.emplace(io, sim, server_config(options));
  // The world's subjects on the NATS link.
  std::unique_ptr<tumble::nats::NatsWorld> nats_world;
  const LinkCloser close_link_before_the_nats_world{nats_link};
  if (nats_link) {
    tumble::nats::NatsWorldConfig world_config;
    world_config.world = options.world;
    world_config.streams = options.nats_streams;
    world_config.key_interval_s = options.nats_key_interval_seconds;
    world_config.rest_key_interval_s = options.nats_rest_key_interval_seconds;
    world_config.sleep_events = options.nats_sleep_events;
    world_config.version = tumble::kVersion;
    world_config.server_id = server_id;
    world_config.lease = lease.get();
    nats_world = std::make_unique<tumble::nats::NatsWorld>(sim, *nats_link, world_config, *log);
    if (auto status = nats_world->start(); !status.ok()) {
      log->error("{}", status.message());
      return kExitFailure;
    }
    log->info("serving world '{}' over NATS ({} stream(s))", options.world, options.nats_streams.size());
  }
  // The handlers are in place before anyone can learn the port: a SIGINT
  // or SIGTERM sent as soon as the port file appears stops the server
  // cleanly (saving the world) instead of killing it. One that comes
  // before io.run() waits in the signal set until then.
  boost::asio::signal_set signals(io, SIGINT, SIGTERM);
  signals.async_wait([&](const boost::system::error_code& error, int signal) {
    if (error) return;
    log->info("received {}: shutting down", signal == SIGINT ? "SIGINT" : "SIGTERM");
    if (server) server->stop();
    io.stop();
  });
  if (server) {
    if (auto status = server->start(); !status.ok()) {
      log->error("{}", status.message());
      return kExitFailure;
    }
    // The HTTP port first: whoever waits for --port-file then finds both.
    if (!options.http_port_file.empty()) write_port_file(options.http_port_file, server->http_port());
    if (!options.port_file.empty()) write_port_file(options.port_file, server->port());
  }
  // Without listeners nothing else keeps io.run() busy until a signal.
  auto keep_running = boost::asio::make_work_guard(io);

  sim.start();
  io.run();
  if (lease) lease->stop_renewing();
  sim.stop();
  if (nats_world) nats_world->stop();
  if (world.checkpoints) world.checkpoints->stop();  // a late checkpoint must not land after the final save
  log->info("stopped at tick {} ({} overruns)", sim.tick(), sim.overruns());
  if (world.journal && !world.journal->status().ok()) {
    log->error("the journal is incomplete: {}", world.journal->status().message());
  }
  if (!options.state_path.empty()) {
    tumble::v1::WorldState state;
    sim.capture(&state);
    if (auto status = tumble::sim::write_state_file(options.state_path, state); !status.ok()) {
      log->error("the world was not saved: {}", status.message());
      return kExitFailure;
    }
    log->info("saved the world at tick {} to {}", state.tick(), options.state_path);
  }
  if (state_store) {
    tumble::v1::WorldState state;
    sim.capture(&state);
    if (!lease->held()) {
      log->warn("the world was not saved: this server no longer leads it");
    } else if (auto put = state_store->put(state); !put.ok()) {
      log->error("the world was not saved: {}", put.message());
      return kExitFailure;
    } else {
      log->info("saved the world at tick {} to {} (revision {})", state.tick(), state_store->where(),
                state_store->last_revision());
    }
    // A standby takes over at once rather than after the timeout.
    lease->release();
  }
  return kExitSuccess;
}
