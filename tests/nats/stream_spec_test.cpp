// The names and stream specs of --world and --nats-stream, and the
// numbering of a stream's frames.
#include <gtest/gtest.h>

#include "nats/sequence_planner.h"
#include "nats/stream_spec.h"

namespace tumble::nats {
namespace {

TEST(WorldName, PlainNamesPassAndDotsWildcardsAndSpacesDoNot) {
  EXPECT_FALSE(check_world_name("demo"));
  EXPECT_FALSE(check_world_name("Lab_2-b"));
  EXPECT_FALSE(check_world_name(std::string(64, 'w')));
  for (const char* bad : {"", "a.b", "a*", ">", "a b", "tumble.>"}) {
    const auto problem = check_world_name(bad);
    ASSERT_TRUE(problem) << bad;
    EXPECT_NE(problem->find("--world"), std::string::npos);
  }
  EXPECT_TRUE(check_world_name(std::string(65, 'w')));
}

TEST(StreamSpec, ParsesNameEncodingRateAndFields) {
  auto spec = parse_stream_spec("d30=delta@30:all");
  ASSERT_TRUE(std::holds_alternative<StreamSpec>(spec)) << std::get<std::string>(spec);
  EXPECT_EQ(std::get<StreamSpec>(spec).name, "d30");
  EXPECT_EQ(std::get<StreamSpec>(spec).encoding, tumble::v1::POSE_ENCODING_DELTA);
  EXPECT_DOUBLE_EQ(std::get<StreamSpec>(spec).rate_hz, 30);
  EXPECT_TRUE(std::get<StreamSpec>(spec).velocities);
  auto plain = parse_stream_spec(kDefaultStreamSpec);
  ASSERT_TRUE(std::holds_alternative<StreamSpec>(plain));
  EXPECT_EQ(std::get<StreamSpec>(plain).encoding, tumble::v1::POSE_ENCODING_QUANTIZED);
  EXPECT_FALSE(std::get<StreamSpec>(plain).velocities);
  EXPECT_DOUBLE_EQ(std::get<StreamSpec>(parse_stream_spec("f=full@12.5")).rate_hz, 12.5);
  EXPECT_FALSE(std::get<StreamSpec>(plain).joints);
  for (const auto& [text, velocities] :
       {std::pair{"j=full@30:all,joints", true}, std::pair{"j=delta@30:pose,joints", false},
        std::pair{"j=quantized@30:joints", false}}) {
    const auto with_joints = parse_stream_spec(text);
    ASSERT_TRUE(std::holds_alternative<StreamSpec>(with_joints)) << std::get<std::string>(with_joints);
    EXPECT_TRUE(std::get<StreamSpec>(with_joints).joints) << text;
    EXPECT_EQ(std::get<StreamSpec>(with_joints).velocities, velocities) << text;
  }
}

TEST(StreamSpec, EachBadPartIsNamed) {
  const std::pair<const char*, const char*> cases[] = {
      {"q60", "does not parse"},
      {"q60=quantized", "does not parse"},
      {"q.1=full@5", "stream name"},
      {"=full@5", "stream name"},
      {"q=zip@5", "encoding 'zip'"},
      {"q=full@0", "rate '0'"},
      {"q=full@fast", "rate 'fast'"},
      {"q=full@1e9", "rate"},
      {"q=full@5:vel", "fields 'vel'"},
      {"q=full@5x", "rate '5x'"},
      {"q=full@5:joints,all", "fields 'joints,all'"},
      {"q=full@5:all,", "fields 'all,'"},
  };
  for (const auto& [text, expected] : cases) {
    const auto spec = parse_stream_spec(text);
    ASSERT_TRUE(std::holds_alternative<std::string>(spec)) << text;
    EXPECT_NE(std::get<std::string>(spec).find(expected), std::string::npos) << std::get<std::string>(spec);
    EXPECT_NE(std::get<std::string>(spec).find("--nats-stream"), std::string::npos);
  }
}

TEST(SequencePlanner, NumbersFromOneWithAKeyFrameFirstAndThenEveryIntervalWhileBodiesMove) {
  SequencePlanner planner(0.25, 30);
  const double dt = 1.0 / 60;
  std::vector<std::uint64_t> keys;
  for (int i = 0; i < 60; ++i) {
    const SequencePlanner::Frame frame = planner.next(i * dt);
    EXPECT_EQ(frame.sequence, static_cast<std::uint64_t>(i + 1));
    if (frame.key) keys.push_back(frame.sequence);
    planner.changed();
  }
  // 0.25 s at 60 Hz is 15 frames: keys at sequences 1, 16, 31, 46.
  EXPECT_EQ(keys, (std::vector<std::uint64_t>{1, 16, 31, 46}));
}

TEST(SequencePlanner, AtRestTheKeyFrameWaitsTheRestIntervalAndAChangeBringsItBackToTheShortOne) {
  SequencePlanner planner(0.25, 2);
  const double dt = 1.0 / 60;
  std::vector<std::uint64_t> keys;
  for (int i = 0; i < 300; ++i) {
    const SequencePlanner::Frame frame = planner.next(i * dt);
    if (frame.key) keys.push_back(frame.sequence);
    // One body moves in the frame of sequence 150 (t = 149/60 s), nothing else.
    if (frame.sequence == 150) planner.changed();
  }
  // At rest, keys 2 s apart (121 frames after 1); the change at 150 makes
  // the next key due 0.25 s after the last one (121, t = 2 s): at 151,
  // the frame after the change. Then rest again: 2 s after 151.
  EXPECT_EQ(keys, (std::vector<std::uint64_t>{1, 121, 151, 271}));
}

TEST(SequencePlanner, AFrameNotPublishedMakesTheNextAKeyFrame) {
  SequencePlanner planner(10, 10);
  EXPECT_TRUE(planner.next(0).key);
  EXPECT_FALSE(planner.next(0.1).key);
  planner.lost();
  const SequencePlanner::Frame after = planner.next(0.2);
  EXPECT_TRUE(after.key);
  EXPECT_EQ(after.sequence, 3u);
  EXPECT_FALSE(planner.next(0.3).key);
}

}  // namespace
}  // namespace tumble::nats
