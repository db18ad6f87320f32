// What `tumble worlds` and `tumble stats` print for a world served over NATS.
#include <gtest/gtest.h>

#include "output.h"

namespace tumble::cli {
namespace {

tumble::v1::WorldInfo demo_world() {
  tumble::v1::WorldInfo info;
  info.set_world("demo");
  info.set_tick(12345);
  info.set_tick_rate_hz(240);
  info.set_bodies(901);
  info.set_version("0.1.0");
  info.set_server_id("a1b2");
  info.set_events_subject("tumble.v1.demo.events");
  info.set_rpc_subject("tumble.v1.demo.rpc");
  info.set_query_subject("tumble.v1.demo.query");
  auto* q60 = info.add_streams();
  q60->set_name("q60");
  q60->set_subject("tumble.v1.demo.poses.q60");
  q60->set_encoding(tumble::v1::POSE_ENCODING_QUANTIZED);
  q60->set_rate_hz(60);
  q60->set_fields(tumble::v1::POSE_FIELDS_POSE);
  auto* d = info.add_streams();
  d->set_name("d12");
  d->set_subject("tumble.v1.demo.poses.d12");
  d->set_encoding(tumble::v1::POSE_ENCODING_DELTA);
  d->set_rate_hz(12.5);
  d->set_fields(tumble::v1::POSE_FIELDS_POSE_AND_VELOCITY);
  d->set_key_interval_s(1);
  d->set_rest_key_interval_s(30);
  d->set_joints(true);
  return info;
}

TEST(WorldsOutput, ATableOfWorldsWithTheirStreamsAsTheServerSpellsThem) {
  tumble::v1::WorldInfo lab = demo_world();
  lab.set_world("lab");
  lab.set_tick(7);
  lab.set_paused(true);
  lab.set_bodies(3);
  lab.clear_streams();
  EXPECT_EQ(format_world_table({demo_world(), lab}),
            "WORLD        TICK  RATE (Hz)  BODIES  STREAMS\n"
            "demo        12345        240     901  q60=quantized@60 d12=delta@12.5:all,joints\n"
            "lab    7 (paused)        240       3  -\n");
  EXPECT_EQ(format_world_table({}), "no worlds answered\n");
}

TEST(WorldsOutput, OneJsonObjectPerWorld) {
  EXPECT_EQ(
      json_line(world_info_json(demo_world())),
      "{\"world\": \"demo\", \"tick\": 12345, \"tick_rate_hz\": 240.0, \"bodies\": 901, \"paused\": false, "
      "\"version\": \"0.1.0\", \"server_id\": \"a1b2\", \"streams\": [{\"name\": \"q60\", \"subject\": "
      "\"tumble.v1.demo.poses.q60\", \"encoding\": \"quantized\", \"rate_hz\": 60.0, \"fields\": \"pose\", "
      "\"joints\": false, \"key_interval_s\": 0.0, \"rest_key_interval_s\": 0.0}, {\"name\": \"d12\", \"subject\": "
      "\"tumble.v1.demo.poses.d12\", \"encoding\": "
      "\"delta\", \"rate_hz\": 12.5, \"fields\": \"all\", \"joints\": true, \"key_interval_s\": 1.0, "
      "\"rest_key_interval_s\": 30.0}], "
      "\"events_subject\": "
      "\"tumble.v1.demo.events\", \"rpc_subject\": \"tumble.v1.demo.rpc\", \"query_subject\": "
      "\"tumble.v1.demo.query\", \"epoch\": 0, \"standby\": false, \"leader_id\": \"\"}\n");
}

TEST(WorldsOutput, AWorldKeptInJetStreamShowsItsLeaderWithItsEpochAndItsStandbys) {
  tumble::v1::WorldInfo leader = demo_world();
  leader.clear_streams();
  leader.set_epoch(9);
  leader.set_leader_id("a1b2");
  tumble::v1::WorldInfo standby;
  standby.set_world("demo");
  standby.set_server_id("c3d4");
  standby.set_standby(true);
  standby.set_leader_id("a1b2");
  standby.set_epoch(9);
  tumble::v1::WorldInfo orphan = standby;  // a world whose leader is gone: only its standby answers
  orphan.set_world("lab");
  orphan.set_server_id("e5f6");
  EXPECT_EQ(format_world_table({leader, standby, orphan}),
            "WORLD   TICK  RATE (Hz)  BODIES  STREAMS  LEADER          STANDBYS\n"
            "demo   12345        240     901  -        a1b2 (epoch 9)  c3d4\n"
            "lab        -          -       -  -        a1b2 (epoch 9)  e5f6\n");
}

tumble::v1::Stats stats_with_link() {
  tumble::v1::Stats stats;
  stats.set_tick(10);
  auto* nats = stats.mutable_nats();
  nats->set_world("demo");
  nats->set_connected(true);
  nats->set_server_url("nats://127.0.0.1:4222");
  nats->set_messages_out(120);
  nats->set_bytes_out(4096);
  nats->set_reconnects(2);
  nats->set_requests_in(5);
  nats->set_frames_dropped(1);
  return stats;
}

TEST(StatsOutput, TheNatsLinkIsABlockOfItsOwnWhenThereIsOne) {
  const std::string text = format_stats(stats_with_link());
  const std::size_t block = text.find("\nnats\n");
  ASSERT_NE(block, std::string::npos) << text;
  EXPECT_EQ(text.substr(block + 1),
            "nats\n"
            "  world           demo\n"
            "  connected       yes\n"
            "  server          nats://127.0.0.1:4222\n"
            "  messages out    120\n"
            "  bytes out       4096\n"
            "  reconnects      2\n"
            "  requests in     5\n"
            "  frames dropped  1\n");
  EXPECT_EQ(format_stats(tumble::v1::Stats{}).find("nats"), std::string::npos);
}

TEST(StatsOutput, TheNatsLinkIsAnObjectInJson) {
  const Json json = stats_json(stats_with_link());
  ASSERT_TRUE(json.contains("nats"));
  EXPECT_EQ(json_line(json["nats"]),
            "{\"world\": \"demo\", \"connected\": true, \"server_url\": \"nats://127.0.0.1:4222\", \"messages_out\": "
            "120, \"bytes_out\": 4096, \"reconnects\": 2, \"requests_in\": 5, \"frames_dropped\": 1}\n");
  EXPECT_FALSE(stats_json(tumble::v1::Stats{}).contains("nats"));
}

}  // namespace
}  // namespace tumble::cli
