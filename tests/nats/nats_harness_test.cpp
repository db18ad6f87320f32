// The NATS test harness itself: nats-server processes that start, route
// into a cluster, die by SIGKILL and come back on the same port, and the
// test client that talks to them.
#include <gtest/gtest.h>

#include <algorithm>
#include <thread>

#include "nats_server_process.h"
#include "nats_test_client.h"
#include "poll_until.h"

namespace tumble::test {
namespace {

TEST(NatsHarness, ANodeStartsAndCarriesMessages) {
  NatsServerProcess node;
  ASSERT_TRUE(node.start()) << node.log();
  NatsTestClient publisher(node.url());
  NatsTestClient subscriber(node.url());
  ASSERT_TRUE(publisher.connected()) << publisher.error();
  ASSERT_TRUE(subscriber.connected()) << subscriber.error();
  auto collector = subscriber.subscribe("harness.>");
  ASSERT_NE(collector, nullptr) << subscriber.error();
  ASSERT_EQ(publisher.publish("harness.one", "hello"), NATS_OK);
  ASSERT_TRUE(collector->wait_count(1));
  EXPECT_EQ(collector->messages()[0].subject, "harness.one");
  EXPECT_EQ(collector->messages()[0].data, "hello");
}

TEST(NatsHarness, AKilledNodeComesBackOnItsPortAndClientsReconnect) {
  NatsServerProcess node;
  ASSERT_TRUE(node.start()) << node.log();
  NatsTestClient client(node.url());
  ASSERT_TRUE(client.connected()) << client.error();
  const std::uint16_t port = node.port();
  node.kill();
  EXPECT_FALSE(node.running());
  EXPECT_NE(client.flush(std::chrono::milliseconds(300)), NATS_OK);  // nobody answers the PING
  ASSERT_TRUE(node.start()) << node.log();
  EXPECT_EQ(node.port(), port);
  auto collector = client.subscribe("after.restart");
  ASSERT_NE(collector, nullptr) << client.error();
  ASSERT_EQ(client.publish("after.restart", "x"), NATS_OK);
  EXPECT_TRUE(collector->wait_count(1));
}

TEST(NatsHarness, RequestManyCollectsEveryResponder) {
  NatsServerProcess node;
  ASSERT_TRUE(node.start()) << node.log();
  NatsTestClient responders(node.url());
  NatsTestClient requester(node.url());
  auto a = responders.subscribe("who");
  auto b = responders.subscribe("who");
  ASSERT_TRUE(a && b);
  // Each responder answers the request it sees, from its reply subject.
  std::thread answer([&] {
    for (auto [collector, name] : {std::pair{a.get(), "a"}, std::pair{b.get(), "b"}}) {
      if (collector->wait_count(1)) responders.publish(collector->messages()[0].reply, name);
    }
  });
  std::vector<std::string> replies = requester.request_many("who", "");
  answer.join();
  std::sort(replies.begin(), replies.end());
  EXPECT_EQ(replies, (std::vector<std::string>{"a", "b"}));
}

TEST(NatsHarness, AClusterOfThreeRoutesMessagesBetweenNodes) {
  NatsCluster cluster;
  ASSERT_TRUE(cluster.start()) << cluster.node(0).log();
  NatsTestClient on_a(cluster.node(0).url());
  NatsTestClient on_c(cluster.node(2).url());
  ASSERT_TRUE(on_a.connected() && on_c.connected());
  auto collector = on_c.subscribe("across");
  ASSERT_NE(collector, nullptr);
  EXPECT_TRUE(on_a.wait_for_interest("across", *collector));
}

TEST(NatsHarness, AHeldSubscriberIsASlowConsumerThatDropsMessages) {
  NatsServerProcess node;
  ASSERT_TRUE(node.start()) << node.log();
  NatsTestClient client(node.url());
  auto collector = client.subscribe("flood", 4, 1 << 20);
  ASSERT_NE(collector, nullptr);
  collector->hold();
  for (int i = 0; i < 50; ++i) client.publish("flood", std::to_string(i));
  client.flush();
  EXPECT_TRUE(poll_until([&] { return collector->dropped() > 0; }));
  collector->release();
  EXPECT_TRUE(collector->wait([](const auto& messages) { return !messages.empty(); }));
  EXPECT_LT(collector->messages().size(), 50u);
}

}  // namespace
}  // namespace tumble::test
