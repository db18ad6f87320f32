#include "net/publisher.h"

#include <algorithm>
#include <cmath>

#include "net/session.h"
#include "wire/frame.h"

namespace tumble::net {

Publisher::Publisher(boost::asio::io_context& io, sim::Simulation& sim) : io_(io), sim_(sim) {}

std::variant<Subscription, sim::RequestError> Publisher::subscribe(const std::shared_ptr<Session>& session,
                                                                   const tumble::v1::Subscribe& request) {
  // Resolve the filter to ids now: a misspelt name is an error the client should hear about.
  std::vector<physics::BodyId> bodies;
  const std::shared_ptr<const sim::BodyDirectory> directory = sim_.directory();
  for (const tumble::v1::BodyRef& ref : request.bodies()) {
    const physics::BodyId id = directory->resolve(ref);
    if (id == physics::kInvalidBodyId) {
      return sim::RequestError{tumble::v1::UNKNOWN_BODY,
                               "no " + sim::BodyDirectory::describe(ref) + " in the world"};
    }
    bodies.push_back(id);
  }
  std::sort(bodies.begin(), bodies.end());
  bodies.erase(std::unique(bodies.begin(), bodies.end()), bodies.end());
  const bool all_bodies = request.bodies_size() == 0;

  // The period is a whole number of ticks, so the rate is rounded to a divisor of the tick rate.
  const double tick_rate = sim_.tick_rate_hz();
  std::uint32_t period = 1;
  if (request.rate_hz() > 0) {
    period = static_cast<std::uint32_t>(std::clamp(std::round(tick_rate / request.rate_hz()), 1.0, 1e6));
  }

  auto it = std::find_if(streams_.begin(), streams_.end(), [&](const Stream& s) {
    return s.all_bodies == all_bodies && s.bodies == bodies && s.period_ticks == period;
  });
  if (it == streams_.end()) {
    Stream stream;
    stream.id = next_stream_id_++;
    stream.all_bodies = all_bodies;
    stream.bodies = std::move(bodies);
    stream.period_ticks = period;
    stream.last_tick = sim_.tick();
    streams_.push_back(std::move(stream));
    it = std::prev(streams_.end());
    update_periods();
  }
  const bool already_member = std::any_of(it->members.begin(), it->members.end(),
                                          [&](const Member& m) { return m.key == session.get(); });
  if (!already_member) it->members.push_back({session.get(), session});
  it->awaiting_first.push_back({session.get(), session});
  sim_.request_snapshot();
  return Subscription{it->id, period, tick_rate / period};
}

bool Publisher::unsubscribe(const Session& session, std::uint32_t stream_id) {
  auto it = std::find_if(streams_.begin(), streams_.end(), [&](const Stream& s) { return s.id == stream_id; });
  if (it == streams_.end()) return false;
  const auto is_session = [&](const Member& m) { return m.key == &session; };
  const std::size_t removed = std::erase_if(it->members, is_session);
  std::erase_if(it->awaiting_first, is_session);
  if (it->members.empty()) {
    streams_.erase(it);
    update_periods();
  }
  return removed > 0;
}

void Publisher::remove_session(const Session& session) {
  const auto is_session = [&](const Member& m) { return m.key == &session; };
  for (Stream& stream : streams_) {
    std::erase_if(stream.members, is_session);
    std::erase_if(stream.awaiting_first, is_session);
  }
  const std::size_t removed = std::erase_if(streams_, [](const Stream& s) { return s.members.empty(); });
  if (removed > 0) update_periods();
}

void Publisher::offer(std::shared_ptr<const sim::Snapshot> snapshot) {
  std::lock_guard lock(handoff_mutex_);
  latest_ = std::move(snapshot);
  if (publish_posted_) return;  // the pending publish will take this newer snapshot
  publish_posted_ = true;
  boost::asio::post(io_, [this] { publish_latest(); });
}

void Publisher::publish_latest() {
  std::shared_ptr<const sim::Snapshot> snapshot;
  {
    std::lock_guard lock(handoff_mutex_);
    snapshot = std::move(latest_);
    publish_posted_ = false;
  }
  if (snapshot) publish(*snapshot);
}

void Publisher::publish(const sim::Snapshot& snapshot) {
  for (Stream& stream : streams_) {
    // Regular frames fall on multiples of the period; a frame whose
    // snapshot was superseded in the handoff is made up by the next one.
    const bool regular = snapshot.tick > stream.last_tick &&
                         (snapshot.tick % stream.period_ticks == 0 ||
                          snapshot.tick - stream.last_tick > stream.period_ticks);
    if (!regular && stream.awaiting_first.empty()) continue;
    const std::shared_ptr<const std::string> bytes = encode(stream, snapshot);
    const std::vector<Member>& targets = regular ? stream.members : stream.awaiting_first;
    for (const Member& member : targets) {
      if (auto session = member.session.lock()) session->send_frame(stream.id, bytes);
    }
    stream.awaiting_first.clear();
    if (regular) stream.last_tick = snapshot.tick;
  }
}

std::shared_ptr<const std::string> Publisher::encode(const Stream& stream, const sim::Snapshot& snapshot) const {
  tumble::v1::ServerMessage message;
  tumble::v1::PoseFrame& frame = *message.mutable_pose_frame();
  frame.set_subscription_id(stream.id);
  frame.set_tick(snapshot.tick);
  frame.set_sim_time(snapshot.sim_time);
  const std::size_t n = stream.all_bodies ? snapshot.body_count() : stream.bodies.size();
  frame.mutable_ids()->Reserve(static_cast<int>(n));
  frame.mutable_positions()->Reserve(static_cast<int>(3 * n));
  frame.mutable_orientations()->Reserve(static_cast<int>(4 * n));
  frame.mutable_linear_velocities()->Reserve(static_cast<int>(3 * n));
  frame.mutable_angular_velocities()->Reserve(static_cast<int>(3 * n));
  for (std::size_t i = 0; i < snapshot.body_count(); ++i) {
    const physics::BodyId id = snapshot.ids[i];
    if (!stream.all_bodies && !std::binary_search(stream.bodies.begin(), stream.bodies.end(), id)) continue;
    frame.add_ids(id);
    for (std::size_t k = 0; k < 3; ++k) {
      frame.add_positions(static_cast<float>(snapshot.positions[3 * i + k]));
      frame.add_linear_velocities(static_cast<float>(snapshot.linear_velocities[3 * i + k]));
      frame.add_angular_velocities(static_cast<float>(snapshot.angular_velocities[3 * i + k]));
    }
    for (std::size_t k = 0; k < 4; ++k) frame.add_orientations(static_cast<float>(snapshot.orientations[4 * i + k]));
  }
  return std::make_shared<const std::string>(wire::encode_frame(message));
}

void Publisher::update_periods() {
  std::vector<std::uint32_t> periods;
  for (const Stream& stream : streams_) periods.push_back(stream.period_ticks);
  std::sort(periods.begin(), periods.end());
  periods.erase(std::unique(periods.begin(), periods.end()), periods.end());
  sim_.set_publish_periods(std::move(periods));
}

}  // namespace tumble::net
