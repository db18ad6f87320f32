// NatsWorld: one world served over NATS (subjects: docs/protocol.md).
//
//  - tumble.v1.<world>.poses.<stream>: each configured stream's frames,
//    published once whatever the audience, numbered by `sequence`
//    (nats/sequence_planner.h); a DELTA stream's frames are changes from
//    the previous one, with a key frame every key_interval_s (every
//    rest_key_interval_s while nothing changes).
//  - tumble.v1.<world>.key.<stream>: answered with the stream's latest
//    frame, whole (a DELTA stream's as a key frame of the same sequence).
//  - tumble.v1.<world>.events: each world event, one a message.
//  - tumble.v1.<world>.rpc (queue group tumble.<world>.rpc): a ClientMessage
//    checked as TCP checks it (sim/request_check.h) and submitted to the
//    sim; the ServerMessage reply goes to the requester. Subscriptions are
//    refused there: they are the pose subjects.
//  - tumble.v1.worlds: answered with this world's WorldInfo.
//
// The sim thread only hands over: the latest snapshot (latest wins), the
// events (queued, bounded) and the replies (queued, bounded); the frames
// are made and published on NatsWorld's own thread, so a slow or lost
// NATS link never holds the sim or the TCP clients. A frame larger than
// the server's max payload is not published: counted in frames_dropped
// and logged at most once a second per stream; so is a frame while the
// link is down. The next frame of a DELTA stream is then a key frame.
//
// Thread: constructed, started and stopped on tumbled's main thread, before
// the sim starts and after it stops. The rest runs on its thread and on
// nats.c's.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <spdlog/logger.h>

#include "frames/quantize_memo.h"
#include "nats/nats_link.h"
#include "nats/sequence_planner.h"
#include "nats/stream_spec.h"
#include "nats/world_lease.h"
#include "sim/simulation.h"
#include "sim/snapshot.h"
#include "sim/status.h"
#include "sim/world_event.h"
#include "tumble/v1/world_info.pb.h"
#include "wire/quantized_poses.h"

namespace tumble::nats {

struct NatsWorldConfig {
  std::string world;                // checked by check_world_name
  std::vector<StreamSpec> streams;  // unique names, at least one
  double key_interval_s = 1;        // > 0
  double rest_key_interval_s = 30;  // >= key_interval_s: between key frames while nothing changes
  bool sleep_events = false;        // also publish bodies falling asleep and waking
  std::string version;              // tumbled's, for WorldInfo
  std::string server_id;            // this server's id (make_server_id()); empty: a new one
  // With --nats-state: this server's lease of the world. While it is not
  // held nothing is published or answered; frames and WorldInfo carry its
  // epoch. Null: no lease, always published. Outlives the NatsWorld.
  const WorldLease* lease = nullptr;
  // Most events and replies waiting for the publisher's thread; beyond,
  // the oldest events go (counted), a reply is answered with an Error.
  std::size_t max_queued = 65536;
};

class NatsWorld {
 public:
  // `sim` and `link` must outlive it.
  NatsWorld(sim::Simulation& sim, NatsLink& link, NatsWorldConfig config, spdlog::logger& log);
  ~NatsWorld();
  NatsWorld(const NatsWorld&) = delete;
  NatsWorld& operator=(const NatsWorld&) = delete;

  // Adds the sim's listeners and stats hook, states the streams' interest,
  // subscribes the responders and starts the publishing thread. Before
  // sim.start().
  sim::Status start();
  // Stops the publishing thread. After sim.stop().
  void stop();

  // This world's WorldInfo as a tumble.v1.worlds request is answered.
  tumble::v1::WorldInfo world_info() const;

 private:
  // One configured stream and the state of its numbering.
  struct Stream {
    Stream(StreamSpec spec_in, std::string subject_in, double key_interval_s, double rest_key_interval_s)
        : spec(std::move(spec_in)), subject(std::move(subject_in)), planner(key_interval_s, rest_key_interval_s) {}
    StreamSpec spec;
    std::string subject;
    std::uint32_t period_ticks = 1;
    SequencePlanner planner;
    frames::QuantizeMemo memo;
    std::uint64_t last_tick = 0;  // tick of its last frame
    bool any_frame = false;
    // Its latest frame: the header, and the bodies (QUANTIZED, DELTA) or
    // the FULL frame's bytes, for the .key answer.
    std::uint64_t latest_sequence = 0;
    std::uint64_t latest_tick = 0;
    double latest_sim_time = 0;
    std::vector<wire::QuantizedBody> latest_bodies;
    std::string latest_full;
    tumble::v1::PoseFrame latest_joints;       // its joints' states (spec.joints), in a frame of only those
    std::vector<wire::QuantizedBody> changed;  // scratch of the DELTA change
    std::chrono::steady_clock::time_point last_drop_log{};
    std::uint64_t drops_since_log = 0;
  };

  void run();
  void publish(const sim::Snapshot& snapshot);
  void publish_frame(Stream& stream, const sim::Snapshot& snapshot);
  void publish_events(const sim::WorldEvents& events);
  // Answers a .key request for stream `index` (on the publishing thread).
  void answer_key(std::size_t index, const std::string& reply);
  // Answers a request on .rpc, or on .query when `read_only` (reads only).
  void answer_rpc(NatsRequest request, bool read_only);
  // Sends `message` to `reply` from the publishing thread; over the max
  // payload it is an Error instead.
  // Publishes through the link while this server leads the world (see
  // NatsWorldConfig::lease); else publishes nothing and says the link is down.
  NatsLink::Sent publish_to(const std::string& subject, std::string_view data);
  void send_reply(const std::string& reply, const tumble::v1::ServerMessage& message, std::uint64_t request_id);
  // Queues work for the publishing thread; false when the queue is full.
  bool post(std::function<void()> work);
  void note_drop(Stream& stream, NatsLink::Sent why, std::size_t bytes);

  sim::Simulation& sim_;
  NatsLink& link_;
  const NatsWorldConfig config_;
  spdlog::logger& log_;
  const std::string server_id_;
  sim::PublishSource source_ = 0;
  std::vector<Stream> streams_;  // the publishing thread's, once started

  std::mutex mutex_;
  std::condition_variable wake_;
  std::shared_ptr<const sim::Snapshot> latest_;  // guarded by mutex_
  std::deque<std::function<void()>> work_;       // guarded by mutex_: events, replies, .key answers
  bool stopping_ = false;                        // guarded by mutex_
  std::thread thread_;
};

}  // namespace tumble::nats
