// Fans snapshots and world events out to subscribers. Subscriptions that
// ask for the same thing (the same bodies at the same period, with the same
// fields, event kinds and encoding) share one stream: its frame is encoded
// once per snapshot and the bytes are shared by every session on it. A
// DELTA stream shares its quantized frame instead, and each session encodes
// it against what its own client last received (net/delta_encoder.h). The
// stream's id is the subscription_id clients see.
//
// The sim thread hands snapshots over with offer(), which never blocks: it
// keeps only the latest one and posts the publishing to the I/O thread. A
// new subscriber asks the sim for a snapshot and gets the current state from
// it at once, whatever its stream's period, paused or not. An out-of-band
// snapshot (an edit while paused) goes to every stream. The sim copies
// into a snapshot only the bodies the streams due at its tick read (their
// periods and filters, update_sim_interest()), and publishes the bodies
// of small streams (kEarlySnapshotBodies in publisher.cpp) in a snapshot of
// their own ahead of the large ones due at the same tick; a stream due at a
// snapshot that does not hold its bodies (made before the sim knew of the
// stream, or after the stream's own snapshot was superseded) asks for one
// of every body and is served from that.
//
// Events come over with offer_events(), which queues them all (they are not
// latest-wins); each is sent as a WorldEvent to the members of the streams
// that asked for its kind, before the frame of the same tick. A removed body
// leaves the filters of the streams that named it.
//
// Thread: offer() and offer_events() from any thread; everything else on
// the I/O thread.
//
// Order: the streams due at a snapshot are published cheapest first (the
// fewest bodies times sessions), so a small stream's latency does not
// depend on the large ones beside it. A frame is handed to its sessions a
// slice of I/O time at a time (the constructor's fanout_slice): between slices the I/O thread
// reads requests, so a command that arrives while a frame goes out to a
// hundred sessions is not held until all of it is sent (it would miss its
// tick). Every other call finishes the fan-out under way first, so what a
// session receives is in the order it would be without slicing.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <variant>
#include <vector>

#include "frames/quantize_memo.h"
#include "net/asio.h"
#include "net/quantized_frame.h"
#include "sim/request_check.h"
#include "sim/simulation.h"
#include "sim/snapshot.h"
#include "sim/world_event.h"
#include "tumble/v1/protocol.pb.h"

namespace tumble::net {

class Session;

// What a client gets back for a Subscribe.
struct Subscription {
  std::uint32_t stream_id = 0;
  std::uint32_t period_ticks = 1;
  double rate_hz = 0;
  tumble::v1::PoseEncoding encoding = tumble::v1::POSE_ENCODING_FULL;
};

class Publisher {
 public:
  // `fanout_slice`: the I/O time a fan-out takes before the I/O thread turns
  // to other work; zero hands a frame to one session a turn.
  Publisher(boost::asio::io_context& io, sim::Simulation& sim, std::chrono::microseconds fanout_slice);

  // Adds `session` to the stream for `request`, making the stream if it is
  // new. Fails with UNKNOWN_BODY when the filter names a body that is not
  // in the world.
  std::variant<Subscription, sim::RequestError> subscribe(const std::shared_ptr<Session>& session,
                                                          const tumble::v1::Subscribe& request);

  // False when the session is not on that stream.
  bool unsubscribe(const Session& session, std::uint32_t stream_id);

  // Sends `session` the current state of `stream_id` at once, as it does a
  // new subscriber. False when the session is not on that stream.
  bool request_key_frame(const std::shared_ptr<Session>& session, std::uint32_t stream_id);

  // Takes a closing session off every stream.
  void remove_session(const Session& session);

  // Hands a snapshot over from the sim thread.
  void offer(std::shared_ptr<const sim::Snapshot> snapshot);

  // Hands a tick's events over from the sim thread.
  void offer_events(std::shared_ptr<const sim::WorldEvents> events);

  std::size_t stream_count() const { return streams_.size(); }

 private:
  struct Member {
    const Session* key;
    std::weak_ptr<Session> session;
  };
  struct Stream {
    std::uint32_t id = 0;
    bool all_bodies = true;
    std::vector<physics::BodyId> bodies;  // sorted, when !all_bodies
    std::uint32_t period_ticks = 1;
    bool velocities = true;  // POSE_FIELDS_POSE_AND_VELOCITY
    bool joints = false;     // Subscribe.joints
    tumble::v1::PoseEncoding encoding = tumble::v1::POSE_ENCODING_FULL;
    std::uint32_t event_kinds = 0;  // bit k set: events of tumble.v1.WorldEventKind k
    std::uint64_t last_tick = 0;    // tick of the last regular frame
    std::uint64_t frames_made = 0;  // DELTA: the sequence number of the last QuantizedFrame made
    std::vector<Member> members;
    std::vector<Member> awaiting_first;  // joined since the last frame
    frames::QuantizeMemo memo;           // QUANTIZED and DELTA: the bodies of its last frame on the grids
  };

  // A frame on its way to the members of a stream.
  struct Fanout {
    std::uint32_t stream_id = 0;
    std::shared_ptr<const std::string> bytes;     // FULL or QUANTIZED, framed
    std::shared_ptr<const QuantizedFrame> delta;  // DELTA: each session encodes its own
    std::vector<std::weak_ptr<Session>> targets;
    std::size_t next = 0;  // targets served so far
  };

  // Hands queued frames to their sessions: all of them, or for one slice
  // of I/O time and then again from a posted handler.
  void serve_fanouts(bool all);

  void publish_latest();
  void publish(const sim::Snapshot& snapshot);
  void deliver(const sim::WorldEvent& event);
  // Queues the stream's frame of `snapshot` for `targets`.
  void send_frame(Stream& stream, const sim::Snapshot& snapshot, const std::vector<Member>& targets);
  // A FULL or QUANTIZED frame, framed for the wire.
  std::shared_ptr<const std::string> encode(Stream& stream, const sim::Snapshot& snapshot);
  // Tells the sim which bodies it must publish at which periods, and whether
  // anyone wants sleep events.
  void update_sim_interest();
  // Sorts streams_ cheapest first: a snapshot is published in that order, so
  // a frame of a few bodies is not written after a fan-out of thousands to
  // every subscriber (shortest job first, for the latency of small streams).
  void order_streams();

  boost::asio::io_context& io_;
  sim::Simulation& sim_;
  const std::chrono::microseconds fanout_slice_;
  std::vector<Stream> streams_;
  std::uint32_t next_stream_id_ = 1;
  std::deque<Fanout> fanouts_;  // in the order they were made
  bool fanout_posted_ = false;  // a serve_fanouts() handler is queued

  std::mutex handoff_mutex_;
  std::shared_ptr<const sim::Snapshot> latest_;                      // guarded by handoff_mutex_
  std::vector<std::shared_ptr<const sim::WorldEvents>> events_;      // guarded by handoff_mutex_
  bool publish_posted_ = false;                                      // guarded by handoff_mutex_
  std::vector<std::shared_ptr<const sim::WorldEvents>> delivering_;  // I/O thread's swap partner of events_
};

}  // namespace tumble::net
