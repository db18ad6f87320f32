// Text from clients over a real socket: names and Hello strings past their
// limits are refused with errors naming the field and the limit, and a
// world's body list reaches a reading client in pages however large it is.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "raw_client.h"
#include "replies.h"
#include "requests.h"
#include "test_scenes.h"
#include "test_server.h"

namespace tumble::test {
namespace {

using tumble::v1::ClientMessage;
using tumble::v1::ServerMessage;

// Sends `request` and returns its reply (an Error or whatever answers it).
ServerMessage reply_to(RawClient& client, const ClientMessage& request) {
  EXPECT_TRUE(client.send(request));
  const auto reply = client.read_until([&](const ServerMessage& m) { return is_reply_to(m, request.request_id()); });
  EXPECT_TRUE(reply.has_value()) << "no reply to request " << request.request_id();
  return reply.value_or(ServerMessage{});
}

TEST(ClientText, AMillionByteBodyNameIsRefusedWithTheLimit) {
  TestServer server(kCrateScene);
  RawClient client(server.port());
  ASSERT_TRUE(client.handshake());

  const std::string huge(1000000, 'n');
  ServerMessage reply = reply_to(client, spawn_sphere(2, huge));
  ASSERT_TRUE(reply.has_error()) << reply.ShortDebugString().substr(0, 200);
  EXPECT_EQ(reply.error().code(), tumble::v1::INVALID_ARGUMENT);
  EXPECT_EQ(reply.error().message(), "body.name: 1000000 bytes, over the limit of 128 bytes");

  // The same limit on a name that only refers to a body: no million bytes echoed back.
  ClientMessage remove;
  remove.set_request_id(3);
  remove.mutable_remove_body()->mutable_body()->set_name(huge);
  reply = reply_to(client, remove);
  EXPECT_EQ(reply.error().message(), "body.name: 1000000 bytes, over the limit of 128 bytes");

  // Nothing was spawned, and the connection still serves.
  reply = reply_to(client, list_bodies(4));
  ASSERT_TRUE(reply.has_body_list());
  EXPECT_EQ(reply.body_list().bodies_size(), 1);
  reply = reply_to(client, spawn_sphere(5, std::string(128, 'n')));
  EXPECT_TRUE(reply.has_ack()) << reply.ShortDebugString();
}

TEST(ClientText, ANameOfDigitsOnlyIsRefusedBecauseItReadsAsAnId) {
  TestServer server(kCrateScene);
  RawClient client(server.port());
  ASSERT_TRUE(client.handshake());
  ServerMessage reply = reply_to(client, spawn_sphere(2, "123"));
  ASSERT_TRUE(reply.has_error());
  EXPECT_EQ(reply.error().code(), tumble::v1::INVALID_ARGUMENT);
  EXPECT_EQ(reply.error().message(),
            "body.name: '123' is digits only, which clients read as a body id; a name needs another character");
  EXPECT_TRUE(reply_to(client, spawn_sphere(3, "rock-123")).has_ack());
}

TEST(ClientText, HelloStringsPastTheirLimitsEndTheHandshake) {
  TestServer server(kCrateScene);
  {
    RawClient client(server.port());
    const auto reply = client.handshake(std::string(1000000, 'c'));
    ASSERT_TRUE(reply && reply->has_error());
    EXPECT_EQ(reply->error().code(), tumble::v1::INVALID_ARGUMENT);
    EXPECT_EQ(reply->error().message(), "Hello.client_name: 1000000 bytes, over the limit of 128 bytes");
    EXPECT_TRUE(client.closed_by_server());
  }
  {
    RawClient client(server.port());
    ClientMessage hello;
    hello.set_request_id(1);
    hello.mutable_hello()->set_protocol_version(tumble::v1::PROTOCOL_VERSION_CURRENT);
    hello.mutable_hello()->set_token(std::string(257, 't'));
    ASSERT_TRUE(client.send(hello));
    const auto reply = client.read();
    ASSERT_TRUE(reply && reply->has_error());
    EXPECT_EQ(reply->error().code(), tumble::v1::UNAUTHENTICATED);
    EXPECT_EQ(reply->error().message(), "Hello.token: 257 bytes, over the limit of 256 bytes");
    EXPECT_TRUE(client.closed_by_server());
  }
  RawClient fine(server.port());
  const auto welcome = fine.handshake(std::string(128, 'c'));
  EXPECT_TRUE(welcome && welcome->has_welcome());
}

TEST(ClientText, ABodyListLargerThanThePendingLimitArrivesInPages) {
  // 400 bodies of about 100 bytes each: 40 KB, ten times what this client may
  // leave unread. Pages of half the limit reach it one after the other.
  net::SessionLimits limits;
  limits.max_pending_bytes = 4096;
  TestServer server(row_of_spheres(400), 240, limits);
  RawClient client(server.port());
  ASSERT_TRUE(client.handshake());

  // An empty ListBodies, as a client that knows nothing of pages sends it.
  ServerMessage reply = reply_to(client, list_bodies(2));
  ASSERT_TRUE(reply.has_body_list()) << reply.ShortDebugString();
  const tumble::v1::BodyList& first = reply.body_list();
  EXPECT_EQ(first.total_bodies(), 400u);
  EXPECT_GT(first.bodies_size(), 0);
  EXPECT_LT(first.bodies_size(), 400);
  EXPECT_EQ(first.next_start_id(), first.bodies(first.bodies_size() - 1).id() + 1);

  std::vector<std::string> names;
  std::uint32_t start = 0;
  std::uint64_t request = 10;
  do {
    ClientMessage page = list_bodies(++request);
    page.mutable_list_bodies()->set_start_id(start);
    reply = reply_to(client, page);
    ASSERT_TRUE(reply.has_body_list()) << reply.ShortDebugString();
    EXPECT_LE(reply.ByteSizeLong(), 4096u / 2 + 64);  // a page and the BodyList's own fields
    for (const auto& body : reply.body_list().bodies()) names.push_back(body.name());
    start = reply.body_list().next_start_id();
  } while (start != 0 && names.size() <= 400);
  ASSERT_EQ(names.size(), 400u);
  for (std::size_t i = 0; i < names.size(); ++i) EXPECT_EQ(names[i], "s" + std::to_string(i));
}

}  // namespace
}  // namespace tumble::test
