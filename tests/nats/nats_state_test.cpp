// tumbled --nats-state: the world's checkpoints in a JetStream key-value
// bucket, end to end with real nats-server processes (one node, or a
// JetStream cluster of three) and real tumbled processes. Every check is on
// what the bucket holds and what tumbled answers, on ticks and revisions.
#include <gtest/gtest.h>

#include <csignal>
#include <fstream>
#include <optional>

#include "cli_helpers.h"
#include "clock_requests.h"
#include "nats_messages.h"
#include "nats_server_process.h"
#include "nats_test_client.h"
#include "poll_until.h"
#include "process.h"
#include "sim/state_file.h"
#include "tumble/v1/protocol.pb.h"
#include "tumble/v1/state.pb.h"
#include "tumble/v1/world_info.pb.h"
#include "tumbled_process.h"

namespace tumble::test {
namespace {

using tumble::v1::ClientMessage;
using tumble::v1::ServerMessage;

constexpr const char* kBucket = "tumble_worlds";
constexpr const char* kEmptyScene = R"({"gravity": [0, 0, 0], "bodies": []})";

// The world's checkpoint as the bucket holds it.
struct Checkpoint {
  tumble::v1::WorldState state;
  std::uint64_t revision = 0;
};

// The checkpoint of world "lab", read through `client`; nullopt while there
// is none (or it does not parse: a test failure).
std::optional<Checkpoint> checkpoint_of(NatsTestClient& client) {
  const auto value = client.kv_get(kBucket, "lab");
  if (!value) return std::nullopt;
  Checkpoint checkpoint;
  checkpoint.revision = value->revision;
  sim::StateFileFormat format{};
  const sim::Status status = sim::parse_state_file(value->data, &checkpoint.state, &format);
  EXPECT_TRUE(status.ok()) << status.message();
  if (!status.ok()) return std::nullopt;
  return checkpoint;
}

const tumble::v1::SavedBody* body_named(const tumble::v1::WorldState& state, const std::string& name) {
  for (const tumble::v1::SavedBody& body : state.bodies()) {
    if (body.spec().name() == name) return &body;
  }
  return nullptr;
}

std::string list_bodies_request(std::uint64_t request_id) {
  ClientMessage message;
  message.set_request_id(request_id);
  message.mutable_list_bodies();
  return message.SerializeAsString();
}

class NatsState : public ::testing::Test {
 protected:
  void SetUp() override {
    nats_.enable_jetstream();
    ASSERT_TRUE(nats_.start()) << nats_.log();
  }

  std::unique_ptr<TumbledProcess> start_tumbled(std::vector<std::string> args = {},
                                                const std::string& scene = kFloatingScene) {
    std::vector<std::string> all = {"--nats", nats_.url(), "--world", "lab", "--nats-state"};
    all.insert(all.end(), args.begin(), args.end());
    return std::make_unique<TumbledProcess>(scene, all);
  }

  // The Stats reply over .rpc once tumbled answers there.
  std::optional<tumble::v1::Stats> stats(NatsTestClient& client) {
    std::optional<tumble::v1::Stats> stats;
    poll_until([&] {
      auto reply = client.request("tumble.v1.lab.rpc", stats_request(1), std::chrono::milliseconds(500));
      if (reply && parse_server_message(*reply).has_stats()) stats = parse_server_message(*reply).stats();
      return stats.has_value();
    });
    return stats;
  }

  NatsServerProcess nats_;
};

TEST_F(NatsState, CheckpointsLandInTheBucketAndTheNextStartResumesFromTheLastOne) {
  auto first = start_tumbled({"--checkpoint-interval", "0.1"});
  ASSERT_TRUE(first->started()) << first->log();
  NatsTestClient client(nats_.url());
  ASSERT_TRUE(stats(client));
  // Checkpoints keep coming: a later one has a later tick.
  std::optional<Checkpoint> earlier;
  ASSERT_TRUE(poll_until([&] { return (earlier = checkpoint_of(client)).has_value(); })) << client.error();
  std::optional<Checkpoint> later;
  ASSERT_TRUE(poll_until([&] {
    later = checkpoint_of(client);
    return later && later->state.tick() > earlier->state.tick();
  }));
  EXPECT_GT(later->revision, earlier->revision);

  // Stats say what was written. Paused, the world stops changing, so the
  // last checkpoint reported comes to be the one the bucket holds.
  const auto clock = [&](ClockRequest kind, std::uint64_t id) {
    return parse_server_message(*client.request("tumble.v1.lab.rpc", clock_request(kind, id, 0).SerializeAsString()));
  };
  ASSERT_TRUE(clock(ClockRequest::pause, 5).has_ack());
  std::optional<tumble::v1::Stats> now;
  std::optional<Checkpoint> held;
  ASSERT_TRUE(poll_until([&] {
    now = stats(client);
    held = checkpoint_of(client);
    return now && held && held->state.tick() == now->tick() && now->checkpoints().last_tick() == now->tick();
  })) << (now ? now->DebugString() : "no stats");
  const tumble::v1::Checkpoints& saved = now->checkpoints();
  EXPECT_EQ(saved.destination(), "bucket tumble_worlds, key lab");
  EXPECT_DOUBLE_EQ(saved.interval_s(), 0.1);
  EXPECT_GE(saved.written(), 2u);
  EXPECT_EQ(saved.failed(), 0u);
  EXPECT_EQ(saved.last_bytes(), held->state.ByteSizeLong());
  EXPECT_GT(saved.last_write_ms(), 0.0);
  EXPECT_GE(saved.write_ms_max(), saved.last_write_ms());
  ASSERT_TRUE(clock(ClockRequest::resume, 6).has_ack());

  // 480 N for one tick of 1/240 s on 2 kg: the crate drifts at 1 m/s.
  const ServerMessage ack = parse_server_message(*client.request("tumble.v1.lab.rpc", force_request("crate", 480, 2)));
  ASSERT_TRUE(ack.has_ack()) << ack.DebugString();
  ASSERT_EQ(terminate(*first), 0) << first->log();
  EXPECT_NE(first->log().find("saved the world at tick"), std::string::npos) << first->log();
  const std::optional<Checkpoint> last = checkpoint_of(client);
  ASSERT_TRUE(last);
  ASSERT_GE(last->state.tick(), ack.ack().applied_tick());  // a state is the end of its tick
  const tumble::v1::SavedBody* crate = body_named(last->state, "crate");
  ASSERT_NE(crate, nullptr);
  EXPECT_DOUBLE_EQ(crate->linear_momentum().x(), 2.0);

  // An empty scene only seeds a world the bucket has not: this one resumes.
  auto second = start_tumbled({}, kEmptyScene);
  ASSERT_TRUE(second->started()) << second->log();
  const auto resumed = stats(client);
  ASSERT_TRUE(resumed);
  EXPECT_GE(resumed->tick(), last->state.tick());
  const ServerMessage list = parse_server_message(*client.request("tumble.v1.lab.rpc", list_bodies_request(3)));
  ASSERT_EQ(list.body_list().bodies_size(), 2) << list.DebugString();
  ASSERT_EQ(terminate(*second), 0) << second->log();
  // It went on from there: the crate is where 1 m/s took it since.
  const std::optional<Checkpoint> after = checkpoint_of(client);
  ASSERT_TRUE(after);
  ASSERT_GT(after->state.tick(), last->state.tick());
  const tumble::v1::SavedBody* moved = body_named(after->state, "crate");
  ASSERT_NE(moved, nullptr);
  const double elapsed = after->state.sim_time() - last->state.sim_time();
  EXPECT_NEAR(moved->spec().position().x() - crate->spec().position().x(), elapsed, 1e-9);
  EXPECT_DOUBLE_EQ(moved->linear_momentum().x(), 2.0);
}

TEST_F(NatsState, ADamagedValueIsRefusedNamingTheBucketAndKeyUnlessResetStartsFromTheScene) {
  NatsTestClient client(nats_.url());
  // The first run makes the bucket and leaves a good checkpoint.
  auto maker = start_tumbled();
  ASSERT_TRUE(maker->started()) << maker->log();
  ASSERT_EQ(terminate(*maker), 0) << maker->log();
  const auto good = client.kv_get(kBucket, "lab");
  ASSERT_TRUE(good) << client.error();

  for (const std::string& damaged : {std::string("not a world"), good->data.substr(0, good->data.size() - 7),
                                     good->data.substr(0, 40) + "x" + good->data.substr(41)}) {
    ASSERT_TRUE(client.kv_put(kBucket, "lab", damaged)) << client.error();
    auto refused = start_tumbled();
    EXPECT_FALSE(refused->started());
    EXPECT_EQ(refused->process().wait(std::chrono::seconds(30)), 1);
    const std::string log = refused->log();
    EXPECT_NE(log.find("bucket tumble_worlds, key lab"), std::string::npos) << log;
    EXPECT_NE(log.find("--nats-state-reset"), std::string::npos) << log;
    // Nothing was written over it.
    EXPECT_EQ(client.kv_get(kBucket, "lab")->data, damaged);
  }

  auto reset = start_tumbled({"--nats-state-reset", "--checkpoint-interval", "0.1"});
  ASSERT_TRUE(reset->started()) << reset->log();
  EXPECT_NE(reset->log().find("--nats-state-reset: starting from the scene"), std::string::npos) << reset->log();
  // The scene's two bodies, once its link answers (started() means the
  // TCP port listens, not that NATS has the world's subscription yet), and
  // the bad value replaced by a checkpoint.
  std::optional<std::string> listed;
  ASSERT_TRUE(poll_until([&] {
    return (listed = client.request("tumble.v1.lab.rpc", list_bodies_request(1))).has_value();
  })) << client.error();
  const ServerMessage list = parse_server_message(*listed);
  EXPECT_EQ(list.body_list().bodies_size(), 2) << list.DebugString();
  EXPECT_TRUE(poll_until([&] {
    const auto value = client.kv_get(kBucket, "lab");
    tumble::v1::WorldState state;
    sim::StateFileFormat format{};
    return value && sim::parse_state_file(value->data, &state, &format).ok();
  }));
}

TEST(NatsStateWithoutJetStream, TumbledSaysTheServerHasNoJetStreamAndExits) {
  NatsServerProcess nats;
  ASSERT_TRUE(nats.start()) << nats.log();
  TumbledProcess tumbled(kFloatingScene, {"--nats", nats.url(), "--world", "lab", "--nats-state"});
  EXPECT_FALSE(tumbled.started());
  EXPECT_EQ(tumbled.process().wait(std::chrono::seconds(30)), 1);
  EXPECT_NE(tumbled.log().find("--nats-state: bucket tumble_worlds: the NATS server has no JetStream"),
            std::string::npos)
      << tumbled.log();
}

// What answers tumble.v1.worlds for world "lab" through `client`: the
// leader's WorldInfo (nullopt when none leads) and how many standbys answer.
struct LabRoles {
  std::optional<tumble::v1::WorldInfo> leader;
  std::size_t standbys = 0;
};
LabRoles lab_roles(NatsTestClient& client) {
  LabRoles roles;
  for (const std::string& reply : client.request_many("tumble.v1.worlds", "")) {
    tumble::v1::WorldInfo info;
    if (!info.ParseFromString(reply) || info.world() != "lab") continue;
    if (info.standby()) {
      ++roles.standbys;
    } else {
      roles.leader = info;
    }
  }
  return roles;
}

TEST(NatsStateCluster, TheBucketHasThreeReplicasNoCheckpointIsLostWhenANodeIsKilledAndTheNextTakeoverWorks) {
  NatsCluster cluster({}, /*jetstream=*/true);
  ASSERT_TRUE(cluster.start()) << cluster.node(0).log() << cluster.node(1).log() << cluster.node(2).log();
  // tumbled's node is node 0, the first URL.
  TumbledProcess tumbled(kFloatingScene, {"--nats", cluster.urls(), "--world", "lab", "--nats-state",
                                          "--checkpoint-interval", "0.1", "--nats-stream", "f=full@10"});
  ASSERT_TRUE(tumbled.started()) << tumbled.log();
  EXPECT_NE(tumbled.log().find("made the JetStream bucket tumble_worlds with 3 replica(s)"), std::string::npos)
      << tumbled.log();
  NatsTestClient survivor(cluster.node(1).url());
  ASSERT_TRUE(survivor.connected());
  EXPECT_TRUE(poll_until([&] { return survivor.kv_current_replicas(kBucket) == 3; })) << survivor.error();
  // Each node reads the checkpoints.
  for (std::size_t i = 0; i < 3; ++i) {
    NatsTestClient reader(cluster.node(i).url());
    EXPECT_TRUE(poll_until([&] { return checkpoint_of(reader).has_value(); })) << "node " << i;
  }

  std::optional<Checkpoint> before;
  ASSERT_TRUE(poll_until([&] { return (before = checkpoint_of(survivor)).has_value(); }));
  cluster.node(0).kill();
  // tumbled goes on through a survivor, and its checkpoints with it; none
  // read after the kill is older than one read before it.
  std::optional<Checkpoint> after;
  EXPECT_TRUE(poll_until(
      [&] {
        after = checkpoint_of(survivor);
        if (after) {
          EXPECT_GE(after->state.tick(), before->state.tick());
        }
        return after && after->revision > before->revision + 2;
      },
      std::chrono::seconds(30)))
      << tumbled.log();

  // With that node still down, the next takeover works: a standby started
  // now leads once the leader is killed, and goes on from its checkpoint.
  LabRoles roles;
  ASSERT_TRUE(poll_until([&] { return (roles = lab_roles(survivor)).leader.has_value(); }));
  const std::uint64_t old_epoch = roles.leader->epoch();
  const std::string dir = make_temp_dir();
  std::ofstream(dir + "/scene.json") << kFloatingScene;
  ChildProcess standby({tumbled_path(), "--scene", dir + "/scene.json", "--listen", "none", "--nats", cluster.urls(),
                        "--world", "lab", "--standby", "--checkpoint-interval", "0.1"},
                       dir + "/standby.log");
  ASSERT_TRUE(poll_until([&] { return lab_roles(survivor).standbys == 1; })) << read_file(dir + "/standby.log");
  const std::optional<Checkpoint> last_of_old = checkpoint_of(survivor);
  ASSERT_TRUE(last_of_old);
  tumbled.process().signal(SIGKILL);
  ASSERT_EQ(tumbled.process().wait(std::chrono::seconds(10)), 128 + SIGKILL);
  ASSERT_TRUE(poll_until([&] {
    roles = lab_roles(survivor);
    return roles.leader && roles.leader->epoch() > old_epoch;
  })) << read_file(dir + "/standby.log");
  std::optional<Checkpoint> of_new;
  EXPECT_TRUE(poll_until([&] {
    of_new = checkpoint_of(survivor);
    return of_new && of_new->revision > last_of_old->revision && of_new->state.tick() > last_of_old->state.tick();
  })) << read_file(dir + "/standby.log");
  standby.signal(SIGTERM);
  EXPECT_EQ(standby.wait(std::chrono::seconds(30)), 0) << read_file(dir + "/standby.log");
  const auto last = checkpoint_of(survivor);
  ASSERT_TRUE(last);
  EXPECT_GE(last->state.tick(), of_new->state.tick());
}

TEST(NatsStateCluster, AfterTheWholeClusterAndTheServerRestartTheWorldGoesOnFromItsLastCheckpoint) {
  NatsCluster cluster({}, /*jetstream=*/true);
  ASSERT_TRUE(cluster.start()) << cluster.node(0).log();
  const std::vector<std::string> args = {"--nats",       cluster.urls(),          "--world", "lab",
                                         "--nats-state", "--checkpoint-interval", "0.1"};
  std::optional<Checkpoint> last;
  {
    TumbledProcess tumbled(kFloatingScene, args);
    ASSERT_TRUE(tumbled.started()) << tumbled.log();
    NatsTestClient client(cluster.node(1).url());
    // 480 N for one tick of 1/240 s on 2 kg: the crate drifts at 1 m/s.
    std::optional<std::string> reply;
    ASSERT_TRUE(poll_until([&] {
      reply = client.request("tumble.v1.lab.rpc", force_request("crate", 480, 1), std::chrono::milliseconds(500));
      return reply.has_value();
    }));
    ASSERT_TRUE(parse_server_message(*reply).has_ack()) << parse_server_message(*reply).DebugString();
    const std::uint64_t pushed = parse_server_message(*reply).ack().applied_tick();
    ASSERT_TRUE(poll_until([&] {
      last = checkpoint_of(client);
      return last && last->state.tick() > pushed;
    }));
    // Everything goes at once: the server first, then every node.
    tumbled.process().signal(SIGKILL);
    tumbled.process().wait(std::chrono::seconds(10));
    last = checkpoint_of(client);
    ASSERT_TRUE(last);
  }
  for (std::size_t i = 0; i < 3; ++i) cluster.node(i).kill();
  ASSERT_TRUE(cluster.start()) << cluster.node(0).log();

  // The scene is not used: the world resumes from the checkpoint, where the crate drifts on.
  TumbledProcess again(kFloatingScene, args);
  ASSERT_TRUE(again.started()) << again.log();
  EXPECT_NE(again.log().find("from bucket tumble_worlds, key lab"), std::string::npos) << again.log();
  NatsTestClient client(cluster.node(2).url());
  std::optional<Checkpoint> later;
  ASSERT_TRUE(poll_until([&] {
    later = checkpoint_of(client);
    return later && later->state.tick() > last->state.tick();
  }));
  const tumble::v1::SavedBody* crate = body_named(later->state, "crate");
  ASSERT_NE(crate, nullptr);
  EXPECT_DOUBLE_EQ(crate->linear_momentum().x(), 2.0);
  EXPECT_NEAR(crate->spec().position().x() - body_named(last->state, "crate")->spec().position().x(),
              later->state.sim_time() - last->state.sim_time(), 1e-9);
}

}  // namespace
}  // namespace tumble::test
