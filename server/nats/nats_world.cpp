#include "nats/nats_world.h"

#include <algorithm>
#include <cmath>

#include "frames/pose_frames.h"
#include "frames/world_events.h"
#include "sim/reply.h"
#include "sim/request_check.h"

namespace tumble::nats {
namespace {

using tumble::v1::ClientMessage;
using tumble::v1::ServerMessage;

// Sleep events need the sim to scan the bodies after every step.
bool is_sleep_event(sim::WorldEventKind kind) {
  return kind == sim::WorldEventKind::body_asleep || kind == sim::WorldEventKind::body_awake;
}

}  // namespace

NatsWorld::NatsWorld(sim::Simulation& sim, NatsLink& link, NatsWorldConfig config, spdlog::logger& log)
    : sim_(sim),
      link_(link),
      config_(std::move(config)),
      log_(log),
      server_id_(config_.server_id.empty() ? make_server_id() : config_.server_id) {
  for (const StreamSpec& spec : config_.streams) {
    streams_.emplace_back(spec, poses_subject(config_.world, spec.name), config_.key_interval_s,
                          config_.rest_key_interval_s);
  }
}

NatsWorld::~NatsWorld() { stop(); }

sim::Status NatsWorld::start() {
  // The period is a whole number of ticks, so the rate is rounded to a divisor of the tick rate.
  const double tick_rate = sim_.tick_rate_hz();
  std::vector<sim::PublishInterest> interest;
  for (Stream& stream : streams_) {
    stream.period_ticks = static_cast<std::uint32_t>(std::clamp(std::round(tick_rate / stream.spec.rate_hz), 1.0, 1e6));
    stream.last_tick = sim_.tick();
    interest.push_back({stream.period_ticks, true, {}, stream.spec.joints});
  }
  source_ = sim_.add_publish_source();
  sim_.set_publish_interest(std::move(interest), 0, source_);
  sim_.set_sleep_events_wanted(config_.sleep_events, source_);
  sim_.add_snapshot_listener([this](std::shared_ptr<const sim::Snapshot> snapshot) {
    if (!snapshot->all_bodies) return;  // another consumer's bodies; every stream here reads the whole world
    std::lock_guard lock(mutex_);
    latest_ = std::move(snapshot);
    wake_.notify_one();
  });
  sim_.add_event_listener(
      [this](std::shared_ptr<const sim::WorldEvents> events) { post([this, events] { publish_events(*events); }); });
  sim_.add_stats_hook([this](tumble::v1::Stats* stats) { link_.fill(config_.world, stats->mutable_nats()); });

  for (std::size_t i = 0; i < streams_.size(); ++i) {
    const std::string subject = key_subject(config_.world, streams_[i].spec.name);
    auto status = link_.subscribe(subject, "", [this, i](NatsRequest request) {
      link_.count_request();
      if (!request.reply.empty()) post([this, i, reply = std::move(request.reply)] { answer_key(i, reply); });
    });
    if (!status.ok()) return status;
  }
  if (auto status = link_.subscribe(rpc_subject(config_.world), rpc_queue_group(config_.world),
                                    [this](NatsRequest request) { answer_rpc(std::move(request), false); });
      !status.ok()) {
    return status;
  }
  if (auto status = link_.subscribe(query_subject(config_.world), rpc_queue_group(config_.world),
                                    [this](NatsRequest request) { answer_rpc(std::move(request), true); });
      !status.ok()) {
    return status;
  }
  if (auto status = link_.subscribe(std::string(kWorldsSubject), "",
                                    [this](NatsRequest request) {
                                      link_.count_request();
                                      if (request.reply.empty()) return;
                                      publish_to(request.reply, world_info().SerializeAsString());
                                    });
      !status.ok()) {
    return status;
  }
  thread_ = std::thread([this] { run(); });
  return {};
}

void NatsWorld::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    wake_.notify_one();
  }
  if (thread_.joinable()) thread_.join();
}

tumble::v1::WorldInfo NatsWorld::world_info() const {
  tumble::v1::WorldInfo info;
  info.set_world(config_.world);
  info.set_tick(sim_.tick());
  info.set_tick_rate_hz(sim_.tick_rate_hz());
  info.set_bodies(sim_.body_count());
  info.set_paused(sim_.paused());
  info.set_version(config_.version);
  for (const StreamSpec& spec : config_.streams) {
    tumble::v1::NatsStreamInfo& stream = *info.add_streams();
    stream.set_name(spec.name);
    stream.set_subject(poses_subject(config_.world, spec.name));
    stream.set_encoding(spec.encoding);
    stream.set_rate_hz(spec.rate_hz);
    stream.set_fields(spec.velocities ? tumble::v1::POSE_FIELDS_POSE_AND_VELOCITY : tumble::v1::POSE_FIELDS_POSE);
    stream.set_joints(spec.joints);
    if (spec.encoding == tumble::v1::POSE_ENCODING_DELTA) {
      stream.set_key_interval_s(config_.key_interval_s);
      stream.set_rest_key_interval_s(config_.rest_key_interval_s);
    }
  }
  info.set_events_subject(events_subject(config_.world));
  info.set_rpc_subject(rpc_subject(config_.world));
  info.set_query_subject(query_subject(config_.world));
  info.set_server_id(server_id_);
  if (config_.lease != nullptr) {
    info.set_epoch(config_.lease->epoch());
    info.set_leader_id(server_id_);
  }
  return info;
}

bool NatsWorld::post(std::function<void()> work) {
  std::lock_guard lock(mutex_);
  if (work_.size() >= config_.max_queued) return false;
  work_.push_back(std::move(work));
  wake_.notify_one();
  return true;
}

void NatsWorld::run() {
  std::deque<std::function<void()>> work;
  for (;;) {
    std::shared_ptr<const sim::Snapshot> snapshot;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [this] { return stopping_ || latest_ || !work_.empty(); });
      if (stopping_) return;
      snapshot = std::move(latest_);
      work.swap(work_);
    }
    for (auto& item : work) item();
    work.clear();
    if (snapshot) publish(*snapshot);
  }
}

void NatsWorld::publish(const sim::Snapshot& snapshot) {
  for (Stream& stream : streams_) {
    // Regular frames fall on multiples of the period; a frame whose
    // snapshot was superseded is made up by the next one; an edit while
    // paused is shown at once.
    const bool regular =
        (snapshot.tick > stream.last_tick &&
         (snapshot.tick % stream.period_ticks == 0 || snapshot.tick - stream.last_tick > stream.period_ticks)) ||
        (snapshot.out_of_band && snapshot.tick >= stream.last_tick) || !stream.any_frame;
    if (!regular) continue;
    // Taken before the sim knew of this source's interest: the next one has them.
    if (stream.spec.joints && !snapshot.has_joints) continue;
    publish_frame(stream, snapshot);
    stream.last_tick = snapshot.tick;
    stream.any_frame = true;
  }
}

void NatsWorld::publish_frame(Stream& stream, const sim::Snapshot& snapshot) {
  const SequencePlanner::Frame plan = stream.planner.next(snapshot.sim_time);
  ServerMessage message;
  tumble::v1::PoseFrame& frame = *message.mutable_pose_frame();
  frame.set_tick(snapshot.tick);
  frame.set_sim_time(snapshot.sim_time);
  frame.set_sequence(plan.sequence);
  if (config_.lease != nullptr) frame.set_epoch(config_.lease->epoch());
  const bool velocities = stream.spec.velocities;
  static const std::vector<physics::BodyId> kNoFilter;
  switch (stream.spec.encoding) {
    case tumble::v1::POSE_ENCODING_DELTA: {
      std::vector<wire::QuantizedBody> bodies = stream.memo.quantize(snapshot, true, kNoFilter, velocities);
      if (plan.key) {
        frames::fill_delta_key(bodies, velocities, &frame);
      } else {
        frames::fill_delta_change(stream.latest_bodies, bodies, velocities, &frame, &stream.changed);
        if (!stream.changed.empty() || frame.removed_ids_size() > 0) stream.planner.changed();
      }
      stream.latest_bodies = std::move(bodies);
      break;
    }
    case tumble::v1::POSE_ENCODING_QUANTIZED:
      stream.latest_bodies = stream.memo.quantize(snapshot, true, kNoFilter, velocities);
      frames::fill_quantized(stream.latest_bodies, velocities, &frame);
      break;
    default:
      frame.set_encoding(tumble::v1::POSE_ENCODING_FULL);
      frames::fill_full(snapshot, true, kNoFilter, velocities, &frame);
      break;
  }
  if (stream.spec.joints) {
    stream.latest_joints.Clear();
    frames::fill_joints(snapshot, &stream.latest_joints);
    frame.MergeFrom(stream.latest_joints);
  }
  stream.latest_sequence = plan.sequence;
  stream.latest_tick = snapshot.tick;
  stream.latest_sim_time = snapshot.sim_time;
  std::string bytes = message.SerializeAsString();
  const NatsLink::Sent sent = publish_to(stream.subject, bytes);
  if (stream.spec.encoding == tumble::v1::POSE_ENCODING_FULL) stream.latest_full = std::move(bytes);
  if (sent != NatsLink::Sent::ok) {
    stream.planner.lost();
    note_drop(stream, sent,
              stream.spec.encoding == tumble::v1::POSE_ENCODING_FULL ? stream.latest_full.size() : bytes.size());
  }
}

void NatsWorld::note_drop(Stream& stream, NatsLink::Sent why, std::size_t bytes) {
  link_.count_dropped_frame();
  ++stream.drops_since_log;
  const auto now = std::chrono::steady_clock::now();
  if (now - stream.last_drop_log < std::chrono::seconds(1)) return;
  stream.last_drop_log = now;
  if (why == NatsLink::Sent::too_large) {
    log_.warn(
        "NATS stream {}: a frame of {} bytes is over the server's max payload of {} bytes; not published ({} "
        "frame(s) dropped since the last line)",
        stream.spec.name, bytes, link_.max_payload(), stream.drops_since_log);
  } else if (why == NatsLink::Sent::down) {
    log_.debug("NATS stream {}: the link is down; {} frame(s) not published since the last line", stream.spec.name,
               stream.drops_since_log);
  } else {
    log_.warn("NATS stream {}: publishing failed; {} frame(s) dropped since the last line", stream.spec.name,
              stream.drops_since_log);
  }
  stream.drops_since_log = 0;
}

void NatsWorld::publish_events(const sim::WorldEvents& events) {
  const std::string subject = events_subject(config_.world);
  for (const sim::WorldEvent& event : events) {
    if (is_sleep_event(event.kind) && !config_.sleep_events) continue;
    ServerMessage message;
    frames::fill_world_event(event, 0, message.mutable_world_event());
    publish_to(subject, message.SerializeAsString());
  }
}

void NatsWorld::answer_key(std::size_t index, const std::string& reply) {
  Stream& stream = streams_[index];
  if (!stream.any_frame) {
    ServerMessage error;
    error.mutable_error()->set_code(tumble::v1::FAILED_PRECONDITION);
    error.mutable_error()->set_message("stream " + stream.spec.name + " has no frame yet");
    publish_to(reply, error.SerializeAsString());
    return;
  }
  if (stream.spec.encoding == tumble::v1::POSE_ENCODING_FULL) {
    publish_to(reply, stream.latest_full);
    return;
  }
  ServerMessage message;
  tumble::v1::PoseFrame& frame = *message.mutable_pose_frame();
  frame.set_tick(stream.latest_tick);
  frame.set_sim_time(stream.latest_sim_time);
  frame.set_sequence(stream.latest_sequence);
  if (config_.lease != nullptr) frame.set_epoch(config_.lease->epoch());
  if (stream.spec.encoding == tumble::v1::POSE_ENCODING_DELTA) {
    frames::fill_delta_key(stream.latest_bodies, stream.spec.velocities, &frame);
  } else {
    frames::fill_quantized(stream.latest_bodies, stream.spec.velocities, &frame);
  }
  frame.MergeFrom(stream.latest_joints);
  send_reply(reply, message, 0);
}

void NatsWorld::answer_rpc(NatsRequest request, bool read_only) {
  link_.count_request();
  const std::string subject = read_only ? query_subject(config_.world) : rpc_subject(config_.world);
  ClientMessage message;
  if (!message.ParseFromString(request.data)) {
    ServerMessage error;
    error.mutable_error()->set_code(tumble::v1::INVALID_ARGUMENT);
    error.mutable_error()->set_message("the payload on " + subject + " is not a ClientMessage; nothing was applied");
    if (!request.reply.empty()) publish_to(request.reply, error.SerializeAsString());
    return;
  }
  const auto answer = [&](const ServerMessage& reply) {
    if (!request.reply.empty()) send_reply(request.reply, reply, message.request_id());
  };
  const ClientMessage::KindCase kind = message.kind_case();
  if (read_only && kind != ClientMessage::kHello && kind != ClientMessage::kListBodies &&
      kind != ClientMessage::kListJoints && kind != ClientMessage::kGetStats) {
    answer(sim::error_reply(message, tumble::v1::PERMISSION_DENIED,
                            subject +
                                " takes Hello, ListBodies, ListJoints and GetStats, which change nothing; commands go "
                                "to " +
                                rpc_subject(config_.world) + ", which NATS may let only controllers publish to"));
    return;
  }
  switch (kind) {
    case ClientMessage::kHello: {
      if (auto problem = sim::check_hello(message.hello())) {
        answer(sim::error_reply(message, problem->code, problem->message));
        return;
      }
      ServerMessage reply;
      auto& welcome = *reply.mutable_welcome();
      welcome.set_protocol_version(tumble::v1::PROTOCOL_VERSION_CURRENT);
      welcome.set_server_version(config_.version);
      welcome.set_tick_rate_hz(sim_.tick_rate_hz());
      welcome.set_tick(sim_.tick());
      welcome.set_sim_time(sim_.sim_time());
      welcome.set_body_count(sim_.body_count());
      // On .query the asker may be anyone; on .rpc NATS let it send commands.
      welcome.set_role(read_only ? tumble::v1::ROLE_OBSERVER : tumble::v1::ROLE_CONTROLLER);
      answer(reply);
      return;
    }
    case ClientMessage::kSubscribe:
    case ClientMessage::kUnsubscribe:
    case ClientMessage::kKeyFrameRequest: {
      std::string streams;
      for (const StreamSpec& spec : config_.streams) streams += (streams.empty() ? "" : ", ") + spec.name;
      answer(sim::error_reply(message, tumble::v1::INVALID_ARGUMENT,
                              "subscriptions are not made over " + rpc_subject(config_.world) + ": subscribe on " +
                                  poses_subject(config_.world, config_.streams.front().name) + " (streams: " + streams +
                                  "; a key frame: request on " + key_subject(config_.world, "<stream>") + ")"));
      return;
    }
    default:
      break;
  }
  if (auto problem = sim::check_request(message)) {
    answer(sim::error_reply(message, problem->code, problem->message));
    return;
  }
  sim::Command command;
  command.message = std::move(message);
  if (!request.reply.empty()) {
    // The reply comes on the sim thread, which must not publish: the publishing thread sends it.
    command.reply = [this, reply = std::move(request.reply), id = command.message.request_id()](ServerMessage out) {
      auto shared = std::make_shared<ServerMessage>(std::move(out));
      if (!post([this, reply, shared, id] { send_reply(reply, *shared, id); })) {
        log_.warn("NATS: a reply to {} was dropped: the publishing thread is {} tasks behind", reply,
                  config_.max_queued);
      }
    };
  }
  sim_.submit(std::move(command));
}

NatsLink::Sent NatsWorld::publish_to(const std::string& subject, std::string_view data) {
  if (config_.lease != nullptr && !config_.lease->held()) return NatsLink::Sent::down;
  return link_.publish(subject, data);
}

void NatsWorld::send_reply(const std::string& reply, const ServerMessage& message, std::uint64_t request_id) {
  const std::string bytes = message.SerializeAsString();
  if (publish_to(reply, bytes) != NatsLink::Sent::too_large) return;
  ServerMessage error;
  error.mutable_error()->set_request_id(request_id);
  error.mutable_error()->set_code(tumble::v1::RESOURCE_EXHAUSTED);
  error.mutable_error()->set_message(
      "the reply of " + std::to_string(bytes.size()) + " bytes is over the NATS server's max payload of " +
      std::to_string(link_.max_payload()) + " bytes; ask for less (ListBodies.max_bodies)");
  publish_to(reply, error.SerializeAsString());
}

}  // namespace tumble::nats
