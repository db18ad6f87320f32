// tumbled publishing into a cluster of three nats-server processes:
// subscribers on every node get the same frames, and when the node tumbled
// is connected to is SIGKILLed, the stream goes on through the others
// while TCP clients are served throughout. Assertions are on sequences,
// ticks and what NATS delivers, not on wall time.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "cli_helpers.h"
#include "nats_messages.h"
#include "nats_server_process.h"
#include "nats_test_client.h"
#include "poll_until.h"
#include "tumbled_process.h"

namespace tumble::test {
namespace {

using nlohmann::json;
constexpr std::uint64_t kTickRateHz = 240;  // tumbled's default

// The frames a collector holds, by sequence.
std::map<std::uint64_t, std::string> by_sequence(NatsCollector& collector) {
  std::map<std::uint64_t, std::string> frames;
  for (const NatsMessage& m : collector.messages())
    frames[parse_server_message(m.data).pose_frame().sequence()] = m.data;
  return frames;
}

std::uint64_t last_sequence(NatsCollector& collector) {
  const std::vector<NatsMessage> messages = collector.messages();
  return messages.empty() ? 0 : parse_server_message(messages.back().data).pose_frame().sequence();
}

class NatsClusterWorld : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(cluster_.start()) << cluster_.node(0).log();
    tumbled_ = std::make_unique<TumbledProcess>(
        kFloatingScene,
        std::vector<std::string>{"--nats", cluster_.urls(), "--world", "lab", "--nats-stream", "q=quantized@60"});
    ASSERT_TRUE(tumbled_->started()) << tumbled_->log();
    for (std::size_t i = 0; i < 3; ++i) {
      clients_.push_back(std::make_unique<NatsTestClient>(cluster_.node(i).url()));
      ASSERT_TRUE(clients_[i]->connected()) << clients_[i]->error();
    }
  }

  // tumbled's link as it reports it over .rpc, asked through node `via`.
  tumble::v1::NatsLink link_through(std::size_t via) {
    auto reply = clients_[via]->request("tumble.v1.lab.rpc", stats_request(1), std::chrono::milliseconds(500));
    return reply ? parse_server_message(*reply).stats().nats() : tumble::v1::NatsLink{};
  }

  NatsCluster cluster_;
  std::unique_ptr<TumbledProcess> tumbled_;
  std::vector<std::unique_ptr<NatsTestClient>> clients_;
};

TEST_F(NatsClusterWorld, SubscribersOnEveryNodeGetTheSameFrames) {
  std::vector<std::unique_ptr<NatsCollector>> frames;
  for (auto& client : clients_) frames.push_back(client->subscribe("tumble.v1.lab.poses.q"));
  for (auto& collector : frames) ASSERT_TRUE(collector && collector->wait_count(60)) << tumbled_->log();
  // Wait until every node has delivered one sequence that all have passed.
  std::uint64_t upto = 0;
  for (auto& collector : frames) upto = std::max(upto, last_sequence(*collector));
  for (auto& collector : frames) {
    ASSERT_TRUE(collector->wait([&](const std::vector<NatsMessage>& messages) {
      return parse_server_message(messages.back().data).pose_frame().sequence() >= upto;
    }));
  }
  const std::vector<std::map<std::uint64_t, std::string>> seen = {by_sequence(*frames[0]), by_sequence(*frames[1]),
                                                                  by_sequence(*frames[2])};
  std::uint64_t from = 0;
  for (const auto& node : seen) from = std::max(from, node.begin()->first);
  ASSERT_LT(from + 30, upto) << "the three subscriptions overlap by 30 frames at least";
  // From the latest first frame on, each node delivered every frame, byte for byte the same.
  for (std::uint64_t sequence = from; sequence <= upto; ++sequence) {
    for (std::size_t node = 0; node < 3; ++node) {
      ASSERT_EQ(seen[node].count(sequence), 1u) << "node " << node << " missed sequence " << sequence;
      EXPECT_EQ(seen[node].at(sequence), seen[0].at(sequence)) << "node " << node << ", sequence " << sequence;
    }
  }
}

TEST_F(NatsClusterWorld, WhenTumbledsNodeIsKilledItPublishesThroughAnotherWithinFiveSecondsOfTicks) {
  tumble::v1::NatsLink link;
  ASSERT_TRUE(poll_until([&] {
    link = link_through(1);
    return link.connected();
  })) << tumbled_->log();
  std::size_t victim = 3;
  for (std::size_t i = 0; i < 3; ++i) {
    if (link.server_url() == cluster_.node(i).url()) victim = i;
  }
  ASSERT_LT(victim, 3u) << "tumbled is connected to " << link.server_url() << ", which is no node of the cluster";
  const std::size_t survivor = (victim + 1) % 3;
  auto frames = clients_[survivor]->subscribe("tumble.v1.lab.poses.q");
  ASSERT_TRUE(frames && frames->wait_count(10));

  cluster_.node(victim).kill();
  const std::uint64_t sequence_at_kill = last_sequence(*frames);
  // TCP clients are served while tumbled has no NATS server.
  const json during = run_json(*tumbled_, {"stats"});
  const std::uint64_t tick_at_kill = during.value("tick", std::uint64_t{0});
  ASSERT_GT(tick_at_kill, 0u) << during.dump();

  // Back through a survivor: the first .rpc answered is a tick of tumbled's own clock.
  ASSERT_TRUE(poll_until([&] {
    link = link_through(survivor);
    return link.connected();
  })) << tumbled_->log();
  EXPECT_NE(link.server_url(), cluster_.node(victim).url());
  EXPECT_EQ(link.reconnects(), 1u);
  const json after = run_json(*tumbled_, {"stats"});
  const std::uint64_t tick_back = after.value("tick", std::uint64_t{0});
  EXPECT_LE(tick_back - tick_at_kill, 5 * kTickRateHz) << "ticks from the kill to an answer through a survivor";

  // Frames go on for the survivor's subscriber, in sequence.
  ASSERT_TRUE(frames->wait([&](const std::vector<NatsMessage>& messages) {
    return parse_server_message(messages.back().data).pose_frame().sequence() > sequence_at_kill + 60;
  })) << tumbled_->log();
  const std::vector<NatsMessage> messages = frames->messages();
  for (std::size_t i = 1; i < messages.size(); ++i) {
    EXPECT_GT(parse_server_message(messages[i].data).pose_frame().sequence(),
              parse_server_message(messages[i - 1].data).pose_frame().sequence());
  }
}

}  // namespace
}  // namespace tumble::test
