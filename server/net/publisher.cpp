#include "net/publisher.h"

#include <algorithm>
#include <cmath>

#include "frames/pose_frames.h"
#include "frames/world_events.h"
#include "net/session.h"
#include "wire/frame.h"

namespace tumble::net {
namespace {

std::uint32_t kind_bit(int kind) { return std::uint32_t{1} << static_cast<unsigned>(kind); }

// The kinds that need the sim to scan the bodies after every step.
constexpr std::uint32_t kSleepEventBits = (std::uint32_t{1} << tumble::v1::WORLD_EVENT_BODY_ASLEEP) |
                                          (std::uint32_t{1} << tumble::v1::WORLD_EVENT_BODY_AWAKE);

// Streams of at most this many bodies are published ahead of larger ones
// due at the same tick, in a snapshot of their own. The publisher's latency
// policy: the sim is handed the same line with the interest, so both split
// in the same place.
constexpr std::size_t kEarlySnapshotBodies = 64;

bool publishes_early(bool all_bodies, const std::vector<physics::BodyId>& bodies) {
  return sim::goes_early(all_bodies, bodies.size(), kEarlySnapshotBodies);
}

}  // namespace

Publisher::Publisher(boost::asio::io_context& io, sim::Simulation& sim, std::chrono::microseconds fanout_slice)
    : io_(io), sim_(sim), fanout_slice_(fanout_slice) {}

std::variant<Subscription, sim::RequestError> Publisher::subscribe(const std::shared_ptr<Session>& session,
                                                                   const tumble::v1::Subscribe& request) {
  serve_fanouts(true);  // what a session gets stays in order
  // Resolve the filter to ids now: a misspelt name is an error the client should hear about.
  std::vector<physics::BodyId> bodies;
  for (const tumble::v1::BodyRef& ref : request.bodies()) {
    const physics::BodyId id = sim_.resolve(ref);
    if (id == physics::kInvalidBodyId) {
      return sim::RequestError{tumble::v1::UNKNOWN_BODY, "no " + sim::BodyDirectory::describe(ref) + " in the world"};
    }
    bodies.push_back(id);
  }
  std::sort(bodies.begin(), bodies.end());
  bodies.erase(std::unique(bodies.begin(), bodies.end()), bodies.end());
  const bool all_bodies = request.bodies_size() == 0;
  const bool velocities = request.fields() != tumble::v1::POSE_FIELDS_POSE;
  const bool joints = request.joints();
  const tumble::v1::PoseEncoding encoding = request.encoding();
  std::uint32_t event_kinds = 0;
  for (const int kind : request.events()) event_kinds |= kind_bit(kind);

  // The period is a whole number of ticks, so the rate is rounded to a divisor of the tick rate.
  const double tick_rate = sim_.tick_rate_hz();
  std::uint32_t period = 1;
  if (request.rate_hz() > 0) {
    period = static_cast<std::uint32_t>(std::clamp(std::round(tick_rate / request.rate_hz()), 1.0, 1e6));
  }

  auto it = std::find_if(streams_.begin(), streams_.end(), [&](const Stream& s) {
    return s.all_bodies == all_bodies && s.bodies == bodies && s.period_ticks == period && s.velocities == velocities &&
           s.joints == joints && s.event_kinds == event_kinds && s.encoding == encoding;
  });
  if (it == streams_.end()) {
    Stream stream;
    stream.id = next_stream_id_++;
    stream.all_bodies = all_bodies;
    stream.bodies = std::move(bodies);
    stream.period_ticks = period;
    stream.velocities = velocities;
    stream.joints = joints;
    stream.encoding = encoding;
    stream.event_kinds = event_kinds;
    stream.last_tick = sim_.tick();
    streams_.push_back(std::move(stream));
    it = std::prev(streams_.end());
    update_sim_interest();
  }
  const bool already_member =
      std::any_of(it->members.begin(), it->members.end(), [&](const Member& m) { return m.key == session.get(); });
  if (!already_member) it->members.push_back({session.get(), session});
  it->awaiting_first.push_back({session.get(), session});
  const Subscription subscription{it->id, period, tick_rate / period, encoding};
  order_streams();  // `it` is not used past here
  sim_.request_snapshot();
  return subscription;
}

bool Publisher::request_key_frame(const std::shared_ptr<Session>& session, std::uint32_t stream_id) {
  serve_fanouts(true);  // what a session gets stays in order
  auto it = std::find_if(streams_.begin(), streams_.end(), [&](const Stream& s) { return s.id == stream_id; });
  if (it == streams_.end() ||
      std::none_of(it->members.begin(), it->members.end(), [&](const Member& m) { return m.key == session.get(); })) {
    return false;
  }
  it->awaiting_first.push_back({session.get(), session});
  sim_.request_snapshot();
  return true;
}

bool Publisher::unsubscribe(const Session& session, std::uint32_t stream_id) {
  serve_fanouts(true);  // what a session gets stays in order
  auto it = std::find_if(streams_.begin(), streams_.end(), [&](const Stream& s) { return s.id == stream_id; });
  if (it == streams_.end()) return false;
  const auto is_session = [&](const Member& m) { return m.key == &session; };
  const std::size_t removed = std::erase_if(it->members, is_session);
  std::erase_if(it->awaiting_first, is_session);
  if (it->members.empty()) {
    streams_.erase(it);
    update_sim_interest();
  }
  order_streams();
  return removed > 0;
}

void Publisher::remove_session(const Session& session) {
  serve_fanouts(true);  // what a session gets stays in order
  const auto is_session = [&](const Member& m) { return m.key == &session; };
  for (Stream& stream : streams_) {
    std::erase_if(stream.members, is_session);
    std::erase_if(stream.awaiting_first, is_session);
  }
  const std::size_t removed = std::erase_if(streams_, [](const Stream& s) { return s.members.empty(); });
  if (removed > 0) update_sim_interest();
  order_streams();
}

void Publisher::order_streams() {
  // Bodies a frame carries times the sessions it goes to; a stream of
  // every body counts as larger than any filtered one.
  const auto cost = [](const Stream& s) {
    const std::uint64_t bodies = s.all_bodies ? std::uint64_t{1} << 32 : s.bodies.size();
    return bodies * s.members.size();
  };
  std::stable_sort(streams_.begin(), streams_.end(),
                   [&](const Stream& a, const Stream& b) { return cost(a) < cost(b); });
}

void Publisher::offer(std::shared_ptr<const sim::Snapshot> snapshot) {
  std::lock_guard lock(handoff_mutex_);
  latest_ = std::move(snapshot);
  if (publish_posted_) return;  // the pending publish will take this newer snapshot
  publish_posted_ = true;
  boost::asio::post(io_, [this] { publish_latest(); });
}

void Publisher::offer_events(std::shared_ptr<const sim::WorldEvents> events) {
  std::lock_guard lock(handoff_mutex_);
  events_.push_back(std::move(events));
  if (publish_posted_) return;  // the pending publish will take these too
  publish_posted_ = true;
  boost::asio::post(io_, [this] { publish_latest(); });
}

void Publisher::publish_latest() {
  serve_fanouts(true);  // what a session gets stays in order
  std::shared_ptr<const sim::Snapshot> snapshot;
  {
    std::lock_guard lock(handoff_mutex_);
    snapshot = std::move(latest_);
    delivering_.swap(events_);
    publish_posted_ = false;
  }
  // Events first: they are as old as the snapshot or older.
  for (const auto& batch : delivering_) {
    for (const sim::WorldEvent& event : *batch) deliver(event);
  }
  delivering_.clear();
  if (snapshot) publish(*snapshot);
}

void Publisher::deliver(const sim::WorldEvent& event) {
  const tumble::v1::WorldEventKind kind = frames::wire_kind(event.kind);
  bool filters_changed = false;
  for (Stream& stream : streams_) {
    const bool names_body =
        !stream.all_bodies && std::binary_search(stream.bodies.begin(), stream.bodies.end(), event.body);
    // A joint's event concerns the streams of either of its bodies.
    const bool names_body_a = event.joint != physics::kInvalidJointId && !stream.all_bodies &&
                              std::binary_search(stream.bodies.begin(), stream.bodies.end(), event.body_a);
    const bool concerns_stream =
        stream.all_bodies || names_body || names_body_a || kind == tumble::v1::WORLD_EVENT_WORLD_RESET;
    if (concerns_stream && (stream.event_kinds & kind_bit(kind)) != 0) {
      tumble::v1::ServerMessage message;
      frames::fill_world_event(event, stream.id, message.mutable_world_event());
      for (const Member& member : stream.members) {
        if (auto session = member.session.lock()) session->send(message);
      }
    }
    if (names_body && kind == tumble::v1::WORLD_EVENT_BODY_REMOVED) {
      stream.bodies.erase(std::lower_bound(stream.bodies.begin(), stream.bodies.end(), event.body));
      filters_changed = true;
    }
  }
  if (filters_changed) update_sim_interest();
}

void Publisher::publish(const sim::Snapshot& snapshot) {
  for (Stream& stream : streams_) {
    // Regular frames fall on multiples of the period; a frame whose
    // snapshot was superseded in the handoff is made up by the next one.
    // An edit while paused is shown to every stream at once.
    const bool regular =
        (snapshot.tick > stream.last_tick &&
         (snapshot.tick % stream.period_ticks == 0 || snapshot.tick - stream.last_tick > stream.period_ticks)) ||
        (snapshot.out_of_band && snapshot.tick >= stream.last_tick);
    if (!regular && stream.awaiting_first.empty()) continue;
    if (!snapshot.covers(stream.all_bodies, stream.bodies, stream.joints)) {
      // A larger snapshot of this tick follows; or this one was
      // taken before the sim knew of the stream, or the stream's own was
      // superseded in the handoff: the next one then holds every body, and
      // the frame is made up from it.
      if (!snapshot.more_follows) sim_.request_snapshot();
      continue;
    }
    send_frame(stream, snapshot, regular ? stream.members : stream.awaiting_first);
    stream.awaiting_first.clear();
    if (regular) stream.last_tick = snapshot.tick;
  }
  serve_fanouts(false);
}

void Publisher::send_frame(Stream& stream, const sim::Snapshot& snapshot, const std::vector<Member>& targets) {
  Fanout fanout;
  fanout.stream_id = stream.id;
  if (stream.encoding == tumble::v1::POSE_ENCODING_DELTA) {
    auto frame = std::make_shared<QuantizedFrame>();
    frame->subscription_id = stream.id;
    frame->tick = snapshot.tick;
    frame->sim_time = snapshot.sim_time;
    frame->velocities = stream.velocities;
    frame->bodies = stream.memo.quantize(snapshot, stream.all_bodies, stream.bodies, stream.velocities);
    frame->sequence = ++stream.frames_made;
    if (stream.joints) frames::fill_joints(snapshot, &frame->joints);
    fanout.delta = std::move(frame);
  } else {
    fanout.bytes = encode(stream, snapshot);
  }
  fanout.targets.reserve(targets.size());
  for (const Member& member : targets) fanout.targets.push_back(member.session);
  fanouts_.push_back(std::move(fanout));
}

void Publisher::serve_fanouts(bool all) {
  const auto started = std::chrono::steady_clock::now();
  while (!fanouts_.empty()) {
    Fanout& fanout = fanouts_.front();
    while (fanout.next < fanout.targets.size()) {
      if (auto session = fanout.targets[fanout.next].lock()) {
        if (fanout.delta) {
          session->send_delta_frame(fanout.stream_id, fanout.delta);
        } else {
          session->send_frame(fanout.stream_id, fanout.bytes);
        }
      }
      ++fanout.next;
      if (!all && std::chrono::steady_clock::now() - started >= fanout_slice_) {
        if (!fanout_posted_) {
          fanout_posted_ = true;
          boost::asio::post(io_, [this] {
            fanout_posted_ = false;
            serve_fanouts(false);
          });
        }
        return;
      }
    }
    fanouts_.pop_front();
  }
}

std::shared_ptr<const std::string> Publisher::encode(Stream& stream, const sim::Snapshot& snapshot) {
  tumble::v1::ServerMessage message;
  tumble::v1::PoseFrame& frame = *message.mutable_pose_frame();
  frame.set_subscription_id(stream.id);
  frame.set_tick(snapshot.tick);
  frame.set_sim_time(snapshot.sim_time);
  if (stream.encoding == tumble::v1::POSE_ENCODING_QUANTIZED) {
    frames::fill_quantized(stream.memo.quantize(snapshot, stream.all_bodies, stream.bodies, stream.velocities),
                           stream.velocities, &frame);
  } else {
    frames::fill_full(snapshot, stream.all_bodies, stream.bodies, stream.velocities, &frame);
  }
  if (stream.joints) frames::fill_joints(snapshot, &frame);
  return std::make_shared<const std::string>(wire::encode_frame(message));
}

void Publisher::update_sim_interest() {
  // One interest a period and size: every body when a stream at that
  // period wants all, else the union of the streams' filters; small
  // streams apart from large ones, so that the sim can publish them first.
  std::vector<sim::PublishInterest> interest;
  bool sleep_events = false;
  for (const Stream& stream : streams_) {
    sleep_events = sleep_events || (stream.event_kinds & kSleepEventBits) != 0;
    const bool stream_small = publishes_early(stream.all_bodies, stream.bodies);
    auto it = std::find_if(interest.begin(), interest.end(), [&](const sim::PublishInterest& i) {
      return i.period_ticks == stream.period_ticks && publishes_early(i.all_bodies, i.bodies) == stream_small;
    });
    if (it == interest.end()) {
      interest.push_back({stream.period_ticks, stream.all_bodies, stream.bodies, stream.joints});
      continue;
    }
    it->joints = it->joints || stream.joints;
    if (it->all_bodies) continue;
    if (stream.all_bodies) {
      it->all_bodies = true;
      it->bodies.clear();
      continue;
    }
    std::vector<physics::BodyId> both;
    both.reserve(it->bodies.size() + stream.bodies.size());
    std::set_union(it->bodies.begin(), it->bodies.end(), stream.bodies.begin(), stream.bodies.end(),
                   std::back_inserter(both));
    it->bodies = std::move(both);
  }
  sim_.set_publish_interest(std::move(interest), kEarlySnapshotBodies);
  sim_.set_sleep_events_wanted(sleep_events);
}

}  // namespace tumble::net
