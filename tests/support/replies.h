// Which request a ServerMessage answers, for tests that read past pose
// frames and events to the reply they wait for.
#pragma once

#include <cstdint>

#include "tumble/v1/protocol.pb.h"

namespace tumble::test {

// True when `m` is the reply (Ack, Error, BodyList, JointList, Subscribed or
// Stats) to request `id`.
inline bool is_reply_to(const tumble::v1::ServerMessage& m, std::uint64_t id) {
  return (m.has_ack() && m.ack().request_id() == id) || (m.has_error() && m.error().request_id() == id) ||
         (m.has_body_list() && m.body_list().request_id() == id) ||
         (m.has_subscribed() && m.subscribed().request_id() == id) || (m.has_stats() && m.stats().request_id() == id) ||
         (m.has_joint_list() && m.joint_list().request_id() == id);
}

}  // namespace tumble::test
