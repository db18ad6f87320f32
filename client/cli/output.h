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
#include "tumble_client/pose_sample.h"

namespace tumble::cli {

// JSON objects keep their keys in the order they were written.
using Json = nlohmann::ordered_json;

// Body names by id, for output that shows names where frames carry ids.
using BodyNames = std::unordered_map<std::uint32_t, std::string>;

// The names in a BodyList.
BodyNames body_names(const tumble::v1::BodyList& list);

// "box", "sphere", "capsule" or "points"; "" when the shape is not set.
std::string shape_name(const tumble::v1::Shape& shape);

// "applied at tick 1234\n".
std::string format_ack(const tumble::v1::Ack& ack);

// {"applied_tick": N, "request_id": R}
Json ack_json(const tumble::v1::Ack& ack);

// An aligned table, one header line and one line per body: id, name,
// shape, mass (kg), position (m) and speed (m/s).
std::string format_body_table(const tumble::v1::BodyList& list);

// {"tick": N, "bodies": [{"id", "name", "shape", "mass", "position",
// "orientation", "linear_velocity", "angular_velocity"}, ...]}; "shape" is
// null when not set.
Json body_list_json(const tumble::v1::BodyList& list);

// "tick 1234  t=5.142s\n", then one line per body:
// "  crate  pos (x, y, z)  quat [w, x, y, z]  v (x, y, z)  w (x, y, z)\n".
// Bodies without a known name show as #id.
std::string format_pose_sample(const client::PoseSample& sample, const BodyNames& names);

// {"tick": N, "time": S, "bodies": [{"id", "name", "position",
// "orientation", "linear_velocity", "angular_velocity"}, ...]}; "name" is ""
// when unknown.
Json pose_sample_json(const client::PoseSample& sample, const BodyNames& names);

// `value` on one line followed by a newline, with a space after each ':'
// and ',' ({"tick": 1, "bodies": [...]}); invalid UTF-8 in strings is
// replaced rather than thrown on.
std::string json_line(const Json& value);

}  // namespace tumble::cli
