// What `tumble` prints: replies and pose samples as text for people or as
// JSON for programs. Pure functions of their arguments; the caller writes
// the result and flushes.
//
// Text: positions, velocities and masses with 3 decimals, quaternions with 4,
// as [w, x, y, z]. JSON: one object per line; vectors as [x, y, z],
// quaternions as [w, x, y, z]; float32 pose values are written with the
// fewest digits that read back as the same float (0.1f prints 0.1).
#pragma once

#include <cstdint>
#include <string>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "tumble/v1/protocol.pb.h"
#include "tumble/v1/world_info.pb.h"
#include "tumble_client/pose_sample.h"
#include "watch_state.h"

namespace tumble::cli {

// JSON objects keep their keys in the order they were written.
using Json = nlohmann::ordered_json;

// Body names by id, for output that shows names where frames carry ids.
using BodyNames = std::unordered_map<std::uint32_t, std::string>;

// The names in a BodyList.
BodyNames body_names(const tumble::v1::BodyList& list);

// "box", "sphere", "capsule", "points", "plane" or "convex"; "" when the
// shape is not set.
std::string shape_name(const tumble::v1::Shape& shape);

// "dynamic", "static" or "kinematic" (a value this version does not know:
// "dynamic", the wire's default).
std::string motion_name(tumble::v1::Motion motion);

// "applied at tick 1234\n".
std::string format_ack(const tumble::v1::Ack& ack);

// {"applied_tick": N, "request_id": R}, with "body_id" or "joint_id" first
// when the Ack carries one (SpawnBody, AddJoint), and "step_ended_by" (step_end_word) and
// "step_ticks_left" last when it answers a Step.
Json ack_json(const tumble::v1::Ack& ack);

// What ended a Step, in one word: "completed", "pause", "resume", "reset".
const char* step_end_word(tumble::v1::StepEnd end);

// "spawned body 7 at tick 1234\n".
std::string format_spawned(const tumble::v1::Ack& ack);

// "added joint 3 at tick 1234\n".
std::string format_joint_added(const tumble::v1::Ack& ack);

// "paused at tick 1234\n".
std::string format_paused(const tumble::v1::Ack& ack);

// "stepped to tick 1234\n", or, for a Step another client's request cut
// short, "stepped to tick 1234, cut short by a resume with 766 ticks left\n".
std::string format_stepped(const tumble::v1::Ack& ack);

// One "label  value" line per figure: tick, sim time, paused, tick rate,
// real-time factor, tick time p50/p99, tick CPU p50/p99, late start
// p50/p99 (ms), overruns, bodies (awake, asleep), bodies diverged, clients, bytes sent;
// then, when the server publishes into NATS, a "nats" line and its link
// indented under it: world, connected, server, messages and bytes out,
// reconnects, requests in, frames dropped.
std::string format_stats(const tumble::v1::Stats& stats);

// {"tick", "sim_time", "paused", "tick_rate_hz", "real_time_factor",
// "tick_ms_p50", "tick_ms_p99", "tick_cpu_ms_p50", "tick_cpu_ms_p99",
// "tick_start_late_ms_p50", "tick_start_late_ms_p99", "overruns",
// "bodies", "bodies_awake", "bodies_asleep", "bodies_diverged", "clients", "bytes_sent"},
// and "nats": {"world", "connected", "server_url", "messages_out",
// "bytes_out", "reconnects", "requests_in", "frames_dropped"} when the
// server publishes into NATS.
Json stats_json(const tumble::v1::Stats& stats);

// "full", "quantized" or "delta"; "" for an unknown encoding.
std::string encoding_name(tumble::v1::PoseEncoding encoding);

// A stream as tumbled's --nats-stream spells it: "q60=quantized@60",
// with ":all" when it carries velocities.
std::string stream_spec(const tumble::v1::NatsStreamInfo& stream);

// `tumble worlds`: an aligned table, one header line and one line per
// world: world, tick (with "(paused)"), tick rate (Hz), bodies, and its
// streams as stream_spec() writes them; "no worlds answered" when empty.
std::string format_world_table(const std::vector<tumble::v1::WorldInfo>& worlds);

// {"world", "tick", "tick_rate_hz", "bodies", "paused", "version",
// "server_id", "streams": [{"name", "subject", "encoding", "rate_hz",
// "fields", "key_interval_s"}], "events_subject", "rpc_subject", "query_subject"}.
Json world_info_json(const tumble::v1::WorldInfo& info);

// "spawned", "removed", "asleep", "awake", "reset", "diverged",
// "joint-added", "joint-removed" or "joint-broken"; "" for an unknown kind.
std::string event_kind_name(tumble::v1::WorldEventKind kind);

// "tick 1234  spawned  crate (#7)\n", or "tick 1234  reset\n", or for a
// joint "tick 1234  joint-broken  hinge (#3)  #4294967294 - #7\n" (its
// bodies A and B by id, "world" for the world).
std::string format_world_event(const tumble::v1::WorldEvent& event);

// {"event": "spawned", "tick": N, "id": 7, "name": "crate"}; a reset has
// only "event" and "tick"; a joint's {"event", "tick", "joint_id",
// "joint_name", "body_a", "body_b"} (body_a null for the world).
Json world_event_json(const tumble::v1::WorldEvent& event);

// An aligned table, one header line and one line per body: id, name,
// shape, mass (kg), position (m) and speed (m/s).
std::string format_body_table(const tumble::v1::BodyList& list);

// {"tick": N, "bodies": [{"id", "name", "shape", "mass", "position",
// "orientation", "linear_velocity", "angular_velocity"}, ...]}; "shape" is
// null when not set.
Json body_list_json(const tumble::v1::BodyList& list);

// "ball", "hinge", "slider", "fixed" or "distance"; "" for an unknown type.
std::string joint_type_name(tumble::v1::JointType type);

// An aligned table, one header line and one line per joint: id, name,
// type, body A, body B (names, #id when unnamed), position (rad or m),
// speed and motor ("-", "speed S max M" or "position P max M").
std::string format_joint_table(const tumble::v1::JointList& list);

// {"tick": N, "joints": [{"id", "name", "type", "body_a", "body_a_name",
// "body_b", "body_b_name", "anchor_a", "anchor_b", "axis", "limits"
// ([lower, upper] or null), "cone_limit", "length", "min_length",
// "max_length", "spring", "motor" (null, or {"speed" or "position",
// "hertz", "damping_ratio", "max_torque" or "max_force"}), "break_force",
// "break_torque", "friction" (0: none), "collide_connected", "state":
// {"position", "speed", "force", "torque", "motor_impulse"}}, ...]}; limits
// and breaking the joint does not have are null; body_a is null for the
// world.
Json joint_list_json(const tumble::v1::JointList& list);

// "tick 1234  t=5.142s\n", then one line per body:
// "  crate  pos (x, y, z)  quat [w, x, y, z]  v (x, y, z)  w (x, y, z)\n"
// (without v and w for a pose-only sample), then one line per joint when
// the subscription asked for them: "  joint #3  position 0.250  speed
// 0.500  motor impulse 0.000\n". Bodies without a known name show as #id.
std::string format_pose_sample(const client::PoseSample& sample, const BodyNames& names);

// {"tick": N, "time": S, "bodies": [{"id", "name", "position",
// "orientation", "linear_velocity", "angular_velocity"}, ...]}; "name" is ""
// when unknown; no velocities for a pose-only sample. With joints, also
// "joints": [{"id", "position", "speed", "motor_impulse"}, ...].
Json pose_sample_json(const client::PoseSample& sample, const BodyNames& names);

// The table `tumble watch` draws: "tick 1234  t=5.142s\n", then a header
// and one aligned line per body: name (#id when unnamed), position (m),
// speed (m/s) and asleep (yes or no).
std::string format_watch_table(const client::PoseSample& sample, const WatchState& state);

// {"tick": N, "time": S, "bodies": [{"id", "name", "position", "speed",
// "asleep"}, ...]}.
Json watch_json(const client::PoseSample& sample, const WatchState& state);

// `value` on one line followed by a newline, with a space after each ':'
// and ',' ({"tick": 1, "bodies": [...]}); invalid UTF-8 in strings is
// replaced rather than thrown on.
std::string json_line(const Json& value);

}  // namespace tumble::cli
