// Per-session limits on the in-process server: the handshake timeout, the
// request rate, and clients that leave replies or frames undelivered.
#include <gtest/gtest.h>

#include <map>
#include <thread>

#include "raw_client.h"
#include "requests.h"
#include "test_scenes.h"
#include "test_server.h"

namespace tumble::test {
namespace {

using std::chrono::milliseconds;
using tumble::v1::ClientMessage;
using tumble::v1::ServerMessage;

const char* kScene = R"({"gravity": [0, 0, 0], "bodies": [
    {"name": "crate", "shape": {"box": {"half_extents": [0.5, 0.5, 0.5]}}, "mass": 2}]})";

bool is_reply_to(const ServerMessage& m, std::uint64_t id) {
  return (m.has_error() && m.error().request_id() == id) || (m.has_body_list() && m.body_list().request_id() == id);
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
  TestServer server(kScene, 240, limits);

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
  TestServer server(kScene, 240, limits);

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
  TestServer server(kScene, 240, limits);

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
  TestServer server(kScene, 240, limits);

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

}  // namespace
}  // namespace tumble::test
