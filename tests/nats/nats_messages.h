// Messages the NATS tests send to tumbled over .rpc, and the parsing of
// what comes back; the subjects of the world "lab" most of them serve.
#pragma once

#include <cstdint>
#include <string>

#include <gtest/gtest.h>

#include "tumble/v1/protocol.pb.h"

namespace tumble::test {

// A ServerMessage from its bytes; a test failure when they are not one.
inline tumble::v1::ServerMessage parse_server_message(const std::string& bytes) {
  tumble::v1::ServerMessage message;
  EXPECT_TRUE(message.ParseFromString(bytes));
  return message;
}

// ApplyForce of `fx` newtons along x on `body` for one tick.
inline std::string force_request(const std::string& body, double fx, std::uint64_t request_id) {
  tumble::v1::ClientMessage message;
  message.set_request_id(request_id);
  auto& force = *message.mutable_apply_force();
  force.mutable_body()->set_name(body);
  force.mutable_force()->set_x(fx);
  force.set_ticks(1);
  return message.SerializeAsString();
}

// ApplyImpulse of `jy` newton-seconds along y on `body`, at its centre.
inline std::string impulse_request(const std::string& body, double jy, std::uint64_t request_id) {
  tumble::v1::ClientMessage message;
  message.set_request_id(request_id);
  auto& impulse = *message.mutable_apply_impulse();
  impulse.mutable_body()->set_name(body);
  impulse.mutable_impulse()->set_y(jy);
  return message.SerializeAsString();
}

inline std::string stats_request(std::uint64_t request_id) {
  tumble::v1::ClientMessage message;
  message.set_request_id(request_id);
  message.mutable_get_stats();
  return message.SerializeAsString();
}

}  // namespace tumble::test
