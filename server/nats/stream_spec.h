// The names and stream specs of a world served over NATS, as tumbled's
// command line gives them: --world NAME and --nats-stream
// NAME=ENCODING@HZ[:fields]. Both names are 1 to their limit of
// [A-Za-z0-9_-], so they are one token of a NATS subject (no dot, no
// wildcard).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include "tumble/v1/protocol.pb.h"

namespace tumble::nats {

inline constexpr std::size_t kMaxWorldNameBytes = 64;
inline constexpr std::size_t kMaxStreamNameBytes = 32;
// The default stream: every body, quantized, at 60 Hz.
inline constexpr std::string_view kDefaultStreamSpec = "q60=quantized@60";

// One pose stream published on tumble.v1.<world>.poses.<name>, of every body.
struct StreamSpec {
  std::string name;
  tumble::v1::PoseEncoding encoding = tumble::v1::POSE_ENCODING_QUANTIZED;
  double rate_hz = 60;      // > 0; rounded to a divisor of the tick rate when published
  bool velocities = false;  // fields `all` (POSE_FIELDS_POSE_AND_VELOCITY); `pose` by default
  bool joints = false;      // fields with `joints`: every joint's state too (Subscribe.joints)
};

// Why a name is refused ("must be ..."), or nullopt when it may be used.
// `what` names the flag or field in the sentence.
std::optional<std::string> check_world_name(std::string_view name, std::string_view what = "--world");
std::optional<std::string> check_stream_name(std::string_view name, std::string_view what = "--nats-stream");
// A JetStream key-value bucket's name, by the same rules as a world's.
std::optional<std::string> check_bucket_name(std::string_view name);

// Parses NAME=ENCODING@HZ[:fields] (ENCODING: full | quantized | delta;
// HZ: a number in (0, 10000]; fields: pose | all | joints, or pose or all
// with joints after a comma, e.g. all,joints); else the reason.
std::variant<StreamSpec, std::string> parse_stream_spec(std::string_view text);

// The subjects of a world.
std::string poses_subject(std::string_view world, std::string_view stream);
std::string key_subject(std::string_view world, std::string_view stream);
std::string events_subject(std::string_view world);
std::string rpc_subject(std::string_view world);
// Requests that read and change nothing (Hello, ListBodies, ListJoints, GetStats): what an observer may send.
std::string query_subject(std::string_view world);
std::string rpc_queue_group(std::string_view world);
inline constexpr std::string_view kWorldsSubject = "tumble.v1.worlds";

}  // namespace tumble::nats
