// Checks that every transport must pass alike (a TCP socket in RawClient,
// WebSocket messages in WsClient): the protocol is the same over both.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>

#include "frame_client.h"
#include "replies.h"

namespace tumble::test {

// On a world whose "crate" (2 kg) rests in zero gravity: an impulse of 4 N s
// along y shows in the frames from its applied tick on (2 m/s), and not
// before. Frames are latest-wins, so the one of the applied tick itself may
// have been replaced by a later one before it was written.
inline void expect_impulse_shows_from_its_applied_tick(FrameClient& client) {
  tumble::v1::ClientMessage watch;
  watch.set_request_id(1);
  watch.mutable_subscribe()->set_rate_hz(0);  // every tick
  watch.mutable_subscribe()->add_bodies()->set_name("crate");
  ASSERT_TRUE(client.send(watch));
  ASSERT_TRUE(client.read_until([](const tumble::v1::ServerMessage& m) { return m.has_subscribed(); }));
  tumble::v1::ClientMessage impulse;
  impulse.set_request_id(2);
  impulse.mutable_apply_impulse()->mutable_body()->set_name("crate");
  impulse.mutable_apply_impulse()->mutable_impulse()->set_y(4);
  ASSERT_TRUE(client.send(impulse));
  const auto ack = client.read_until([](const tumble::v1::ServerMessage& m) { return is_reply_to(m, 2); });
  ASSERT_TRUE(ack && ack->has_ack());
  const std::uint64_t applied = ack->ack().applied_tick();
  for (int k = 0; k < 8; ++k) {
    const auto frame = client.read_until([](const tumble::v1::ServerMessage& m) { return m.has_pose_frame(); });
    ASSERT_TRUE(frame);
    const float expected = frame->pose_frame().tick() >= applied ? 2.0f : 0.0f;
    EXPECT_FLOAT_EQ(frame->pose_frame().linear_velocities(1), expected) << "tick " << frame->pose_frame().tick();
  }
}

}  // namespace tumble::test
