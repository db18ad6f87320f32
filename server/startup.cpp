#include "startup.h"

#include <algorithm>
#include <chrono>
#include <string>

#include "sim/replay.h"
#include "sim/scene_file.h"
#include "sim/state_resume.h"
#include "tumble/version.h"

namespace tumble::server {
namespace {

constexpr std::size_t kNatsListPageBytes = std::size_t{512} << 10;

}  // namespace
namespace {

// Where the world starts, before the simulation is built.
struct Origin {
  tumble::v1::Scene scene;       // the scene to build, unless resuming
  tumble::v1::WorldState saved;  // the state to resume, when `resume`
  bool resume = false;
  // Built from the state file already, when `resume` comes from --state.
  std::unique_ptr<sim::Simulation> resumed;
  std::string name;  // for the log: the file, "the start of" a journal, or "no scene"
};

// The --scene file, or an empty world under standard gravity.
sim::Status load_scene(const ServerOptions& options, tumble::v1::Scene* scene) {
  if (options.scene_path.empty()) {
    scene->mutable_gravity()->set_y(-9.81);
    return {};
  }
  if (auto status = sim::load_scene_file(options.scene_path, scene); !status.ok()) {
    return sim::Status::error("cannot load the scene: " + status.message());
  }
  return {};
}

// Picks the journal's start, the state file (or the one it replaced, when
// it is damaged) or the scene; `config`'s tick rate becomes the journal's
// when it starts from a scene.
sim::Status choose_origin(const ServerOptions& options, spdlog::logger& log, const KeptState* kept,
                          sim::JournalReader& replay, sim::SimConfig& config, Origin* origin) {
  if (auto status = load_scene(options, &origin->scene); !status.ok()) return status;
  origin->name = options.scene_path.empty() ? std::string("no scene") : options.scene_path;
  if (!options.replay_path.empty()) {
    if (auto status = replay.open(options.replay_path); !status.ok()) {
      return sim::Status::error("cannot replay: " + status.message());
    }
    if (!replay.checksummed()) {
      log.warn("{} is a version 1 journal, whose records carry no checksums: damage to it cannot be detected",
               options.replay_path);
    }
    const tumble::v1::JournalHeader& header = replay.header();
    if (header.has_state()) {
      origin->saved = header.state();
      origin->resume = true;
    } else {
      if (!options.scene_path.empty() && header.scene().SerializeAsString() != origin->scene.SerializeAsString()) {
        return sim::Status::error("cannot replay " + options.replay_path +
                                  ": it was recorded with another scene than " + options.scene_path);
      }
      origin->scene = header.scene();
      config.tick_rate_hz = header.tick_rate_hz();
    }
    origin->name = "the start of " + options.replay_path;
  } else if (!options.state_path.empty()) {
    // A state that does not build a world counts as damaged, as one that
    // fails its checksum does.
    const auto build = [&](const tumble::v1::WorldState& state) {
      return sim::Simulation::create_from_state(state, config, &origin->resumed);
    };
    sim::ResumedState resumed;
    const sim::Status status = sim::resume_state(options.state_path, build, &resumed);
    for (const std::string& warning : resumed.warnings) log.warn("{}", warning);
    if (!status.ok()) return sim::Status::error("cannot resume: " + status.message());
    origin->resume = resumed.resumed;
    if (resumed.resumed) origin->name = resumed.from;
  } else if (kept != nullptr && kept->saved) {
    origin->saved = *kept->saved;
    origin->resume = true;
    origin->name = kept->from;
  }
  return {};
}

// Opens the --record journal, headed by where this run starts.
sim::Status open_journal(const ServerOptions& options, const Origin& origin, sim::Simulation& simulation,
                         sim::JournalWriter* journal) {
  tumble::v1::JournalHeader header;
  header.set_format_version(sim::kJournalFormat);
  header.set_server_version(kVersion);
  header.set_tick_rate_hz(simulation.tick_rate_hz());
  if (origin.resume) {
    simulation.capture(header.mutable_state());
  } else {
    *header.mutable_scene() = origin.scene;
  }
  if (auto status = journal->open(options.record_path, header); !status.ok()) {
    return sim::Status::error("cannot record: " + status.message());
  }
  return {};
}

}  // namespace

sim::Status start_world(const ServerOptions& options, spdlog::logger& log, ReadyWorld* world, const KeptState* kept) {
  sim::SimConfig config;
  config.tick_rate_hz = options.tick_rate_hz;
  config.max_bodies = options.max_bodies;
  config.physics_threads = options.physics_threads;
  // A page of ListBodies is never more than a client that reads may leave unread.
  config.list_page_bytes = std::min(config.list_page_bytes, options.max_pending_bytes / 2);
  // Over NATS a reply must fit the server's max payload (1 MiB by default).
  if (!options.nats_urls.empty()) config.list_page_bytes = std::min(config.list_page_bytes, kNatsListPageBytes);

  sim::JournalReader replay;
  Origin origin;
  if (auto status = choose_origin(options, log, kept, replay, config, &origin); !status.ok()) return status;
  if (!origin.resume && options.scene_path.empty() && options.replay_path.empty()) {
    log.warn("no --scene given: starting with an empty world");
  }

  if (origin.resumed) {
    world->sim = std::move(origin.resumed);
  } else if (origin.resume) {
    if (auto status = sim::Simulation::create_from_state(origin.saved, config, &world->sim); !status.ok()) {
      const bool reset = kept != nullptr && options.nats_state_reset;
      if (!reset) return sim::Status::error("cannot resume from " + origin.name + ": " + status.message());
      // --nats-state-reset: the checkpoint gives way to the scene.
      log.warn("--nats-state-reset: not resuming from {} ({}); starting from the scene", origin.name, status.message());
      world->sim.reset();
      origin.resume = false;
      origin.name = options.scene_path.empty() ? std::string("no scene") : options.scene_path;
    }
  }
  if (!world->sim) {
    if (auto status = sim::Simulation::create(origin.scene, config, &world->sim); !status.ok()) {
      return sim::Status::error("invalid scene " + options.scene_path + ": " + status.message());
    }
  }
  sim::Simulation& simulation = *world->sim;
  log.info("tumbled {}: {} bodies from {}, at tick {}{}", kVersion, simulation.body_count(), origin.name,
           simulation.tick(), simulation.paused() ? ", paused" : "");

  if (!options.replay_path.empty()) {
    sim::ReplaySummary summary;
    if (auto status = sim::replay_journal(replay, simulation, &summary); !status.ok()) {
      return sim::Status::error("replay of " + options.replay_path + " failed after " +
                                std::to_string(summary.commands) + " commands: " + status.message());
    }
    if (replay.torn()) {
      log.warn("{}: {}: the run that wrote it was killed mid-write; replayed up to it", options.replay_path,
               replay.torn_record());
    }
    log.info("replayed {} commands of {} to tick {}{}; paused there", summary.commands, options.replay_path,
             summary.end_tick, summary.complete ? "" : " (the journal was cut short: its run was killed)");
  }

  if (!options.record_path.empty()) {
    world->journal = std::make_unique<sim::JournalWriter>();
    if (auto status = open_journal(options, origin, simulation, world->journal.get()); !status.ok()) return status;
    simulation.set_journal(world->journal.get());
    log.info("recording commands to {}", options.record_path);
  }

  if (options.checkpoint_interval_seconds > 0 && (!options.state_path.empty() || kept != nullptr)) {
    world->checkpoints = options.state_path.empty() ? std::make_unique<sim::StateSaver>(kept->destination, kept->write)
                                                    : std::make_unique<sim::StateSaver>(options.state_path);
    sim::StateSaver* saver = world->checkpoints.get();
    simulation.set_checkpoints(
        std::chrono::duration_cast<std::chrono::steady_clock::duration>(
            std::chrono::duration<double>(options.checkpoint_interval_seconds)),
        [saver](std::shared_ptr<const tumble::v1::WorldState> state, std::chrono::steady_clock::duration capture) {
          saver->offer(std::move(state), capture);
        });
    // The saver outlives the sim thread that calls the hook (ReadyWorld).
    simulation.add_stats_hook([saver, interval = options.checkpoint_interval_seconds](tumble::v1::Stats* stats) {
      const sim::StateSaver::Report report = saver->report();
      tumble::v1::Checkpoints& checkpoints = *stats->mutable_checkpoints();
      checkpoints.set_destination(saver->destination());
      checkpoints.set_interval_s(interval);
      checkpoints.set_written(report.written);
      checkpoints.set_failed(report.failed);
      checkpoints.set_last_tick(report.last_tick);
      checkpoints.set_last_bytes(report.last_bytes);
      checkpoints.set_last_write_ms(report.last_write_ms);
      checkpoints.set_write_ms_max(report.write_ms_max);
      checkpoints.set_last_capture_ms(report.last_capture_ms);
      checkpoints.set_capture_ms_max(report.capture_ms_max);
    });
    log.info("checkpointing the world to {} every {} s", saver->destination(), options.checkpoint_interval_seconds);
  }
  return {};
}

}  // namespace tumble::server
