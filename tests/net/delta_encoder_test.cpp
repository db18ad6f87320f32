// DELTA frames: what one client gets, encoded against what it was last
// written, through the session's outbound queue as the server uses it.
#include <gtest/gtest.h>

#include <string_view>

#include "net/delta_encoder.h"
#include "net/outbound_queue.h"
#include "tumble/v1/protocol.pb.h"
#include "wire/frame.h"

namespace tumble::net {
namespace {

std::shared_ptr<const QuantizedFrame> frame_of(std::uint64_t tick, std::vector<std::pair<std::uint32_t, double>> xs) {
  auto frame = std::make_shared<QuantizedFrame>();
  frame->subscription_id = 1;
  frame->tick = tick;
  frame->sequence = tick;  // one frame a tick: the stream's frames in order
  const double q[4] = {1, 0, 0, 0};
  for (const auto& [id, x] : xs) {
    const double position[3] = {x, 0, 0};
    frame->bodies.push_back(wire::quantize_body(id, position, q, nullptr, nullptr));
  }
  return frame;
}

// The PoseFrame in framed bytes.
tumble::v1::PoseFrame parse(std::string_view bytes) {
  wire::FrameReader reader;
  reader.append(bytes.data(), bytes.size());
  std::string_view body;
  EXPECT_EQ(reader.next(body), wire::FrameStatus::frame);
  tumble::v1::ServerMessage message;
  EXPECT_TRUE(message.ParseFromArray(body.data(), static_cast<int>(body.size())));
  return message.pose_frame();
}

std::vector<std::uint32_t> ids_in(const tumble::v1::PoseFrame& frame) {
  std::vector<std::uint32_t> ids;
  const auto poses = wire::decode_quantized_poses(frame.packed());
  EXPECT_TRUE(poses.has_value());
  if (!poses) return ids;
  for (const auto& body : poses->bodies) ids.push_back(body.id);
  return ids;
}

TEST(DeltaEncoder, FirstFrameIsAKeyFrameThenOnlyChanges) {
  DeltaEncoder encoder;
  const auto key = parse(*encoder.encode(frame_of(1, {{1, 0.0}, {2, 1.0}, {3, 2.0}})));
  EXPECT_TRUE(key.key_frame());
  EXPECT_EQ(key.encoding(), tumble::v1::POSE_ENCODING_DELTA);
  EXPECT_EQ(ids_in(key), (std::vector<std::uint32_t>{1, 2, 3}));

  // Body 2 moves, 3 leaves, 4 arrives; a move under half a grid step is no change.
  const auto change = parse(*encoder.encode(frame_of(2, {{1, 0.0001}, {2, 1.5}, {4, 3.0}})));
  EXPECT_FALSE(change.key_frame());
  EXPECT_EQ(ids_in(change), (std::vector<std::uint32_t>{2, 4}));
  ASSERT_EQ(change.removed_ids_size(), 1);
  EXPECT_EQ(change.removed_ids(0), 3u);

  const auto idle = parse(*encoder.encode(frame_of(3, {{1, 0.0}, {2, 1.5}, {4, 3.0}})));
  EXPECT_TRUE(ids_in(idle).empty());
  EXPECT_EQ(idle.removed_ids_size(), 0);

  encoder.restart();
  EXPECT_TRUE(parse(*encoder.encode(frame_of(4, {{1, 0.0}}))).key_frame());
}

TEST(DeltaEncoder, ClientsThatKeepUpShareTheBytesOthersGetTheirOwn) {
  DeltaEncoder a;
  DeltaEncoder b;
  DeltaEncoder late;
  const auto first = frame_of(1, {{1, 0.0}, {2, 0.0}});
  const auto second = frame_of(2, {{1, 1.0}, {2, 0.0}});
  const auto third = frame_of(3, {{1, 1.0}, {2, 2.0}});
  EXPECT_EQ(a.encode(first), b.encode(first)) << "one key frame for both";
  late.encode(first);
  EXPECT_EQ(a.encode(second), b.encode(second)) << "one change from frame 1 for both";
  const auto shared = a.encode(third);
  EXPECT_EQ(shared, b.encode(third));
  EXPECT_EQ(ids_in(parse(*shared)), (std::vector<std::uint32_t>{2}));
  // `late` skipped frame 2 (latest-wins): its change is from frame 1, bodies 1 and 2.
  const auto own = late.encode(third);
  EXPECT_NE(own, shared);
  EXPECT_EQ(ids_in(parse(*own)), (std::vector<std::uint32_t>{1, 2}));
}

TEST(DeltaEncoder, AFrameReplacedBeforeItWasWrittenIsNeverABaseline) {
  OutboundQueue queue;
  OutboundQueue::Batch batch;
  queue.offer_delta_frame(1, frame_of(1, {{1, 0.0}, {2, 0.0}}));
  queue.take_batch(batch);
  ASSERT_EQ(batch.frames.size(), 1u);
  EXPECT_TRUE(parse(*batch.frames[0]).key_frame());

  // Tick 2 moves body 1 but is replaced by tick 3, which moves it back:
  // the client never saw tick 2, so tick 3 is no change at all, and body 2's
  // move at tick 3 is.
  queue.offer_delta_frame(1, frame_of(2, {{1, 5.0}, {2, 0.0}}));
  queue.offer_delta_frame(1, frame_of(3, {{1, 0.0}, {2, 7.0}}));
  EXPECT_EQ(queue.frames_replaced(), 1u);
  queue.take_batch(batch);
  ASSERT_EQ(batch.frames.size(), 1u);
  const auto written = parse(*batch.frames[0]);
  EXPECT_EQ(written.tick(), 3u);
  EXPECT_EQ(ids_in(written), (std::vector<std::uint32_t>{2}));
}

TEST(DeltaEncoder, RestartMakesTheNextWrittenFrameAKeyFrame) {
  OutboundQueue queue;
  OutboundQueue::Batch batch;
  queue.offer_delta_frame(1, frame_of(1, {{1, 0.0}}));
  queue.take_batch(batch);
  queue.offer_delta_frame(1, frame_of(2, {{1, 0.0}}));
  queue.restart_delta(1);
  queue.take_batch(batch);
  EXPECT_TRUE(parse(*batch.frames[0]).key_frame());
  EXPECT_EQ(ids_in(parse(*batch.frames[0])), (std::vector<std::uint32_t>{1}));

  // Leaving the stream forgets its baseline too.
  queue.drop_stream(1);
  queue.offer_delta_frame(1, frame_of(3, {{1, 0.0}}));
  queue.take_batch(batch);
  EXPECT_TRUE(parse(*batch.frames[0]).key_frame());
}

}  // namespace
}  // namespace tumble::net
