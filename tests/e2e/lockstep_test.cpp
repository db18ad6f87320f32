// Lockstep against the real tumbled: a paused server takes a Step up as it
// arrives, not at its loop's next tick, and a Step with forces and a frame
// reply is one round trip of a control loop.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "raw_client.h"
#include "test_scenes.h"
#include "tumbled_process.h"

namespace tumble::test {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;
using tumble::v1::ClientMessage;
using tumble::v1::ServerMessage;

// A 2 kg crate at rest, no gravity.
std::optional<ServerMessage> ask(RawClient& client, const ClientMessage& request) {
  if (!client.send(request)) return std::nullopt;
  return client.read_until([&](const ServerMessage& m) {
    return (m.has_ack() && m.ack().request_id() == request.request_id()) ||
           (m.has_error() && m.error().request_id() == request.request_id());
  });
}

ClientMessage pause(std::uint64_t id) {
  ClientMessage m;
  m.set_request_id(id);
  m.mutable_pause();
  return m;
}

ClientMessage step(std::uint64_t id, std::uint32_t ticks) {
  ClientMessage m;
  m.set_request_id(id);
  m.mutable_step()->set_ticks(ticks);
  return m;
}

// At 2 Hz a pass of the loop comes every half second: a Step taken up at
// the next pass would be answered 250 ms later on average, so 40 of them
// in a row would take 10 s. Taken up as they arrive, they take a few ms.
TEST(Lockstep, APausedServerTakesAStepUpAsItArrives) {
  TumbledProcess server(kCrateScene, {"--tick-rate", "2"});
  ASSERT_TRUE(server.started()) << server.log();
  RawClient client(server.port());
  ASSERT_TRUE(client.handshake());
  const auto paused = ask(client, pause(1));
  ASSERT_TRUE(paused && paused->has_ack());
  const auto started = std::chrono::steady_clock::now();
  for (std::uint64_t i = 0; i < 40; ++i) {
    const auto stepped = ask(client, step(2 + i, 1));
    ASSERT_TRUE(stepped && stepped->has_ack()) << (stepped ? stepped->DebugString() : "no reply");
    EXPECT_EQ(stepped->ack().applied_tick(), paused->ack().applied_tick() + i + 1);
  }
  const auto elapsed = std::chrono::steady_clock::now() - started;
  EXPECT_LT(elapsed, seconds(2)) << "40 Steps took " << std::chrono::duration_cast<milliseconds>(elapsed).count()
                                 << " ms";
}

// Step{forces, reply_frame}: the force acts on its ticks only, and the Ack
// carries the crate's state after the last one, as the integrator makes it
// (semi-implicit Euler: v_n = n a dt, x_n = a dt^2 n (n + 1) / 2).
TEST(Lockstep, AStepWithForcesIsAnsweredWithTheFrameOfItsLastTick) {
  TumbledProcess server(kCrateScene);
  ASSERT_TRUE(server.started()) << server.log();
  RawClient client(server.port());
  ASSERT_TRUE(client.handshake());
  const auto paused = ask(client, pause(1));
  ASSERT_TRUE(paused && paused->has_ack());
  ClientMessage pushed = step(2, 12);
  auto* force = pushed.mutable_step()->add_forces();
  force->mutable_body()->set_name("crate");
  force->mutable_force()->set_x(10);
  pushed.mutable_step()->set_reply_frame(true);
  const auto first = ask(client, pushed);
  ASSERT_TRUE(first && first->has_ack()) << (first ? first->DebugString() : "no reply");
  const tumble::v1::PoseFrame& frame = first->ack().frame();
  const double dt = 1.0 / 240, a = 10.0 / 2;
  EXPECT_EQ(frame.tick(), paused->ack().applied_tick() + 12);
  ASSERT_EQ(frame.ids_size(), 1);
  EXPECT_NEAR(frame.positions(0), a * dt * dt * 12 * 13 / 2, 1e-6);
  EXPECT_NEAR(frame.linear_velocities(0), 12 * a * dt, 1e-6);

  ClientMessage coasting = step(3, 12);
  coasting.mutable_step()->set_reply_frame(true);
  const auto second = ask(client, coasting);
  ASSERT_TRUE(second && second->has_ack());
  EXPECT_NEAR(second->ack().frame().linear_velocities(0), 12 * a * dt, 1e-6) << "the force ended with its Step";
}

}  // namespace
}  // namespace tumble::test
