// The server's side of a scripted conversation: the messages a tumbled
// would send, built with fixed contents, and the handshake step. For the
// scripts of ScriptedServer.
#pragma once

#include <cstdint>
#include <string>

#include <gtest/gtest.h>

#include "scripted_server.h"
#include "tumble/v1/protocol.pb.h"

namespace tumble::client::testing {

// Welcome from a 240 Hz server with two bodies, at `tick`.
inline tumble::v1::ServerMessage welcome(std::uint64_t tick) {
  tumble::v1::ServerMessage message;
  auto& w = *message.mutable_welcome();
  w.set_protocol_version(tumble::v1::PROTOCOL_VERSION_CURRENT);
  w.set_server_version("scripted");
  w.set_tick_rate_hz(240);
  w.set_tick(tick);
  w.set_body_count(2);
  return message;
}

inline tumble::v1::ServerMessage ack(std::uint64_t request_id, std::uint64_t applied_tick) {
  tumble::v1::ServerMessage message;
  message.mutable_ack()->set_request_id(request_id);
  message.mutable_ack()->set_applied_tick(applied_tick);
  return message;
}

inline tumble::v1::ServerMessage error(std::uint64_t request_id, tumble::v1::ErrorCode code, const std::string& text) {
  tumble::v1::ServerMessage message;
  message.mutable_error()->set_request_id(request_id);
  message.mutable_error()->set_code(code);
  message.mutable_error()->set_message(text);
  return message;
}

// An empty body list at `tick`.
inline tumble::v1::ServerMessage body_list(std::uint64_t request_id, std::uint64_t tick) {
  tumble::v1::ServerMessage message;
  message.mutable_body_list()->set_request_id(request_id);
  message.mutable_body_list()->set_tick(tick);
  return message;
}

// A FULL frame of body 4 at rest at (1, 2, 3), identity orientation.
inline tumble::v1::ServerMessage pose_frame(std::uint32_t subscription, std::uint64_t tick) {
  tumble::v1::ServerMessage message;
  auto& frame = *message.mutable_pose_frame();
  frame.set_subscription_id(subscription);
  frame.set_tick(tick);
  frame.add_ids(4);
  for (float v : {1.f, 2.f, 3.f}) frame.add_positions(v);
  for (float v : {1.f, 0.f, 0.f, 0.f}) frame.add_orientations(v);
  for (int k = 0; k < 3; ++k) {
    frame.add_linear_velocities(0);
    frame.add_angular_velocities(0);
  }
  return message;
}

// Reads the client's Hello and answers with Welcome at `tick`.
inline void accept_hello(ServerPeer& peer, std::uint64_t tick = 7) {
  auto hello = peer.receive();
  ASSERT_TRUE(hello.has_value());
  ASSERT_TRUE(hello->has_hello());
  peer.send(welcome(tick));
}

}  // namespace tumble::client::testing
