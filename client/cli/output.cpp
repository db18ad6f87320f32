#include "output.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

namespace tumble::cli {
namespace {

// `value` with `decimals` digits after the point; a value that rounds to
// zero prints without a minus sign.
std::string fixed(double value, int decimals) {
  char text[64];
  const int length = std::snprintf(text, sizeof text, "%.*f", decimals, value);
  std::string out(text, static_cast<std::size_t>(std::clamp(length, 0, static_cast<int>(sizeof text) - 1)));
  if (out.size() > 1 && out.front() == '-' && out.find_first_not_of("0.", 1) == std::string::npos) out.erase(0, 1);
  return out;
}

// "(x, y, z)" or "[w, x, y, z]" with the given brackets and decimals.
template <typename Values>
std::string tuple(const Values& values, int decimals, char open, char close) {
  std::string out(1, open);
  bool first = true;
  for (const auto value : values) {
    if (!first) out += ", ";
    out += fixed(static_cast<double>(value), decimals);
    first = false;
  }
  out += close;
  return out;
}

// The double nearest to the shortest decimal that reads back as `value`,
// so JSON shows 0.1 for 0.1f rather than 0.10000000149011612.
double shortest(float value) {
  if (!std::isfinite(value)) return static_cast<double>(value);
  char text[32];
  const auto written = std::to_chars(text, text + sizeof text, value);
  double out = 0;
  std::from_chars(text, written.ptr, out);
  return out;
}

template <std::size_t N>
Json json_array(const std::array<float, N>& values) {
  Json out = Json::array();
  for (float value : values) out.push_back(shortest(value));
  return out;
}

Json json_array(const tumble::v1::Vec3& v) { return Json::array({v.x(), v.y(), v.z()}); }

Json json_array(const tumble::v1::Quat& q) { return Json::array({q.w(), q.x(), q.y(), q.z()}); }

// JointInfo.body_a and WorldEvent.joint_body_a for the world.
constexpr std::uint32_t kWorldBodyId = 0xfffffffe;

std::string display_name(std::uint32_t id, const std::string& name) {
  return name.empty() ? "#" + std::to_string(id) : name;
}

std::string name_of(std::uint32_t id, const BodyNames& names) {
  const auto found = names.find(id);
  return found == names.end() ? std::string() : found->second;
}

std::string pad_right(const std::string& text, std::size_t width) {
  return text + std::string(width - std::min(width, text.size()), ' ');
}

// "label  value" lines, the values aligned, each line after `indent`.
std::string labelled_lines(const std::vector<std::pair<std::string, std::string>>& rows, const std::string& indent) {
  std::size_t width = 0;
  for (const auto& row : rows) width = std::max(width, row.first.size());
  std::string out;
  for (const auto& [label, value] : rows) out += indent + pad_right(label, width) + "  " + value + "\n";
  return out;
}

std::string pad_left(const std::string& text, std::size_t width) {
  return std::string(width - std::min(width, text.size()), ' ') + text;
}

// Rows of cells as lines, each column as wide as its widest cell and
// aligned right or left, two spaces between columns, no trailing spaces.
template <std::size_t Columns>
std::string aligned_table(const std::vector<std::array<std::string, Columns>>& rows,
                          const std::array<bool, Columns>& right_aligned) {
  std::array<std::size_t, Columns> widths{};
  for (const auto& row : rows) {
    for (std::size_t c = 0; c < Columns; ++c) widths[c] = std::max(widths[c], row[c].size());
  }
  std::string out;
  for (const auto& row : rows) {
    std::string line;
    for (std::size_t c = 0; c < Columns; ++c) {
      if (c > 0) line += "  ";
      line += right_aligned[c] ? pad_left(row[c], widths[c]) : pad_right(row[c], widths[c]);
    }
    line.erase(line.find_last_not_of(' ') + 1);
    out += line + "\n";
  }
  return out;
}

// |v| of a pose's linear velocity, m/s.
double speed_of(const client::BodyPose& pose) {
  const double x = static_cast<double>(pose.linear_velocity[0]);
  const double y = static_cast<double>(pose.linear_velocity[1]);
  const double z = static_cast<double>(pose.linear_velocity[2]);
  return std::sqrt(x * x + y * y + z * z);
}

// Appends `value` on one line with a space after each ':' and ',', the
// way the protocol's documentation writes JSON.
void append_json(const Json& value, std::string& out) {
  if (value.is_object()) {
    out += '{';
    bool first = true;
    for (const auto& item : value.items()) {
      if (!first) out += ", ";
      append_json(Json(item.key()), out);
      out += ": ";
      append_json(item.value(), out);
      first = false;
    }
    out += '}';
  } else if (value.is_array()) {
    out += '[';
    bool first = true;
    for (const Json& element : value) {
      if (!first) out += ", ";
      append_json(element, out);
      first = false;
    }
    out += ']';
  } else {
    out += value.dump(-1, ' ', false, Json::error_handler_t::replace);
  }
}

}  // namespace

BodyNames body_names(const tumble::v1::BodyList& list) {
  BodyNames names;
  for (const auto& body : list.bodies()) names[body.id()] = body.name();
  return names;
}

std::string shape_name(const tumble::v1::Shape& shape) {
  switch (shape.kind_case()) {
    case tumble::v1::Shape::kBox:
      return "box";
    case tumble::v1::Shape::kSphere:
      return "sphere";
    case tumble::v1::Shape::kCapsule:
      return "capsule";
    case tumble::v1::Shape::kPoints:
      return "points";
    case tumble::v1::Shape::kPlane:
      return "plane";
    case tumble::v1::Shape::kConvex:
      return "convex";
    case tumble::v1::Shape::KIND_NOT_SET:
      break;
  }
  return "";
}

std::string motion_name(tumble::v1::Motion motion) {
  switch (motion) {
    case tumble::v1::MOTION_STATIC:
      return "static";
    case tumble::v1::MOTION_KINEMATIC:
      return "kinematic";
    default:
      return "dynamic";
  }
}

const char* step_end_word(tumble::v1::StepEnd end) {
  switch (end) {
    case tumble::v1::STEP_END_COMPLETED:
      return "completed";
    case tumble::v1::STEP_END_PAUSE:
      return "pause";
    case tumble::v1::STEP_END_RESUME:
      return "resume";
    case tumble::v1::STEP_END_RESET:
      return "reset";
    default:
      return "unknown";
  }
}

std::string format_ack(const tumble::v1::Ack& ack) {
  return "applied at tick " + std::to_string(ack.applied_tick()) + "\n";
}

Json ack_json(const tumble::v1::Ack& ack) {
  Json out = Json::object();
  if (ack.has_body_id()) out["body_id"] = ack.body_id();
  if (ack.has_joint_id()) out["joint_id"] = ack.joint_id();
  out["applied_tick"] = ack.applied_tick();
  out["request_id"] = ack.request_id();
  if (ack.has_step_ticks_left()) {
    out["step_ended_by"] = step_end_word(ack.step_ended_by());
    out["step_ticks_left"] = ack.step_ticks_left();
  }
  return out;
}

std::string format_spawned(const tumble::v1::Ack& ack) {
  return "spawned body " + std::to_string(ack.body_id()) + " at tick " + std::to_string(ack.applied_tick()) + "\n";
}

std::string format_joint_added(const tumble::v1::Ack& ack) {
  return "added joint " + std::to_string(ack.joint_id()) + " at tick " + std::to_string(ack.applied_tick()) + "\n";
}

std::string format_paused(const tumble::v1::Ack& ack) {
  return "paused at tick " + std::to_string(ack.applied_tick()) + "\n";
}

std::string format_stepped(const tumble::v1::Ack& ack) {
  std::string out = "stepped to tick " + std::to_string(ack.applied_tick());
  switch (ack.step_ended_by()) {
    case tumble::v1::STEP_END_PAUSE:
    case tumble::v1::STEP_END_RESUME:
    case tumble::v1::STEP_END_RESET:
      out += ", cut short by a " + std::string(step_end_word(ack.step_ended_by())) + " with " +
             std::to_string(ack.step_ticks_left()) + " ticks left";
      break;
    default:
      break;
  }
  return out + "\n";
}

std::string format_stats(const tumble::v1::Stats& stats) {
  const std::vector<std::pair<std::string, std::string>> rows = {
      {"tick", std::to_string(stats.tick())},
      {"sim time", fixed(stats.sim_time(), 3) + " s"},
      {"paused", stats.paused() ? "yes" : "no"},
      {"tick rate", fixed(stats.tick_rate_hz(), 3) + " Hz"},
      {"real-time factor", fixed(stats.real_time_factor(), 3)},
      {"tick time p50", fixed(stats.tick_ms_p50(), 3) + " ms"},
      {"tick time p99", fixed(stats.tick_ms_p99(), 3) + " ms"},
      {"tick CPU p50", fixed(stats.tick_cpu_ms_p50(), 3) + " ms"},
      {"tick CPU p99", fixed(stats.tick_cpu_ms_p99(), 3) + " ms"},
      {"late start p50", fixed(stats.tick_start_late_ms_p50(), 3) + " ms"},
      {"late start p99", fixed(stats.tick_start_late_ms_p99(), 3) + " ms"},
      {"overruns", std::to_string(stats.overruns())},
      {"bodies", std::to_string(stats.bodies()) + " (" + std::to_string(stats.bodies_awake()) + " awake, " +
                     std::to_string(stats.bodies_asleep()) + " asleep)"},
      {"bodies diverged", std::to_string(stats.bodies_diverged())},
      {"clients", std::to_string(stats.clients())},
      {"refused clients", std::to_string(stats.connections_refused())},
      {"closed on errors", std::to_string(stats.clients_closed_for_errors())},
      {"bytes sent", std::to_string(stats.bytes_sent())},
  };
  std::string out = labelled_lines(rows, "");
  if (stats.has_checkpoints()) {
    const tumble::v1::Checkpoints& checkpoints = stats.checkpoints();
    const std::vector<std::pair<std::string, std::string>> saved = {
        {"to", checkpoints.destination()},
        {"every", fixed(checkpoints.interval_s(), 3) + " s"},
        {"written", std::to_string(checkpoints.written())},
        {"failed", std::to_string(checkpoints.failed())},
        {"last", checkpoints.written() == 0 ? "-"
                                            : "tick " + std::to_string(checkpoints.last_tick()) + ", " +
                                                  std::to_string(checkpoints.last_bytes()) + " bytes"},
        {"capture",
         fixed(checkpoints.last_capture_ms(), 3) + " ms (longest " + fixed(checkpoints.capture_ms_max(), 3) + " ms)"},
        {"write",
         fixed(checkpoints.last_write_ms(), 3) + " ms (longest " + fixed(checkpoints.write_ms_max(), 3) + " ms)"},
    };
    out += "checkpoints\n" + labelled_lines(saved, "  ");
  }
  if (!stats.has_nats()) return out;
  const tumble::v1::NatsLink& nats = stats.nats();
  const std::vector<std::pair<std::string, std::string>> link = {
      {"world", nats.world()},
      {"connected", nats.connected() ? "yes" : "no"},
      {"server", nats.server_url().empty() ? "-" : nats.server_url()},
      {"messages out", std::to_string(nats.messages_out())},
      {"bytes out", std::to_string(nats.bytes_out())},
      {"reconnects", std::to_string(nats.reconnects())},
      {"requests in", std::to_string(nats.requests_in())},
      {"frames dropped", std::to_string(nats.frames_dropped())},
  };
  out += "nats\n" + labelled_lines(link, "  ");
  return out;
}

Json stats_json(const tumble::v1::Stats& stats) {
  Json out = Json::object();
  out["tick"] = stats.tick();
  out["sim_time"] = stats.sim_time();
  out["paused"] = stats.paused();
  out["tick_rate_hz"] = stats.tick_rate_hz();
  out["real_time_factor"] = stats.real_time_factor();
  out["tick_ms_p50"] = stats.tick_ms_p50();
  out["tick_ms_p99"] = stats.tick_ms_p99();
  out["tick_cpu_ms_p50"] = stats.tick_cpu_ms_p50();
  out["tick_cpu_ms_p99"] = stats.tick_cpu_ms_p99();
  out["tick_start_late_ms_p50"] = stats.tick_start_late_ms_p50();
  out["tick_start_late_ms_p99"] = stats.tick_start_late_ms_p99();
  out["overruns"] = stats.overruns();
  out["bodies"] = stats.bodies();
  out["bodies_awake"] = stats.bodies_awake();
  out["bodies_asleep"] = stats.bodies_asleep();
  out["bodies_diverged"] = stats.bodies_diverged();
  out["clients"] = stats.clients();
  out["connections_refused"] = stats.connections_refused();
  out["clients_closed_for_errors"] = stats.clients_closed_for_errors();
  out["bytes_sent"] = stats.bytes_sent();
  if (stats.has_checkpoints()) {
    const tumble::v1::Checkpoints& checkpoints = stats.checkpoints();
    Json saved = Json::object();
    saved["destination"] = checkpoints.destination();
    saved["interval_s"] = checkpoints.interval_s();
    saved["written"] = checkpoints.written();
    saved["failed"] = checkpoints.failed();
    saved["last_tick"] = checkpoints.last_tick();
    saved["last_bytes"] = checkpoints.last_bytes();
    saved["last_write_ms"] = checkpoints.last_write_ms();
    saved["write_ms_max"] = checkpoints.write_ms_max();
    saved["last_capture_ms"] = checkpoints.last_capture_ms();
    saved["capture_ms_max"] = checkpoints.capture_ms_max();
    out["checkpoints"] = std::move(saved);
  }
  if (stats.has_nats()) {
    const tumble::v1::NatsLink& nats = stats.nats();
    Json link = Json::object();
    link["world"] = nats.world();
    link["connected"] = nats.connected();
    link["server_url"] = nats.server_url();
    link["messages_out"] = nats.messages_out();
    link["bytes_out"] = nats.bytes_out();
    link["reconnects"] = nats.reconnects();
    link["requests_in"] = nats.requests_in();
    link["frames_dropped"] = nats.frames_dropped();
    out["nats"] = std::move(link);
  }
  return out;
}

std::string encoding_name(tumble::v1::PoseEncoding encoding) {
  switch (encoding) {
    case tumble::v1::POSE_ENCODING_FULL:
      return "full";
    case tumble::v1::POSE_ENCODING_QUANTIZED:
      return "quantized";
    case tumble::v1::POSE_ENCODING_DELTA:
      return "delta";
    default:
      break;
  }
  return "";
}

std::string fields_name(tumble::v1::PoseFields fields) {
  return fields == tumble::v1::POSE_FIELDS_POSE_AND_VELOCITY ? "all" : "pose";
}

// The fewest decimals that show `value` (60 as "60", 12.5 as "12.5").
std::string short_number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

std::string stream_spec(const tumble::v1::NatsStreamInfo& stream) {
  std::string spec = stream.name() + "=" + encoding_name(stream.encoding()) + "@" + short_number(stream.rate_hz());
  const bool all = stream.fields() == tumble::v1::POSE_FIELDS_POSE_AND_VELOCITY;
  if (all && stream.joints()) {
    spec += ":all,joints";
  } else if (all) {
    spec += ":all";
  } else if (stream.joints()) {
    spec += ":joints";
  }
  return spec;
}

std::string format_world_table(const std::vector<tumble::v1::WorldInfo>& worlds) {
  if (worlds.empty()) return "no worlds answered\n";
  // Worlds kept in JetStream (--nats-state) have a leader and standbys:
  // two more columns, and a standby is named on its world's row.
  const bool leadership = std::any_of(worlds.begin(), worlds.end(), [](const tumble::v1::WorldInfo& info) {
    return info.epoch() != 0 || info.standby();
  });
  const auto standbys_of = [&](const std::string& world) {
    std::string ids;
    for (const tumble::v1::WorldInfo& info : worlds) {
      if (info.standby() && info.world() == world) ids += (ids.empty() ? "" : " ") + info.server_id();
    }
    return ids.empty() ? std::string("-") : ids;
  };
  const auto leader = [](const std::string& id, std::uint64_t epoch) {
    return id.empty() ? std::string("-") : id + " (epoch " + std::to_string(epoch) + ")";
  };
  constexpr std::size_t kColumns = 7;
  constexpr std::array<bool, kColumns> kRightAligned = {false, true, true, true, false, false, false};
  std::vector<std::array<std::string, kColumns>> rows;
  rows.push_back({"WORLD", "TICK", "RATE (Hz)", "BODIES", "STREAMS", "LEADER", "STANDBYS"});
  std::vector<std::string> led;  // worlds a leader answered for
  for (const tumble::v1::WorldInfo& info : worlds) {
    if (info.standby()) continue;
    std::string streams;
    for (const auto& stream : info.streams()) streams += (streams.empty() ? "" : " ") + stream_spec(stream);
    rows.push_back({info.world(), std::to_string(info.tick()) + (info.paused() ? " (paused)" : ""),
                    short_number(info.tick_rate_hz()), std::to_string(info.bodies()), streams.empty() ? "-" : streams,
                    leader(info.epoch() != 0 ? info.server_id() : "", info.epoch()), standbys_of(info.world())});
    led.push_back(info.world());
  }
  // A world whose leader did not answer (a takeover under way): its standbys' view.
  for (const tumble::v1::WorldInfo& info : worlds) {
    if (!info.standby() || std::find(led.begin(), led.end(), info.world()) != led.end()) continue;
    rows.push_back(
        {info.world(), "-", "-", "-", "-", leader(info.leader_id(), info.epoch()), standbys_of(info.world())});
    led.push_back(info.world());
  }
  if (!leadership) {
    for (auto& row : rows) row[5] = row[6] = "";  // the table ends at STREAMS (trailing blanks are trimmed)
  }
  return aligned_table(rows, kRightAligned);
}

Json world_info_json(const tumble::v1::WorldInfo& info) {
  Json streams = Json::array();
  for (const auto& stream : info.streams()) {
    Json entry = Json::object();
    entry["name"] = stream.name();
    entry["subject"] = stream.subject();
    entry["encoding"] = encoding_name(stream.encoding());
    entry["rate_hz"] = stream.rate_hz();
    entry["fields"] = fields_name(stream.fields());
    entry["joints"] = stream.joints();
    entry["key_interval_s"] = stream.key_interval_s();
    entry["rest_key_interval_s"] = stream.rest_key_interval_s();
    streams.push_back(std::move(entry));
  }
  Json out = Json::object();
  out["world"] = info.world();
  out["tick"] = info.tick();
  out["tick_rate_hz"] = info.tick_rate_hz();
  out["bodies"] = info.bodies();
  out["paused"] = info.paused();
  out["version"] = info.version();
  out["server_id"] = info.server_id();
  out["streams"] = std::move(streams);
  out["events_subject"] = info.events_subject();
  out["rpc_subject"] = info.rpc_subject();
  out["query_subject"] = info.query_subject();
  out["epoch"] = info.epoch();
  out["standby"] = info.standby();
  out["leader_id"] = info.leader_id();
  return out;
}

std::string event_kind_name(tumble::v1::WorldEventKind kind) {
  switch (kind) {
    case tumble::v1::WORLD_EVENT_BODY_SPAWNED:
      return "spawned";
    case tumble::v1::WORLD_EVENT_BODY_REMOVED:
      return "removed";
    case tumble::v1::WORLD_EVENT_BODY_ASLEEP:
      return "asleep";
    case tumble::v1::WORLD_EVENT_BODY_AWAKE:
      return "awake";
    case tumble::v1::WORLD_EVENT_WORLD_RESET:
      return "reset";
    case tumble::v1::WORLD_EVENT_BODY_DIVERGED:
      return "diverged";
    case tumble::v1::WORLD_EVENT_JOINT_ADDED:
      return "joint-added";
    case tumble::v1::WORLD_EVENT_JOINT_REMOVED:
      return "joint-removed";
    case tumble::v1::WORLD_EVENT_JOINT_BROKEN:
      return "joint-broken";
    default:
      break;
  }
  return "";
}

std::string format_world_event(const tumble::v1::WorldEvent& event) {
  std::string out = "tick " + std::to_string(event.tick()) + "  " + event_kind_name(event.kind());
  if (event.has_joint_id()) {
    out += "  " + display_name(event.joint_id(), event.joint_name());
    if (!event.joint_name().empty()) out += " (#" + std::to_string(event.joint_id()) + ")";
    const std::string body_a =
        event.joint_body_a() == kWorldBodyId ? std::string("world") : "#" + std::to_string(event.joint_body_a());
    return out + "  " + body_a + " - #" + std::to_string(event.body_id()) + "\n";
  }
  if (event.kind() != tumble::v1::WORLD_EVENT_WORLD_RESET) {
    out += "  " + display_name(event.body_id(), event.body_name());
    if (!event.body_name().empty()) out += " (#" + std::to_string(event.body_id()) + ")";
  }
  return out + "\n";
}

Json world_event_json(const tumble::v1::WorldEvent& event) {
  Json out = Json::object();
  out["event"] = event_kind_name(event.kind());
  out["tick"] = event.tick();
  if (event.has_joint_id()) {
    out["joint_id"] = event.joint_id();
    out["joint_name"] = event.joint_name();
    out["body_a"] = event.joint_body_a() == kWorldBodyId ? Json(nullptr) : Json(event.joint_body_a());
    out["body_b"] = event.body_id();
    return out;
  }
  if (event.kind() != tumble::v1::WORLD_EVENT_WORLD_RESET) {
    out["id"] = event.body_id();
    out["name"] = event.body_name();
  }
  return out;
}

std::string format_body_table(const tumble::v1::BodyList& list) {
  constexpr std::size_t kColumns = 8;
  using Row = std::array<std::string, kColumns>;
  // Numbers line up on the right, words on the left.
  constexpr std::array<bool, kColumns> kRightAligned = {true, false, false, false, true, false, true, false};

  std::vector<Row> rows;
  rows.push_back({"ID", "NAME", "SHAPE", "MOTION", "MASS (kg)", "POSITION (m)", "SPEED (m/s)", "ASLEEP"});
  for (const auto& body : list.bodies()) {
    const auto& p = body.position();
    const auto& v = body.linear_velocity();
    const double speed = std::sqrt(v.x() * v.x() + v.y() * v.y() + v.z() * v.z());
    const std::string shape = shape_name(body.shape());
    rows.push_back({std::to_string(body.id()), display_name(body.id(), body.name()), shape.empty() ? "-" : shape,
                    motion_name(body.motion()), fixed(body.mass(), 3),
                    tuple(std::array{p.x(), p.y(), p.z()}, 3, '(', ')'), fixed(speed, 3),
                    body.asleep() ? "yes" : "no"});
  }

  return aligned_table(rows, kRightAligned);
}

Json body_list_json(const tumble::v1::BodyList& list) {
  Json bodies = Json::array();
  for (const auto& body : list.bodies()) {
    Json entry = Json::object();
    entry["id"] = body.id();
    entry["name"] = body.name();
    const std::string shape = shape_name(body.shape());
    entry["shape"] = shape.empty() ? Json(nullptr) : Json(shape);
    entry["motion"] = motion_name(body.motion());
    entry["mass"] = body.mass();
    entry["position"] = json_array(body.position());
    entry["orientation"] = json_array(body.orientation());
    entry["linear_velocity"] = json_array(body.linear_velocity());
    entry["angular_velocity"] = json_array(body.angular_velocity());
    entry["asleep"] = body.asleep();
    bodies.push_back(std::move(entry));
  }
  Json out = Json::object();
  out["tick"] = list.tick();
  out["bodies"] = std::move(bodies);
  return out;
}

std::string joint_type_name(tumble::v1::JointType type) {
  switch (type) {
    case tumble::v1::JOINT_TYPE_BALL:
      return "ball";
    case tumble::v1::JOINT_TYPE_HINGE:
      return "hinge";
    case tumble::v1::JOINT_TYPE_SLIDER:
      return "slider";
    case tumble::v1::JOINT_TYPE_FIXED:
      return "fixed";
    case tumble::v1::JOINT_TYPE_DISTANCE:
      return "distance";
    default:
      return "";
  }
}

std::string format_joint_table(const tumble::v1::JointList& list) {
  constexpr std::size_t kColumns = 8;
  using Row = std::array<std::string, kColumns>;
  constexpr std::array<bool, kColumns> kRightAligned = {true, false, false, false, false, true, true, false};

  std::vector<Row> rows;
  rows.push_back({"ID", "NAME", "TYPE", "BODY A", "BODY B", "POSITION", "SPEED", "MOTOR"});
  for (const auto& joint : list.joints()) {
    const auto& motor = joint.motor();
    std::string drive = "-";
    if (motor.target_case() != tumble::v1::JointMotorSpec::TARGET_NOT_SET) {
      drive = motor.has_speed() ? "speed " + fixed(motor.speed(), 3) : "position " + fixed(motor.position(), 3);
      drive += " max " + fixed(motor.has_max_torque() ? motor.max_torque() : motor.max_force(), 3);
    }
    const std::string type = joint_type_name(joint.type());
    rows.push_back({std::to_string(joint.id()), display_name(joint.id(), joint.name()), type.empty() ? "-" : type,
                    display_name(joint.body_a(), joint.body_a_name()),
                    display_name(joint.body_b(), joint.body_b_name()), fixed(joint.state().position(), 3),
                    fixed(joint.state().speed(), 3), drive});
  }
  return aligned_table(rows, kRightAligned);
}

Json joint_list_json(const tumble::v1::JointList& list) {
  Json joints = Json::array();
  for (const auto& joint : list.joints()) {
    Json entry = Json::object();
    entry["id"] = joint.id();
    entry["name"] = joint.name();
    const std::string type = joint_type_name(joint.type());
    entry["type"] = type.empty() ? Json(nullptr) : Json(type);
    entry["body_a"] = joint.body_a() == kWorldBodyId ? Json(nullptr) : Json(joint.body_a());
    entry["body_a_name"] = joint.body_a_name();
    entry["body_b"] = joint.body_b();
    entry["body_b_name"] = joint.body_b_name();
    entry["anchor_a"] = json_array(joint.anchor_a());
    entry["anchor_b"] = json_array(joint.anchor_b());
    entry["axis"] = json_array(joint.axis());
    entry["limits"] =
        joint.has_limits() ? Json::array({joint.limits().lower(), joint.limits().upper()}) : Json(nullptr);
    entry["cone_limit"] = joint.has_cone_limit() ? Json(joint.cone_limit()) : Json(nullptr);
    entry["length"] = joint.length();
    entry["min_length"] = joint.min_length();
    entry["max_length"] = joint.max_length();
    entry["spring"] = joint.has_spring()
                          ? Json({{"hertz", joint.spring().hertz()}, {"damping_ratio", joint.spring().damping_ratio()}})
                          : Json(nullptr);
    Json motor = nullptr;
    const auto& m = joint.motor();
    if (m.target_case() != tumble::v1::JointMotorSpec::TARGET_NOT_SET) {
      motor = Json::object();
      if (m.has_speed()) motor["speed"] = m.speed();
      if (m.has_position()) {
        motor["position"] = m.position();
        motor["hertz"] = m.hertz();
        motor["damping_ratio"] = m.damping_ratio();
      }
      if (m.has_max_torque()) motor["max_torque"] = m.max_torque();
      if (m.has_max_force()) motor["max_force"] = m.max_force();
    }
    entry["motor"] = std::move(motor);
    entry["break_force"] = joint.has_break_force() ? Json(joint.break_force()) : Json(nullptr);
    entry["break_torque"] = joint.has_break_torque() ? Json(joint.break_torque()) : Json(nullptr);
    entry["friction"] = joint.friction();
    entry["collide_connected"] = joint.collide_connected();
    const auto& state = joint.state();
    Json state_json = Json::object();
    state_json["position"] = state.position();
    state_json["speed"] = state.speed();
    state_json["force"] = json_array(state.force());
    state_json["torque"] = json_array(state.torque());
    state_json["motor_impulse"] = state.motor_impulse();
    entry["state"] = std::move(state_json);
    joints.push_back(std::move(entry));
  }
  Json out = Json::object();
  out["tick"] = list.tick();
  out["joints"] = std::move(joints);
  return out;
}

std::string format_pose_sample(const client::PoseSample& sample, const BodyNames& names) {
  std::string out = "tick " + std::to_string(sample.tick) + "  t=" + fixed(sample.sim_time, 3) + "s\n";
  std::vector<std::string> labels;
  std::size_t width = 0;
  for (const client::BodyPose& pose : sample.bodies) {
    labels.push_back(display_name(pose.id, name_of(pose.id, names)));
    width = std::max(width, labels.back().size());
  }
  for (std::size_t i = 0; i < sample.bodies.size(); ++i) {
    const client::BodyPose& pose = sample.bodies[i];
    out += "  " + pad_right(labels[i], width) + "  pos " + tuple(pose.position, 3, '(', ')') + "  quat " +
           tuple(pose.orientation, 4, '[', ']');
    if (sample.has_velocities) {
      out += "  v " + tuple(pose.linear_velocity, 3, '(', ')') + "  w " + tuple(pose.angular_velocity, 3, '(', ')');
    }
    out += "\n";
  }
  for (const client::JointSample& joint : sample.joints) {
    out += "  joint #" + std::to_string(joint.id) + "  position " + fixed(joint.position, 3) + "  speed " +
           fixed(joint.speed, 3) + "  motor impulse " + fixed(joint.motor_impulse, 3) + "\n";
  }
  return out;
}

Json pose_sample_json(const client::PoseSample& sample, const BodyNames& names) {
  Json bodies = Json::array();
  for (const client::BodyPose& pose : sample.bodies) {
    Json entry = Json::object();
    entry["id"] = pose.id;
    entry["name"] = name_of(pose.id, names);
    entry["position"] = json_array(pose.position);
    entry["orientation"] = json_array(pose.orientation);
    if (sample.has_velocities) {
      entry["linear_velocity"] = json_array(pose.linear_velocity);
      entry["angular_velocity"] = json_array(pose.angular_velocity);
    }
    bodies.push_back(std::move(entry));
  }
  Json out = Json::object();
  out["tick"] = sample.tick;
  out["time"] = sample.sim_time;
  out["bodies"] = std::move(bodies);
  if (!sample.joints.empty()) {
    Json joints = Json::array();
    for (const client::JointSample& joint : sample.joints) {
      joints.push_back({{"id", joint.id},
                        {"position", joint.position},
                        {"speed", joint.speed},
                        {"motor_impulse", joint.motor_impulse}});
    }
    out["joints"] = std::move(joints);
  }
  return out;
}

std::string format_watch_table(const client::PoseSample& sample, const WatchState& state) {
  constexpr std::size_t kColumns = 4;
  using Row = std::array<std::string, kColumns>;
  constexpr std::array<bool, kColumns> kRightAligned = {false, false, true, false};
  std::vector<Row> rows;
  rows.push_back({"NAME", "POSITION (m)", "SPEED (m/s)", "ASLEEP"});
  for (const client::BodyPose& pose : sample.bodies) {
    rows.push_back({display_name(pose.id, state.name(pose.id)), tuple(pose.position, 3, '(', ')'),
                    fixed(speed_of(pose), 3), state.asleep(pose.id) ? "yes" : "no"});
  }
  return "tick " + std::to_string(sample.tick) + "  t=" + fixed(sample.sim_time, 3) + "s\n" +
         aligned_table(rows, kRightAligned);
}

Json watch_json(const client::PoseSample& sample, const WatchState& state) {
  Json bodies = Json::array();
  for (const client::BodyPose& pose : sample.bodies) {
    Json entry = Json::object();
    entry["id"] = pose.id;
    entry["name"] = state.name(pose.id);
    entry["position"] = json_array(pose.position);
    entry["speed"] = speed_of(pose);
    entry["asleep"] = state.asleep(pose.id);
    bodies.push_back(std::move(entry));
  }
  Json out = Json::object();
  out["tick"] = sample.tick;
  out["time"] = sample.sim_time;
  out["bodies"] = std::move(bodies);
  return out;
}

std::string json_line(const Json& value) {
  std::string out;
  append_json(value, out);
  out += '\n';
  return out;
}

}  // namespace tumble::cli
