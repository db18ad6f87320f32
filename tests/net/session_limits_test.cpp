// Per-session limits on the in-process server: the handshake timeout, the
// request rate, the error budget, frames that stall, clients that leave
// replies or frames undelivered, and connections over the server's limit.
#include <gtest/gtest.h>

#include <map>
#include <thread>

#include "raw_client.h"
#include "replies.h"
#include "requests.h"
#include "test_scenes.h"
#include "test_server.h"

namespace tumble::test {
namespace {

using std::chrono::milliseconds;
using tumble::v1::ClientMessage;
using tumble::v1::ServerMessage;

// The server's Stats, asked for by a fresh client.
tumble::v1::Stats stats_of(std::uint16_t port) {
  RawClient client(port);
  EXPECT_TRUE(client.handshake("stats"));
  EXPECT_TRUE(client.send(get_stats(9)));
  const auto reply = client.read_until([](const ServerMessage& m) { return is_reply_to(m, 9); });
  EXPECT_TRUE(reply && reply->has_stats()) << (reply ? reply->DebugString() : "no reply");
  return reply && reply->has_stats() ? reply->stats() : tumble::v1::Stats{};
}

// A fresh client handshakes and gets its body list: the server serves.
void ExpectServing(std::uint16_t port) {
  RawClient client(port);
  ASSERT_TRUE(client.connected());
  const auto welcome = client.handshake("checker");
  ASSERT_TRUE(welcome && welcome->has_welcome());
  ASSERT_TRUE(client.send(list_bodies(2)));
  const auto list = client.read_until([](const ServerMessage& m) { return is_reply_to(m, 2); });
  ASSERT_TRUE(list && list->has_body_list());
}

TEST(SessionLimits, AClientThatNeverSaysHelloIsCutOff) {
  net::SessionLimits limits;
  limits.handshake_timeout = milliseconds(300);
  TestServer server(kCrateScene, 240, limits);

  RawClient silent(server.port());
  ASSERT_TRUE(silent.connected());
  const auto reply = silent.read(std::chrono::seconds(20));
  ASSERT_TRUE(reply && reply->has_error()) << (reply ? reply->DebugString() : "no reply");
  EXPECT_EQ(reply->error().code(), tumble::v1::HANDSHAKE_REQUIRED);
  EXPECT_EQ(reply->error().message(), "no Hello within 0.3 s of connecting");
  EXPECT_TRUE(silent.closed_by_server());
  ExpectServing(server.port());
}

TEST(SessionLimits, HalfAHelloIsNoHello) {
  net::SessionLimits limits;
  limits.handshake_timeout = milliseconds(300);
  TestServer server(kCrateScene, 240, limits);

  RawClient slow(server.port());
  ASSERT_TRUE(slow.send_bytes("\x20partial"));  // announces 32 bytes, sends 7
  const auto reply = slow.read(std::chrono::seconds(20));
  ASSERT_TRUE(reply && reply->has_error());
  EXPECT_EQ(reply->error().code(), tumble::v1::HANDSHAKE_REQUIRED);
  EXPECT_TRUE(slow.closed_by_server());
}

TEST(SessionLimits, AGreetedClientOutlivesTheHandshakeTimeout) {
  net::SessionLimits limits;
  limits.handshake_timeout = milliseconds(1000);
  TestServer server(kCrateScene, 240, limits);

  RawClient client(server.port());
  ASSERT_TRUE(client.handshake());
  // A client that connects later and says nothing is cut off once its
  // timeout has passed: by then the greeted client's has passed too.
  RawClient silent(server.port());
  ASSERT_TRUE(silent.connected());
  const auto cut_off = silent.read(std::chrono::seconds(20));
  ASSERT_TRUE(cut_off && cut_off->has_error()) << (cut_off ? cut_off->DebugString() : "no reply");
  EXPECT_EQ(cut_off->error().code(), tumble::v1::HANDSHAKE_REQUIRED);
  ASSERT_TRUE(client.send(list_bodies(2)));
  const auto list = client.read_until([](const ServerMessage& m) { return is_reply_to(m, 2); });
  ASSERT_TRUE(list && list->has_body_list());
}

TEST(SessionLimits, RequestsOverTheRateAreRefusedAndTheClientRecovers) {
  net::SessionLimits limits;
  limits.commands_per_second = 5;
  limits.command_burst = 5;
  TestServer server(kCrateScene, 240, limits);

  RawClient client(server.port());
  ASSERT_TRUE(client.handshake());  // Hello is not a request: the burst is whole
  std::string burst;
  for (std::uint64_t id = 1; id <= 30; ++id) burst += wire::encode_frame(list_bodies(id));
  ASSERT_TRUE(client.send_bytes(burst));

  // Refusals are immediate, body lists come from the sim's next tick:
  // collect the replies by request id.
  std::map<std::uint64_t, ServerMessage> replies;
  while (replies.size() < 30) {
    const auto reply = client.read();
    ASSERT_TRUE(reply) << "only " << replies.size() << " replies";
    for (std::uint64_t id = 1; id <= 30; ++id) {
      if (is_reply_to(*reply, id)) replies.emplace(id, *reply);
    }
  }
  int served = 0;
  int limited = 0;
  for (const auto& [id, reply] : replies) {
    if (reply.has_body_list()) {
      ++served;
    } else {
      EXPECT_EQ(reply.error().code(), tumble::v1::RATE_LIMITED);
      EXPECT_EQ(reply.error().request_id(), id);
      EXPECT_NE(reply.error().message().find("5 requests per second"), std::string::npos) << reply.error().message();
      ++limited;
    }
  }
  // The burst of 5, and a token for each 0.2 s the 30 requests took to arrive.
  EXPECT_GE(served, 5);
  EXPECT_GE(limited, 15);
  EXPECT_EQ(served + limited, 30);

  // A token comes back every 0.2 s: the same connection is served again.
  bool recovered = false;
  for (std::uint64_t id = 100; id < 150 && !recovered; ++id) {
    ASSERT_TRUE(client.send(list_bodies(id)));
    const auto reply = client.read_until([&](const ServerMessage& m) { return is_reply_to(m, id); });
    ASSERT_TRUE(reply);
    recovered = reply->has_body_list();
    if (!recovered) std::this_thread::sleep_for(milliseconds(250));
  }
  EXPECT_TRUE(recovered);
}

TEST(SessionLimits, AClientThatStopsReadingFramesIsDisconnected) {
  net::SessionLimits limits;
  limits.max_undelivered = milliseconds(500);
  TestServer server(row_of_spheres(400), 240, limits);

  RawClient sleeper(server.port());
  ASSERT_TRUE(sleeper.handshake());
  ASSERT_TRUE(sleeper.send(subscribe(2, 0)));  // every tick
  // Never reads: once the socket buffers are full a frame waits, and after
  // 0.5 s of that the server lets go of the client.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  bool gone = false;
  while (!gone && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(milliseconds(100));
    ClientMessage probe;  // cheap, with a small Error for an answer
    probe.set_request_id(3);
    probe.mutable_unsubscribe()->set_subscription_id(999999);
    gone = !sleeper.send(probe);  // writes fail once the server has closed (reset) the connection
  }
  EXPECT_TRUE(gone || sleeper.closed_by_server(std::chrono::seconds(30)));
  ExpectServing(server.port());
}

TEST(SessionLimits, AClientThatLetsRepliesPileUpIsDisconnected) {
  net::SessionLimits limits;
  limits.max_pending_bytes = 256 * 1024;
  TestServer server(row_of_spheres(400), 240, limits);

  RawClient hoarder(server.port());
  ASSERT_TRUE(hoarder.handshake());
  // Each BodyList of 400 bodies is tens of kilobytes; asking for hundreds
  // without reading any exceeds the limit once the socket buffers are full.
  bool gone = false;
  for (std::uint64_t id = 2; id < 2000 && !gone; ++id) {
    gone = !hoarder.send(list_bodies(id));
    if (id % 50 == 0) std::this_thread::sleep_for(milliseconds(20));
  }
  EXPECT_TRUE(gone || hoarder.closed_by_server(std::chrono::seconds(30)));
  ExpectServing(server.port());
}

// A stream of junk after Hello (each zero byte is an empty envelope, an
// UNKNOWN_MESSAGE) draws the error budget's burst of Errors, then one
// RESOURCE_EXHAUSTED that says why, and a close: not a reply per byte.
TEST(SessionLimits, AHundredThousandZeroBytesDrawAFewErrorsThenAClose) {
  TestServer server(kCrateScene, 240);  // the default budget: 100 Errors a second
  RawClient client(server.port());
  ASSERT_TRUE(client.handshake());
  ASSERT_TRUE(client.send_bytes(std::string(100000, '\0')));

  std::size_t unknown = 0;
  std::size_t reply_bytes = 0;
  std::optional<ServerMessage> last;
  while (auto message = client.read()) {
    reply_bytes += wire::encode_frame(*message).size();
    ASSERT_TRUE(message->has_error()) << message->DebugString();
    if (message->error().code() == tumble::v1::UNKNOWN_MESSAGE) ++unknown;
    last = message;
    if (message->error().code() != tumble::v1::UNKNOWN_MESSAGE) break;
  }
  ASSERT_TRUE(last);
  EXPECT_EQ(last->error().code(), tumble::v1::RESOURCE_EXHAUSTED);
  EXPECT_EQ(last->error().message(), "over the limit of 100 errors per second; the connection is closed");
  EXPECT_GE(unknown, 100u);  // the burst, and a few more for the time the bytes took to read
  EXPECT_LE(unknown, 120u);
  EXPECT_LT(reply_bytes, 12000u);
  EXPECT_TRUE(client.closed_by_server());
  EXPECT_TRUE(client.saw_eof());
  EXPECT_EQ(stats_of(server.port()).clients_closed_for_errors(), 1u);
}

// Errors the sim answers (a push on a body that does not exist) are charged too.
TEST(SessionLimits, ErrorsFromTheWorldCountAgainstTheBudget) {
  net::SessionLimits limits;
  limits.errors_per_second = 5;
  limits.error_burst = 5;
  TestServer server(kCrateScene, 240, limits);
  RawClient client(server.port());
  ASSERT_TRUE(client.handshake());
  std::string pushes;
  for (std::uint64_t id = 1; id <= 50; ++id) pushes += wire::encode_frame(force(id, "nobody", 1));
  ASSERT_TRUE(client.send_bytes(pushes));
  // The replies to all 50 come from one tick: after the budget's burst, one
  // RESOURCE_EXHAUSTED is the last Error the client gets.
  std::vector<ServerMessage> errors;
  while (auto message = client.read()) {
    ASSERT_TRUE(message->has_error()) << message->DebugString();
    errors.push_back(*message);
  }
  ASSERT_GE(errors.size(), 6u);
  EXPECT_EQ(errors.back().error().code(), tumble::v1::RESOURCE_EXHAUSTED);
  EXPECT_EQ(errors.back().error().message(), "over the limit of 5 errors per second; the connection is closed");
  errors.pop_back();
  for (const auto& error : errors) EXPECT_EQ(error.error().code(), tumble::v1::UNKNOWN_BODY);
  EXPECT_LT(errors.size(), 10u);  // the burst of 5, and a few for the time the replies took
  EXPECT_TRUE(client.saw_eof());
}

// A frame whose first bytes came must come whole within the frame timeout;
// a client that is idle between frames is not touched.
TEST(SessionLimits, AFrameThatStallsMidwayIsCutOffAndAnIdleClientIsNot) {
  net::SessionLimits limits;
  limits.frame_timeout = milliseconds(300);
  TestServer server(kCrateScene, 240, limits);

  RawClient idle(server.port());
  ASSERT_TRUE(idle.handshake());
  RawClient staller(server.port());
  ASSERT_TRUE(staller.handshake());
  ASSERT_TRUE(staller.send_bytes("\x20partial"));  // announces 32 bytes, sends 7
  const auto reply = staller.read(std::chrono::seconds(20));
  ASSERT_TRUE(reply && reply->has_error()) << (reply ? reply->DebugString() : "no reply");
  EXPECT_EQ(reply->error().code(), tumble::v1::MALFORMED_FRAME);
  EXPECT_NE(reply->error().message().find("has 8 bytes and is still incomplete, over the limit of 0.3 s"),
            std::string::npos)
      << reply->error().message();
  EXPECT_TRUE(staller.closed_by_server());

  // The idle client greeted before the staller began its frame: it has been
  // idle for longer than the frame timeout, and is served.
  ASSERT_TRUE(idle.send(list_bodies(2)));
  const auto list = idle.read_until([](const ServerMessage& m) { return is_reply_to(m, 2); });
  ASSERT_TRUE(list && list->has_body_list());
}

// Over max_connections every client is told why, however many are being
// refused at once, up to the bound on pending refusals.
TEST(SessionLimits, EveryConnectionOverTheLimitIsToldWhy) {
  net::ServerConfig config;
  config.max_connections = 1;
  TestServer server(kCrateScene, 240, config);
  RawClient member(server.port());
  ASSERT_TRUE(member.handshake());

  // Three at once, none of which reads or closes before the last is refused.
  std::vector<std::unique_ptr<RawClient>> extras;
  for (int i = 0; i < 3; ++i) extras.push_back(std::make_unique<RawClient>(server.port()));
  for (auto& extra : extras) {
    const auto reply = extra->read();
    ASSERT_TRUE(reply && reply->has_error()) << (reply ? reply->DebugString() : "no reply");
    EXPECT_EQ(reply->error().code(), tumble::v1::RESOURCE_EXHAUSTED);
    EXPECT_EQ(reply->error().message(), "the server is at its limit of 1 connections; try again later");
  }
  extras.clear();
  ASSERT_TRUE(member.send(get_stats(2)));
  const auto stats = member.read_until([](const ServerMessage& m) { return is_reply_to(m, 2); });
  ASSERT_TRUE(stats && stats->has_stats());
  EXPECT_EQ(stats->stats().connections_refused(), 3u);
}

// Beyond the bound on refusals being written, a connection is closed
// without a word, and counted all the same.
TEST(SessionLimits, BeyondThePendingRefusalsAConnectionIsClosedAndCounted) {
  net::ServerConfig config;
  config.max_connections = 1;
  config.max_pending_refusals = 1;
  TestServer server(kCrateScene, 240, config);
  RawClient member(server.port());
  ASSERT_TRUE(member.handshake());

  RawClient told(server.port());  // reads its refusal and keeps the connection: the refusal lingers
  const auto reply = told.read();
  ASSERT_TRUE(reply && reply->has_error());
  EXPECT_EQ(reply->error().code(), tumble::v1::RESOURCE_EXHAUSTED);
  RawClient untold(server.port());
  EXPECT_FALSE(untold.read(std::chrono::seconds(10))) << "a refusal was written past the bound";
  EXPECT_TRUE(untold.saw_eof());

  ASSERT_TRUE(member.send(get_stats(2)));
  const auto stats = member.read_until([](const ServerMessage& m) { return is_reply_to(m, 2); });
  ASSERT_TRUE(stats && stats->has_stats());
  EXPECT_EQ(stats->stats().connections_refused(), 2u);
}

}  // namespace
}  // namespace tumble::test
