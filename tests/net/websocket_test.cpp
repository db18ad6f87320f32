// The protocol over WebSocket (/ws of the HTTP endpoint), on real sockets:
// the same frames and the same rules as over TCP, whatever the message
// boundaries, with refusals that close with a clear reason.
#include <gtest/gtest.h>

#include <map>
#include <set>
#include <sstream>
#include <thread>

#include "http_client.h"
#include "protocol_checks.h"
#include "raw_client.h"
#include "replies.h"
#include "requests.h"
#include "test_scenes.h"
#include "test_server.h"
#include "wire/frame.h"
#include "ws_client.h"

namespace tumble::test {
namespace {

using std::chrono::milliseconds;
using tumble::v1::ClientMessage;
using tumble::v1::ServerMessage;
namespace websocket = boost::beast::websocket;

bool is_frame(const ServerMessage& m) { return m.has_pose_frame(); }

// The server's count of connected clients, asked over `client` until it is
// `expected` (the server notices a departure when it next reads).
template <class Client>
bool clients_become(Client& client, std::uint32_t expected) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  for (std::uint64_t id = 1000; std::chrono::steady_clock::now() < deadline; ++id) {
    if (!client.send(get_stats(id))) return false;
    const auto stats = client.read_until([&](const ServerMessage& m) { return is_reply_to(m, id); });
    if (!stats || !stats->has_stats()) return false;
    if (stats->stats().clients() == expected) return true;
    std::this_thread::sleep_for(milliseconds(50));
  }
  return false;
}

class WebSocketTest : public ::testing::Test {
 protected:
  TestServer server_{kCrateAndBallScene, 240, with_http()};
};

TEST_F(WebSocketTest, HelloIsAnsweredByWelcome) {
  WsClient client(server_.http_port());
  ASSERT_TRUE(client.connected()) << "handshake status " << client.handshake_status();
  EXPECT_EQ(client.handshake_status(), 101u);
  const auto welcome = client.handshake();
  ASSERT_TRUE(welcome && welcome->has_welcome()) << (welcome ? welcome->DebugString() : "no reply");
  EXPECT_EQ(welcome->welcome().protocol_version(), 1u);
  EXPECT_EQ(welcome->welcome().body_count(), 2u);
  EXPECT_EQ(welcome->welcome().role(), tumble::v1::ROLE_CONTROLLER);
}

TEST_F(WebSocketTest, ListBodiesGetsTheBodyList) {
  WsClient client(server_.http_port());
  ASSERT_TRUE(client.handshake());
  ASSERT_TRUE(client.send(list_bodies(2)));
  const auto list = client.read_until([](const ServerMessage& m) { return is_reply_to(m, 2); });
  ASSERT_TRUE(list && list->has_body_list());
  ASSERT_EQ(list->body_list().bodies_size(), 2);
  EXPECT_EQ(list->body_list().bodies(0).name(), "crate");
  EXPECT_EQ(list->body_list().bodies(1).name(), "ball");
}

// GetStats counts what went on the connection: a WebSocket message's frame
// header beside the protocol frame it carries.
TEST_F(WebSocketTest, BytesSentCountTheWebSocketFraming) {
  WsClient client(server_.http_port());
  ASSERT_TRUE(client.handshake());
  ASSERT_TRUE(client.send(get_stats(1)));
  const auto first = client.read_until([](const ServerMessage& m) { return is_reply_to(m, 1); });
  ASSERT_TRUE(first && first->has_stats());
  ASSERT_TRUE(client.send(get_stats(2)));
  const auto second = client.read_until([](const ServerMessage& m) { return is_reply_to(m, 2); });
  ASSERT_TRUE(second && second->has_stats());
  // Only the first Stats was written in between: its frame, under 126
  // bytes, in a binary message with the 2-byte header (RFC 6455 5.2).
  const std::size_t frame = wire::encode_frame(*first).size();
  ASSERT_LT(frame, 126u);
  EXPECT_EQ(second->stats().bytes_sent() - first->stats().bytes_sent(), frame + 2);
}

// A WebSocket subscriber and a TCP one on the same stream get the same
// frames, byte for byte: the WebSocket carries exactly the TCP protocol.
TEST_F(WebSocketTest, PoseFramesAreTheSameAsOverTcp) {
  WsClient ws(server_.http_port());
  RawClient tcp(server_.port());
  ASSERT_TRUE(ws.handshake());
  ASSERT_TRUE(tcp.handshake());
  ASSERT_TRUE(ws.send(subscribe(2, 0)));  // every tick
  ASSERT_TRUE(tcp.send(subscribe(2, 0)));
  const auto ws_subscribed = ws.read_until([](const ServerMessage& m) { return is_reply_to(m, 2); });
  const auto tcp_subscribed = tcp.read_until([](const ServerMessage& m) { return is_reply_to(m, 2); });
  ASSERT_TRUE(ws_subscribed && ws_subscribed->has_subscribed());
  ASSERT_TRUE(tcp_subscribed && tcp_subscribed->has_subscribed());
  EXPECT_EQ(ws_subscribed->subscribed().subscription_id(), tcp_subscribed->subscribed().subscription_id());

  std::map<std::uint64_t, std::string> tcp_frames;  // tick -> serialized frame
  for (int i = 0; i < 30; ++i) {
    const auto frame = tcp.read_until(is_frame);
    ASSERT_TRUE(frame);
    tcp_frames[frame->pose_frame().tick()] = frame->SerializeAsString();
  }
  int compared = 0;
  std::uint64_t last_tick = 0;
  for (int i = 0; i < 30; ++i) {
    const auto frame = ws.read_until(is_frame);
    ASSERT_TRUE(frame);
    EXPECT_GT(frame->pose_frame().tick(), last_tick);
    last_tick = frame->pose_frame().tick();
    EXPECT_EQ(frame->pose_frame().ids_size(), 2);
    const auto same_tick = tcp_frames.find(last_tick);
    if (same_tick == tcp_frames.end()) continue;
    EXPECT_EQ(frame->SerializeAsString(), same_tick->second) << "tick " << last_tick;
    ++compared;
  }
  EXPECT_GT(compared, 0);
}

TEST_F(WebSocketTest, AnImpulseShowsFromItsAppliedTick) {
  WsClient client(server_.http_port());
  ASSERT_TRUE(client.handshake());
  expect_impulse_shows_from_its_applied_tick(client);
}

TEST_F(WebSocketTest, AFrameSplitOverTwoMessagesIsReadWhole) {
  WsClient client(server_.http_port());
  ClientMessage hello;
  hello.set_request_id(1);
  hello.mutable_hello()->set_protocol_version(tumble::v1::PROTOCOL_VERSION_CURRENT);
  hello.mutable_hello()->set_client_name("split");
  const std::string bytes = wire::encode_frame(hello);
  ASSERT_TRUE(client.send_bytes(bytes.substr(0, 1)));  // the length prefix alone
  ASSERT_TRUE(client.send_bytes(bytes.substr(1)));
  const auto welcome = client.read();
  ASSERT_TRUE(welcome && welcome->has_welcome()) << (welcome ? welcome->DebugString() : "no reply");
}

TEST_F(WebSocketTest, SeveralFramesInOneMessageAreEachRead) {
  WsClient client(server_.http_port());
  ClientMessage hello;
  hello.set_request_id(1);
  hello.mutable_hello()->set_protocol_version(tumble::v1::PROTOCOL_VERSION_CURRENT);
  ASSERT_TRUE(client.send_bytes(wire::encode_frame(hello) + wire::encode_frame(list_bodies(2)) +
                                wire::encode_frame(list_bodies(3))));
  const auto welcome = client.read();
  ASSERT_TRUE(welcome && welcome->has_welcome());
  EXPECT_TRUE(client.read_until([](const ServerMessage& m) { return is_reply_to(m, 2) && m.has_body_list(); }));
  EXPECT_TRUE(client.read_until([](const ServerMessage& m) { return is_reply_to(m, 3) && m.has_body_list(); }));
}

TEST_F(WebSocketTest, MalformedFrameGetsAnErrorThenACloseFrameWithTheReason) {
  WsClient client(server_.http_port());
  ASSERT_TRUE(client.handshake());
  ASSERT_TRUE(client.send_bytes(std::string("\x04\xff\xff\xff\xff", 5)));  // 4 bytes that are no ClientMessage
  const auto reply = client.read();
  ASSERT_TRUE(reply && reply->has_error()) << (reply ? reply->DebugString() : "no reply");
  EXPECT_EQ(reply->error().code(), tumble::v1::MALFORMED_FRAME);
  EXPECT_TRUE(client.closed_by_server());
  ASSERT_TRUE(client.got_close_frame());
  EXPECT_EQ(client.close_reason().code, websocket::close_code::policy_error);
  EXPECT_EQ(std::string(client.close_reason().reason), reply->error().message());

  WsClient next(server_.http_port());
  const auto welcome = next.handshake();
  EXPECT_TRUE(welcome && welcome->has_welcome());
}

TEST_F(WebSocketTest, ATextMessageIsRefusedWithAClearReason) {
  WsClient client(server_.http_port());
  ASSERT_TRUE(client.handshake());
  ASSERT_TRUE(client.send_text("{\"hello\": {}}"));
  const auto reply = client.read();
  ASSERT_TRUE(reply && reply->has_error()) << (reply ? reply->DebugString() : "no reply");
  EXPECT_EQ(reply->error().code(), tumble::v1::MALFORMED_FRAME);
  EXPECT_NE(reply->error().message().find("binary messages only"), std::string::npos) << reply->error().message();
  EXPECT_TRUE(client.closed_by_server());
  ASSERT_TRUE(client.got_close_frame());
  EXPECT_EQ(client.close_reason().code, websocket::close_code::policy_error);
  EXPECT_EQ(std::string(client.close_reason().reason), reply->error().message());
}

TEST_F(WebSocketTest, AFirstMessageOtherThanHelloIsRefused) {
  WsClient client(server_.http_port());
  ASSERT_TRUE(client.send(list_bodies(7)));
  const auto reply = client.read();
  ASSERT_TRUE(reply && reply->has_error());
  EXPECT_EQ(reply->error().code(), tumble::v1::HANDSHAKE_REQUIRED);
  EXPECT_EQ(reply->error().request_id(), 7u);
  EXPECT_TRUE(client.closed_by_server());
}

TEST_F(WebSocketTest, APageOfAnotherOriginIsRefused) {
  WsClient foreign(server_.http_port(), "http://attacker.example");
  EXPECT_FALSE(foreign.connected());
  EXPECT_EQ(foreign.handshake_status(), 403u);
  // The page the server itself serves has the server's origin.
  WsClient own(server_.http_port(), "http://127.0.0.1:" + std::to_string(server_.http_port()));
  ASSERT_TRUE(own.connected());
  const auto welcome = own.handshake();
  EXPECT_TRUE(welcome && welcome->has_welcome());
}

// A frame over --max-frame-bytes is refused from its length prefix, and the
// close frame says the message was too big (1009).
TEST_F(WebSocketTest, AFrameOverTheLimitClosesWithMessageTooBig) {
  WsClient client(server_.http_port());
  ASSERT_TRUE(client.handshake());
  ASSERT_TRUE(client.send_bytes(std::string("\x80\x80\x80\x01", 4)));  // announces 2 MiB, over the 1 MiB default
  const auto reply = client.read();
  ASSERT_TRUE(reply && reply->has_error()) << (reply ? reply->DebugString() : "no reply");
  EXPECT_EQ(reply->error().code(), tumble::v1::FRAME_TOO_LARGE);
  EXPECT_TRUE(client.closed_by_server());
  ASSERT_TRUE(client.got_close_frame());
  EXPECT_EQ(client.close_reason().code, websocket::close_code::too_big);
  EXPECT_EQ(std::string(client.close_reason().reason), reply->error().message());
}

// RFC 6455 5.2: a 64-bit payload length must have its most significant bit
// clear. Such a frame header gets MALFORMED_FRAME in a binary message, a
// close frame of 1002 with the reason, and the end of the connection, byte
// for byte; no payload is waited for.
TEST_F(WebSocketTest, AFrameLengthWithItsTopBitSetIsAProtocolError) {
  HttpClient socket(server_.http_port());
  ASSERT_TRUE(socket.send_request("GET", "/ws",
                                  "Connection: Upgrade\r\nUpgrade: websocket\r\nSec-WebSocket-Version: 13\r\n"
                                  "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"));
  const auto upgraded = socket.read_response();
  ASSERT_TRUE(upgraded);
  ASSERT_EQ(upgraded->result_int(), 101u);
  // A masked binary frame that announces 2^63 bytes, and a few of them.
  ASSERT_TRUE(
      socket.send_bytes(std::string("\x82\xff\x80\x00\x00\x00\x00\x00\x00\x00", 10) + std::string(4, '\0') + "0123"));

  const auto received = socket.bytes_until_closed();
  ASSERT_TRUE(received) << "the server did not close the connection";
  std::size_t at = 0;
  // The Error, in one binary message.
  ASSERT_GE(received->size(), at + 2);
  ASSERT_EQ(static_cast<unsigned char>((*received)[at]), 0x82);
  const std::size_t error_size = static_cast<unsigned char>((*received)[at + 1]);
  ASSERT_LT(error_size, 126u);
  wire::FrameReader reader;
  reader.append(received->data() + at + 2, error_size);
  std::string_view body;
  ASSERT_EQ(reader.next(body), wire::FrameStatus::frame);
  ServerMessage error;
  ASSERT_TRUE(error.ParseFromArray(body.data(), static_cast<int>(body.size())));
  ASSERT_TRUE(error.has_error()) << error.DebugString();
  EXPECT_EQ(error.error().code(), tumble::v1::MALFORMED_FRAME);
  const std::string sentence =
      "a WebSocket frame's 64-bit payload length has its most significant bit set, which RFC 6455 section 5.2 "
      "forbids";
  EXPECT_EQ(error.error().message(), sentence);
  at += 2 + error_size;
  // The close frame: 1002 (protocol error) and the sentence, cut to 123 bytes.
  const std::string reason = sentence.substr(0, 123);
  const std::string close = std::string("\x88", 1) + static_cast<char>(2 + reason.size()) + "\x03\xea" + reason;
  EXPECT_EQ(received->substr(at), close);

  // The server serves on.
  WsClient next(server_.http_port());
  const auto welcome = next.handshake();
  EXPECT_TRUE(welcome && welcome->has_welcome());
}

// A subscriber on WebSocket that disappears without a closing handshake
// costs a TCP subscriber nothing: its frames go on, tick after tick.
TEST_F(WebSocketTest, AVanishingWebSocketSubscriberDoesNotDisturbATcpOne) {
  RawClient tcp(server_.port());
  ASSERT_TRUE(tcp.handshake());
  ASSERT_TRUE(tcp.send(subscribe(2, 0)));
  ASSERT_TRUE(tcp.read_until([](const ServerMessage& m) { return is_reply_to(m, 2); }));
  {
    WsClient ws(server_.http_port());
    ASSERT_TRUE(ws.handshake());
    ASSERT_TRUE(ws.send(subscribe(2, 0)));
    ASSERT_TRUE(ws.read_until(is_frame));
    ASSERT_TRUE(clients_become(tcp, 2));
    ws.vanish();
  }
  const auto first = tcp.read_until(is_frame);
  ASSERT_TRUE(first);
  std::uint64_t tick = first->pose_frame().tick();
  const std::uint64_t until = tick + 240;  // a second of ticks
  while (tick < until) {
    const auto frame = tcp.read_until(is_frame);
    ASSERT_TRUE(frame) << "frames stopped at tick " << tick;
    EXPECT_GT(frame->pose_frame().tick(), tick);
    tick = frame->pose_frame().tick();
  }
  EXPECT_TRUE(clients_become(tcp, 1));
}

TEST(WebSocketAccess, AWrongTokenIsUnauthenticatedAndTheRightOneIsAController) {
  net::ServerConfig config = with_http();
  config.access.controller = "secret";
  TestServer server(kCrateAndBallScene, 240, config);

  WsClient wrong(server.http_port());
  const auto refused = wrong.handshake("ws-test", "guess");
  ASSERT_TRUE(refused && refused->has_error());
  EXPECT_EQ(refused->error().code(), tumble::v1::UNAUTHENTICATED);
  EXPECT_TRUE(wrong.closed_by_server());
  ASSERT_TRUE(wrong.got_close_frame());
  EXPECT_EQ(std::string(wrong.close_reason().reason), "the access token in Hello is not accepted by this server");

  WsClient right(server.http_port());
  const auto welcome = right.handshake("ws-test", "secret");
  ASSERT_TRUE(welcome && welcome->has_welcome());
  EXPECT_EQ(welcome->welcome().role(), tumble::v1::ROLE_CONTROLLER);
}

TEST(WebSocketLimits, WebSocketClientsCountTowardMaxConnections) {
  net::ServerConfig config = with_http();
  config.max_connections = 2;
  TestServer server(kCrateAndBallScene, 240, config);

  RawClient tcp(server.port());
  ASSERT_TRUE(tcp.handshake());
  WsClient ws(server.http_port());
  ASSERT_TRUE(ws.handshake());
  EXPECT_TRUE(clients_become(tcp, 2));

  // Full: a third client is refused, over either transport.
  WsClient third_ws(server.http_port());
  ASSERT_TRUE(third_ws.connected());  // the WebSocket handshake is HTTP's; the refusal is the protocol's
  const auto refused_ws = third_ws.read();
  ASSERT_TRUE(refused_ws && refused_ws->has_error());
  EXPECT_EQ(refused_ws->error().code(), tumble::v1::RESOURCE_EXHAUSTED);
  EXPECT_TRUE(third_ws.closed_by_server());
  RawClient third_tcp(server.port());
  const auto refused_tcp = third_tcp.read();
  ASSERT_TRUE(refused_tcp && refused_tcp->has_error());
  EXPECT_EQ(refused_tcp->error().code(), tumble::v1::RESOURCE_EXHAUSTED);

  // The WebSocket client leaves: its place is free again.
  ws.vanish();
  ASSERT_TRUE(clients_become(tcp, 1));
  WsClient again(server.http_port());
  const auto welcome = again.handshake();
  EXPECT_TRUE(welcome && welcome->has_welcome());
}

TEST(WebSocketLimits, AWebSocketThatNeverSaysHelloIsCutOff) {
  net::SessionLimits limits;
  limits.handshake_timeout = milliseconds(300);
  TestServer server(kCrateAndBallScene, 240, with_http(limits));
  WsClient silent(server.http_port());
  ASSERT_TRUE(silent.connected());
  const auto reply = silent.read(std::chrono::seconds(20));
  ASSERT_TRUE(reply && reply->has_error());
  EXPECT_EQ(reply->error().code(), tumble::v1::HANDSHAKE_REQUIRED);
  EXPECT_EQ(reply->error().message(), "no Hello within 0.3 s of connecting");
  EXPECT_TRUE(silent.closed_by_server());
}

TEST(WebSocketLimits, RequestsOverTheRateAreRefused) {
  net::SessionLimits limits;
  limits.commands_per_second = 5;
  limits.command_burst = 5;
  TestServer server(kCrateAndBallScene, 240, with_http(limits));
  WsClient client(server.http_port());
  ASSERT_TRUE(client.handshake());
  std::string burst;
  for (std::uint64_t id = 1; id <= 20; ++id) burst += wire::encode_frame(list_bodies(id));
  ASSERT_TRUE(client.send_bytes(burst));
  int served = 0;
  int limited = 0;
  std::set<std::uint64_t> answered;
  while (answered.size() < 20) {
    const auto reply = client.read();
    ASSERT_TRUE(reply) << "only " << answered.size() << " replies";
    for (std::uint64_t id = 1; id <= 20; ++id) {
      if (!is_reply_to(*reply, id) || !answered.insert(id).second) continue;
      if (reply->has_body_list()) ++served;
      if (reply->has_error() && reply->error().code() == tumble::v1::RATE_LIMITED) ++limited;
    }
  }
  EXPECT_GE(served, 5);
  EXPECT_GE(limited, 10);
  EXPECT_EQ(served + limited, 20);
}

TEST(WebSocketLimits, AWebSocketClientThatStopsReadingIsDisconnected) {
  net::SessionLimits limits;
  limits.max_undelivered = milliseconds(500);
  std::ostringstream scene;  // 400 spheres: frames of kilobytes, every tick
  scene << R"({"gravity": [0, 0, 0], "bodies": [)";
  for (int i = 0; i < 400; ++i) {
    scene << (i ? "," : "") << R"({"shape": {"sphere": {"radius": 0.5}}, "mass": 1, "position": [)" << 3 * i
          << ", 0, 0]}";
  }
  scene << "]}";
  TestServer server(scene.str(), 240, with_http(limits));
  RawClient observer(server.port());
  ASSERT_TRUE(observer.handshake());

  WsClient sleeper(server.http_port());
  ASSERT_TRUE(sleeper.handshake());
  ASSERT_TRUE(sleeper.send(subscribe(2, 0)));
  // Never reads: once the socket buffers are full a frame waits, and after
  // 0.5 s of that the server lets go of the client.
  EXPECT_TRUE(clients_become(observer, 1));
}

}  // namespace
}  // namespace tumble::test
