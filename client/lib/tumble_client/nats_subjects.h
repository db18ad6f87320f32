// The NATS subjects a world is served on, and the names that build them.
//
//   tumble.v1.<world>.poses.<stream>   pose frames of one stream
//   tumble.v1.<world>.key.<stream>     request: the stream's latest frame as a key frame
//   tumble.v1.<world>.events           world events, one per message
//   tumble.v1.<world>.rpc              request: a ClientMessage; reply: a ServerMessage
//   tumble.v1.<world>.query            the same for Hello, ListBodies, ListJoints and GetStats only
//   tumble.v1.worlds                   request: every server answers its WorldInfo
//
// Payloads are protobuf bytes, one message per NATS message, without the
// TCP protocol's length prefix.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace tumble::client {

inline constexpr std::string_view kWorldsSubject = "tumble.v1.worlds";

// The longest world and stream names, in characters.
inline constexpr std::size_t kMaxWorldNameLength = 64;
inline constexpr std::size_t kMaxStreamNameLength = 32;

// Why `name` cannot name a world (1 to 64 of A-Z a-z 0-9 _ -, so that it is
// one subject token: no dot, no wildcard, no space); "" when it can.
std::string world_name_problem(std::string_view name);

// The same for a stream name (1 to 32 of the same characters).
std::string stream_name_problem(std::string_view name);

std::string rpc_subject(std::string_view world);
std::string query_subject(std::string_view world);
std::string events_subject(std::string_view world);
std::string poses_subject(std::string_view world, std::string_view stream);
std::string key_subject(std::string_view world, std::string_view stream);

}  // namespace tumble::client
