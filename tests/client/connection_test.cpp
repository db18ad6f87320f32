#include "tumble_client/connection.h"

#include <poll.h>

#include <atomic>
#include <chrono>
#include <future>
#include <string>
#include <string_view>

#include <gtest/gtest.h>
#include <boost/asio.hpp>

#include "scripted_messages.h"
#include "scripted_server.h"
#include "wire/frame.h"

namespace tumble::client {
namespace {

using namespace std::chrono_literals;
using testing::accept_hello;
using testing::ack;
using testing::body_list;
using testing::error;
using testing::pose_frame;
using testing::ScriptedServer;
using testing::ServerPeer;
using testing::welcome;
using tumble::v1::ServerMessage;
using Clock = std::chrono::steady_clock;

constexpr Timeout kGenerous = 5s;

tumble::v1::ApplyForce force_on(const char* name) {
  tumble::v1::ApplyForce force;
  force.mutable_body()->set_name(name);
  force.mutable_force()->set_y(10);
  return force;
}

TEST(Connection, HandshakeSendsHelloAndKeepsWelcome) {
  ScriptedServer server([](ServerPeer& peer) {
    auto hello = peer.receive();
    ASSERT_TRUE(hello.has_value());
    ASSERT_TRUE(hello->has_hello());
    EXPECT_EQ(hello->hello().protocol_version(), 1u);
    EXPECT_EQ(hello->hello().client_name(), "test-client");
    EXPECT_EQ(hello->hello().token(), "secret");
    peer.send(welcome(41));
    peer.wait_for_close();
  });
  auto connection = Connection::connect(server.endpoint(), "test-client", "secret", kGenerous);
  ASSERT_TRUE(connection.ok()) << connection.failure().message;
  EXPECT_EQ(connection->welcome().tick(), 41u);
  EXPECT_EQ(connection->welcome().tick_rate_hz(), 240);
  EXPECT_EQ(connection->welcome().server_version(), "scripted");
}

TEST(Connection, HostNamesAreResolved) {
  ScriptedServer server([](ServerPeer& peer) {
    accept_hello(peer, 12);
    peer.wait_for_close();
  });
  auto connection = Connection::connect(Endpoint{"localhost", server.endpoint().port}, "test-client", "", kGenerous);
  ASSERT_TRUE(connection.ok()) << connection.failure().message;
  EXPECT_EQ(connection->welcome().tick(), 12u);
  EXPECT_EQ(connection->endpoint().host, "localhost");
}

TEST(Connection, RequestReturnsItsAckAndQueuesTheFrameThatCameFirst) {
  std::atomic<std::uint64_t> seen_request_id{0};
  ScriptedServer server([&](ServerPeer& peer) {
    accept_hello(peer);
    auto request = peer.receive();
    ASSERT_TRUE(request.has_value());
    ASSERT_TRUE(request->has_apply_force());
    EXPECT_EQ(request->apply_force().body().name(), "crate");
    EXPECT_NE(request->request_id(), 0u);
    seen_request_id = request->request_id();
    peer.send(pose_frame(3, 8));
    peer.send(ack(request->request_id() + 100, 1));  // answers nothing the client asked: dropped
    peer.send(ack(request->request_id(), 9));
    peer.wait_for_close();
  });
  auto connection = Connection::connect(server.endpoint(), "test-client", "", kGenerous);
  ASSERT_TRUE(connection.ok()) << connection.failure().message;

  auto reply = connection->apply_force(force_on("crate"), kGenerous);
  ASSERT_TRUE(reply.ok()) << reply.failure().message;
  EXPECT_EQ(reply->request_id(), seen_request_id.load());
  EXPECT_EQ(reply->applied_tick(), 9u);

  auto frame = connection->next_message(0s);
  ASSERT_TRUE(frame.ok()) << frame.failure().message;
  ASSERT_TRUE(frame->has_pose_frame());
  EXPECT_EQ(frame->pose_frame().subscription_id(), 3u);
  EXPECT_EQ(frame->pose_frame().tick(), 8u);

  auto nothing = connection->next_message(50ms);
  ASSERT_FALSE(nothing.ok());
  EXPECT_EQ(nothing.failure().kind, FailureKind::timeout);
}

// Waits up to kGenerous for the connection's socket to be readable.
bool wait_readable(Connection& connection) {
  pollfd descriptor{connection.native_handle(), POLLIN, 0};
  return ::poll(&descriptor, 1, 5000) == 1;
}

// Polls the connection as a caller that waits on many would, until a
// message or a failure other than timeout comes (or kGenerous passes).
Result<ServerMessage> poll_until_message(Connection& connection) {
  const auto give_up = Clock::now() + kGenerous;
  for (;;) {
    auto message = connection.poll_message();
    if (message.ok() || message.failure().kind != FailureKind::timeout || Clock::now() > give_up) return message;
    wait_readable(connection);
  }
}

TEST(Connection, PollMessageTakesWhatHasArrivedWithoutWaiting) {
  std::promise<void> go;
  std::future<void> went = go.get_future();
  const std::string second = wire::encode_frame(pose_frame(3, 9));
  ScriptedServer server([&](ServerPeer& peer) {
    accept_hello(peer);
    peer.send(pose_frame(3, 8));
    peer.send_bytes(std::string_view(second).substr(0, second.size() / 2));  // half a frame
    went.wait();
    peer.send_bytes(std::string_view(second).substr(second.size() / 2));
    peer.close();
  });
  auto connection = Connection::connect(server.endpoint(), "test-client", "", kGenerous);
  ASSERT_TRUE(connection.ok()) << connection.failure().message;

  auto first = poll_until_message(*connection);
  ASSERT_TRUE(first.ok()) << first.failure().message;
  ASSERT_TRUE(first->has_pose_frame());
  EXPECT_EQ(first->pose_frame().tick(), 8u);
  // Half of the next frame, at most: nothing whole, and no waiting for it.
  const auto start = Clock::now();
  auto nothing = connection->poll_message();
  ASSERT_FALSE(nothing.ok());
  EXPECT_EQ(nothing.failure().kind, FailureKind::timeout);
  EXPECT_LT(Clock::now() - start, 1s);

  go.set_value();
  auto rest = poll_until_message(*connection);
  ASSERT_TRUE(rest.ok()) << rest.failure().message;
  EXPECT_EQ(rest->pose_frame().tick(), 9u) << "the half read before is kept";
  auto closed = poll_until_message(*connection);
  ASSERT_FALSE(closed.ok());
  EXPECT_EQ(closed.failure().kind, FailureKind::closed);
  EXPECT_EQ(closed.failure().message, "connection closed by the server");
}

TEST(Connection, PollMessageHandsOverWhatARequestQueuedFirst) {
  ScriptedServer server([&](ServerPeer& peer) {
    accept_hello(peer);
    auto request = peer.receive();
    ASSERT_TRUE(request.has_value());
    peer.send(pose_frame(3, 8));
    peer.send(ack(request->request_id(), 9));
    peer.wait_for_close();
  });
  auto connection = Connection::connect(server.endpoint(), "test-client", "", kGenerous);
  ASSERT_TRUE(connection.ok()) << connection.failure().message;
  auto reply = connection->apply_force(force_on("crate"), kGenerous);
  ASSERT_TRUE(reply.ok()) << reply.failure().message;

  // The frame was read while waiting for the Ack: the socket has nothing more.
  auto frame = connection->poll_message();
  ASSERT_TRUE(frame.ok()) << frame.failure().message;
  EXPECT_EQ(frame->pose_frame().tick(), 8u);
  auto nothing = connection->poll_message();
  ASSERT_FALSE(nothing.ok());
  EXPECT_EQ(nothing.failure().kind, FailureKind::timeout);
  // Still usable by the blocking calls.
  auto later = connection->next_message(50ms);
  ASSERT_FALSE(later.ok());
  EXPECT_EQ(later.failure().kind, FailureKind::timeout);
}

TEST(Connection, WorldEventsThatComeBeforeAReplyAreQueuedInOrder) {
  ScriptedServer server([&](ServerPeer& peer) {
    accept_hello(peer);
    auto request = peer.receive();
    ASSERT_TRUE(request.has_value());
    ASSERT_TRUE(request->has_get_stats());
    ServerMessage event;
    event.mutable_world_event()->set_subscription_id(2);
    event.mutable_world_event()->set_kind(tumble::v1::WORLD_EVENT_BODY_SPAWNED);
    event.mutable_world_event()->set_body_id(5);
    peer.send(event);
    peer.send(pose_frame(2, 8));
    ServerMessage stats;
    stats.mutable_stats()->set_request_id(request->request_id());
    stats.mutable_stats()->set_tick(8);
    stats.mutable_stats()->set_clients(3);
    peer.send(stats);
    peer.wait_for_close();
  });
  auto connection = Connection::connect(server.endpoint(), "test-client", "", kGenerous);
  ASSERT_TRUE(connection.ok()) << connection.failure().message;

  auto stats = connection->get_stats(kGenerous);
  ASSERT_TRUE(stats.ok()) << stats.failure().message;
  EXPECT_EQ(stats->tick(), 8u);
  EXPECT_EQ(stats->clients(), 3u);

  auto first = connection->next_message(0s);
  ASSERT_TRUE(first.ok()) << first.failure().message;
  ASSERT_TRUE(first->has_world_event());
  EXPECT_EQ(first->world_event().body_id(), 5u);
  auto second = connection->next_message(0s);
  ASSERT_TRUE(second.ok());
  EXPECT_TRUE(second->has_pose_frame());
}

TEST(Connection, SpawnAndStepAreAnsweredByAcks) {
  ScriptedServer server([&](ServerPeer& peer) {
    accept_hello(peer);
    auto spawn = peer.receive();
    ASSERT_TRUE(spawn.has_value());
    ASSERT_TRUE(spawn->has_spawn_body());
    EXPECT_EQ(spawn->spawn_body().body().name(), "rock");
    ServerMessage reply = ack(spawn->request_id(), 12);
    reply.mutable_ack()->set_body_id(4);
    peer.send(reply);
    auto step = peer.receive();
    ASSERT_TRUE(step.has_value());
    ASSERT_TRUE(step->has_step());
    EXPECT_EQ(step->step().ticks(), 5u);
    peer.send(body_list(step->request_id(), 17));  // the wrong kind of answer
    peer.wait_for_close();
  });
  auto connection = Connection::connect(server.endpoint(), "test-client", "", kGenerous);
  ASSERT_TRUE(connection.ok()) << connection.failure().message;
  tumble::v1::BodySpec spec;
  spec.set_name("rock");
  auto spawned = connection->spawn_body(spec, kGenerous);
  ASSERT_TRUE(spawned.ok()) << spawned.failure().message;
  EXPECT_EQ(spawned->body_id(), 4u);
  auto stepped = connection->step(5, kGenerous);
  ASSERT_FALSE(stepped.ok());
  EXPECT_EQ(stepped.failure().kind, FailureKind::protocol);
}

TEST(Connection, RequestIdsIncrease) {
  ScriptedServer server([](ServerPeer& peer) {
    accept_hello(peer);
    std::uint64_t previous = 0;
    for (int i = 0; i < 3; ++i) {
      auto request = peer.receive();
      ASSERT_TRUE(request.has_value());
      EXPECT_GT(request->request_id(), previous);
      previous = request->request_id();
      peer.send(ack(request->request_id(), previous));
    }
    peer.wait_for_close();
  });
  auto connection = Connection::connect(server.endpoint(), "test-client", "", kGenerous);
  ASSERT_TRUE(connection.ok()) << connection.failure().message;
  for (int i = 0; i < 3; ++i) {
    auto reply = connection->apply_force(force_on("crate"), kGenerous);
    ASSERT_TRUE(reply.ok()) << reply.failure().message;
    EXPECT_EQ(reply->applied_tick(), reply->request_id());
  }
}

TEST(Connection, ServerErrorReplyIsAFailureWithItsCode) {
  ScriptedServer server([](ServerPeer& peer) {
    accept_hello(peer);
    auto request = peer.receive();
    ASSERT_TRUE(request.has_value());
    peer.send(error(request->request_id(), tumble::v1::UNKNOWN_BODY, "no body named 'foo'"));
    peer.wait_for_close();
  });
  auto connection = Connection::connect(server.endpoint(), "test-client", "", kGenerous);
  ASSERT_TRUE(connection.ok()) << connection.failure().message;
  auto reply = connection->apply_force(force_on("foo"), kGenerous);
  ASSERT_FALSE(reply.ok());
  EXPECT_EQ(reply.failure().kind, FailureKind::server);
  EXPECT_EQ(reply.failure().code, tumble::v1::UNKNOWN_BODY);
  EXPECT_EQ(reply.failure().message, "server error UNKNOWN_BODY: no body named 'foo'");
}

TEST(Connection, TimedOutRequestLeavesTheConnectionUsable) {
  ScriptedServer server([](ServerPeer& peer) {
    accept_hello(peer);
    auto first = peer.receive();
    ASSERT_TRUE(first.has_value());
    auto second = peer.receive();  // the first is left unanswered until now
    ASSERT_TRUE(second.has_value());
    peer.send(body_list(first->request_id(), 1));
    peer.send(body_list(second->request_id(), 2));
    peer.wait_for_close();
  });
  auto connection = Connection::connect(server.endpoint(), "test-client", "", kGenerous);
  ASSERT_TRUE(connection.ok()) << connection.failure().message;

  const auto start = Clock::now();
  auto late = connection->list_bodies(200ms);
  const auto waited = Clock::now() - start;
  ASSERT_FALSE(late.ok());
  EXPECT_EQ(late.failure().kind, FailureKind::timeout);
  EXPECT_EQ(late.failure().message, "timed out after 0.2 s waiting for the reply to ListBodies");
  EXPECT_GE(waited, 150ms);
  EXPECT_LT(waited, 3s);

  auto list = connection->list_bodies(kGenerous);
  ASSERT_TRUE(list.ok()) << list.failure().message;
  EXPECT_EQ(list->tick(), 2u);  // not the late answer to the first request
}

TEST(Connection, ReplyOfTheWrongKindIsAProtocolFailure) {
  ScriptedServer server([](ServerPeer& peer) {
    accept_hello(peer);
    auto request = peer.receive();
    ASSERT_TRUE(request.has_value());
    peer.send(ack(request->request_id(), 5));
    peer.wait_for_close();
  });
  auto connection = Connection::connect(server.endpoint(), "test-client", "", kGenerous);
  ASSERT_TRUE(connection.ok()) << connection.failure().message;
  auto list = connection->list_bodies(kGenerous);
  ASSERT_FALSE(list.ok());
  EXPECT_EQ(list.failure().kind, FailureKind::protocol);
  EXPECT_EQ(list.failure().message, "the server answered ListBodies with Ack");
}

TEST(Connection, ConnectionLevelErrorComesFromNextMessageThenClose) {
  ScriptedServer server([](ServerPeer& peer) {
    accept_hello(peer);
    peer.send(error(0, tumble::v1::MALFORMED_FRAME, "bad bytes"));
    peer.close();
  });
  auto connection = Connection::connect(server.endpoint(), "test-client", "", kGenerous);
  ASSERT_TRUE(connection.ok()) << connection.failure().message;
  auto message = connection->next_message(kGenerous);
  ASSERT_TRUE(message.ok()) << message.failure().message;
  ASSERT_TRUE(message->has_error());
  EXPECT_EQ(message->error().code(), tumble::v1::MALFORMED_FRAME);

  auto closed = connection->next_message(kWaitForever);
  ASSERT_FALSE(closed.ok());
  EXPECT_EQ(closed.failure().kind, FailureKind::closed);
  EXPECT_EQ(closed.failure().message, "connection closed by the server");
}

TEST(Connection, ConnectionLevelErrorFailsAPendingRequest) {
  ScriptedServer server([](ServerPeer& peer) {
    accept_hello(peer);
    ASSERT_TRUE(peer.receive().has_value());
    peer.send(error(0, tumble::v1::INTERNAL, "the world is gone"));
    peer.close();
  });
  auto connection = Connection::connect(server.endpoint(), "test-client", "", kGenerous);
  ASSERT_TRUE(connection.ok()) << connection.failure().message;
  auto list = connection->list_bodies(kGenerous);
  ASSERT_FALSE(list.ok());
  EXPECT_EQ(list.failure().kind, FailureKind::server);
  EXPECT_EQ(list.failure().message, "server error INTERNAL: the world is gone");
}

TEST(Connection, ServerCloseEndsAnEndlessWaitAndLaterCalls) {
  ScriptedServer server([](ServerPeer& peer) {
    accept_hello(peer);
    peer.close();
  });
  auto connection = Connection::connect(server.endpoint(), "test-client", "", kGenerous);
  ASSERT_TRUE(connection.ok()) << connection.failure().message;
  auto message = connection->next_message(kWaitForever);
  ASSERT_FALSE(message.ok());
  EXPECT_EQ(message.failure().kind, FailureKind::closed);
  EXPECT_EQ(message.failure().message, "connection closed by the server");

  auto list = connection->list_bodies(kGenerous);
  ASSERT_FALSE(list.ok());
  EXPECT_EQ(list.failure().kind, FailureKind::closed);
}

TEST(Connection, RefusedHelloIsAServerFailure) {
  ScriptedServer server([](ServerPeer& peer) {
    auto hello = peer.receive();
    ASSERT_TRUE(hello.has_value());
    peer.send(error(hello->request_id(), tumble::v1::UNSUPPORTED_VERSION, "protocol version 1 is not supported"));
    peer.close();
  });
  auto connection = Connection::connect(server.endpoint(), "test-client", "", kGenerous);
  ASSERT_FALSE(connection.ok());
  EXPECT_EQ(connection.failure().kind, FailureKind::server);
  EXPECT_EQ(connection.failure().code, tumble::v1::UNSUPPORTED_VERSION);
  EXPECT_EQ(connection.failure().message, "server error UNSUPPORTED_VERSION: protocol version 1 is not supported");
}

TEST(Connection, SilentServerTimesOutTheHandshake) {
  ScriptedServer server([](ServerPeer& peer) {
    ASSERT_TRUE(peer.receive().has_value());
    peer.wait_for_close();
  });
  const auto start = Clock::now();
  auto connection = Connection::connect(server.endpoint(), "test-client", "", 300ms);
  ASSERT_FALSE(connection.ok());
  EXPECT_EQ(connection.failure().kind, FailureKind::timeout);
  EXPECT_EQ(connection.failure().message, "timed out after 0.3 s waiting for the server's Welcome");
  EXPECT_LT(Clock::now() - start, 3s);
}

TEST(Connection, GarbageFromTheServerIsAProtocolFailure) {
  ScriptedServer server([](ServerPeer& peer) {
    accept_hello(peer);
    peer.send_bytes(std::string("\x02\xff\xff", 3));  // a frame whose body is a truncated tag
    peer.wait_for_close();
  });
  auto connection = Connection::connect(server.endpoint(), "test-client", "", kGenerous);
  ASSERT_TRUE(connection.ok()) << connection.failure().message;
  auto message = connection->next_message(kGenerous);
  ASSERT_FALSE(message.ok());
  EXPECT_EQ(message.failure().kind, FailureKind::protocol);
  EXPECT_EQ(message.failure().message, "the server sent a frame of 2 bytes that is not a tumble.v1.ServerMessage");
}

TEST(Connection, AcceptsBodyListsLargerThanTheServersDefaultLimit) {
  constexpr int kBodies = 3000;
  ScriptedServer server([](ServerPeer& peer) {
    accept_hello(peer);
    auto request = peer.receive();
    ASSERT_TRUE(request.has_value());
    ServerMessage reply = body_list(request->request_id(), 3);
    for (int i = 0; i < kBodies; ++i) {
      auto* body = reply.mutable_body_list()->add_bodies();
      body->set_id(static_cast<std::uint32_t>(i));
      body->set_name(std::string(500, 'b') + std::to_string(i));
    }
    ASSERT_GT(reply.ByteSizeLong(), wire::kDefaultMaxFrameBytes);
    peer.send(reply);
    peer.wait_for_close();
  });
  auto connection = Connection::connect(server.endpoint(), "test-client", "", kGenerous);
  ASSERT_TRUE(connection.ok()) << connection.failure().message;
  auto list = connection->list_bodies(kGenerous);
  ASSERT_TRUE(list.ok()) << list.failure().message;
  ASSERT_EQ(list->bodies_size(), kBodies);
  EXPECT_EQ(list->bodies(kBodies - 1).id(), static_cast<std::uint32_t>(kBodies - 1));
}

TEST(Connection, ClosedPortFailsQuicklyWithAClearMessage) {
  std::uint16_t port = 0;
  {
    boost::asio::io_context io;
    boost::asio::ip::tcp::acceptor acceptor(
        io, boost::asio::ip::tcp::endpoint(boost::asio::ip::make_address("127.0.0.1"), 0));
    port = acceptor.local_endpoint().port();
  }  // closed: nothing listens there now
  const auto start = Clock::now();
  auto connection = Connection::connect(Endpoint{"127.0.0.1", port}, "test-client", "", kGenerous);
  ASSERT_FALSE(connection.ok());
  EXPECT_LT(Clock::now() - start, 2s);
  EXPECT_EQ(connection.failure().kind, FailureKind::connect);
  EXPECT_EQ(connection.failure().message,
            "cannot connect to 127.0.0.1:" + std::to_string(port) + ": Connection refused");
}

}  // namespace
}  // namespace tumble::client
