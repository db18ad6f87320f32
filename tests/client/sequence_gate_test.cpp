// SequenceGate with a PoseStream behind it, as a reader of a DELTA stream
// over NATS uses them: whatever frames go missing or come late, what it
// shows is a state the server had, and it is back in step after a key frame.
#include "tumble_client/sequence_gate.h"

#include <map>
#include <optional>
#include <vector>

#include <gtest/gtest.h>

#include "tumble_client/pose_stream.h"
#include "wire/quantized_poses.h"

namespace tumble::client {
namespace {

using tumble::v1::PoseFrame;

// The x of each body, by id: a world state as the test writes it.
using World = std::map<std::uint32_t, double>;

wire::QuantizedBody body_at(std::uint32_t id, double x) {
  const double position[3] = {x, 0, 0};
  const double orientation[4] = {1, 0, 0, 0};
  return wire::quantize_body(id, position, orientation, nullptr, nullptr);
}

PoseFrame delta_frame(std::uint64_t sequence, const World& bodies, bool key, std::vector<std::uint32_t> removed = {}) {
  std::vector<wire::QuantizedBody> packed;
  for (const auto& [id, x] : bodies) packed.push_back(body_at(id, x));
  PoseFrame frame;
  frame.set_tick(100 + sequence);
  frame.set_sequence(sequence);
  frame.set_encoding(tumble::v1::POSE_ENCODING_DELTA);
  frame.set_packed(wire::encode_quantized_poses(packed, false));
  frame.set_key_frame(key);
  for (std::uint32_t id : removed) frame.add_removed_ids(id);
  return frame;
}

// The server's side: the world after each frame, and its frames.
struct Published {
  std::vector<World> states;      // states[s]: the world of frame s (states[0] unused)
  std::vector<PoseFrame> frames;  // frames[s]: frame s as published (frames[0] unused)
};

// Ten frames: body 1 moves each frame, body 2 every third, body 3 is
// removed at frame 5 and body 4 spawned at frame 7; frames 1 and 8 are key frames.
Published ten_frames() {
  Published out;
  out.states.emplace_back();
  out.frames.emplace_back();
  World world = {{1, 0.0}, {2, 5.0}, {3, -2.0}};
  for (std::uint64_t s = 1; s <= 10; ++s) {
    World changed;
    std::vector<std::uint32_t> removed;
    world[1] = 0.25 * static_cast<double>(s);
    changed[1] = world[1];
    if (s % 3 == 0) changed[2] = world[2] = 5.0 + static_cast<double>(s);
    if (s == 5) {
      world.erase(3);
      removed.push_back(3);
    }
    if (s == 7) changed[4] = world[4] = 9.0;
    const bool key = s == 1 || s == 8;
    out.states.push_back(world);
    out.frames.push_back(delta_frame(s, key ? world : changed, key, key ? std::vector<std::uint32_t>{} : removed));
  }
  return out;
}

// A reader: the gate, the stream behind it, and what it showed.
struct Reader {
  SequenceGate gate;
  PoseStream stream;
  std::vector<std::pair<std::uint64_t, World>> shown;  // (sequence, state) of each frame shown
  int key_requests = 0;

  void take(const PoseFrame& frame, bool key_reply = false) {
    const SequenceGate::Verdict verdict = key_reply ? gate.key_reply(frame) : gate.published(frame);
    if (verdict.request_key) ++key_requests;
    if (!verdict.show) return;
    auto sample = stream.decode(frame);
    ASSERT_TRUE(sample) << sample.failure().message;
    World state;
    for (const BodyPose& body : sample->bodies) state[body.id] = body.position[0];
    shown.emplace_back(frame.sequence(), state);
  }
};

// Every state shown is the server's state of that frame.
void expect_only_true_states(const Reader& reader, const Published& published) {
  for (const auto& [sequence, state] : reader.shown) {
    ASSERT_LT(sequence, published.states.size());
    EXPECT_EQ(state, published.states[sequence]) << "frame " << sequence;
  }
}

std::vector<std::uint64_t> sequences(const Reader& reader) {
  std::vector<std::uint64_t> out;
  for (const auto& shown : reader.shown) out.push_back(shown.first);
  return out;
}

TEST(SequenceGate, EveryFrameInOrderIsShown) {
  const Published published = ten_frames();
  Reader reader;
  for (std::uint64_t s = 1; s <= 10; ++s) reader.take(published.frames[s]);
  EXPECT_EQ(sequences(reader), (std::vector<std::uint64_t>{1, 2, 3, 4, 5, 6, 7, 8, 9, 10}));
  expect_only_true_states(reader, published);
  EXPECT_EQ(reader.key_requests, 0);
}

TEST(SequenceGate, ALateJoinerShowsNothingUntilTheNextKeyFrame) {
  const Published published = ten_frames();
  Reader reader;
  for (std::uint64_t s = 3; s <= 10; ++s) reader.take(published.frames[s]);
  EXPECT_EQ(sequences(reader), (std::vector<std::uint64_t>{8, 9, 10}));
  expect_only_true_states(reader, published);
  EXPECT_EQ(reader.key_requests, 1);  // asked once, not once per frame
}

TEST(SequenceGate, AGapShowsNothingWrongAndTheNextKeyFrameRestores) {
  const Published published = ten_frames();
  Reader reader;
  for (const std::uint64_t s : {1u, 2u, 3u, 5u, 6u, 7u, 8u, 9u, 10u}) reader.take(published.frames[s]);  // 4 lost
  EXPECT_EQ(sequences(reader), (std::vector<std::uint64_t>{1, 2, 3, 8, 9, 10}));
  expect_only_true_states(reader, published);
  EXPECT_EQ(reader.key_requests, 1);
}

TEST(SequenceGate, AKeyReplyRestoresAndTheChangeAfterItApplies) {
  const Published published = ten_frames();
  Reader reader;
  reader.take(published.frames[1]);
  reader.take(published.frames[2]);
  reader.take(published.frames[4]);  // 3 lost: out of step, a key frame is asked for
  EXPECT_EQ(reader.key_requests, 1);
  reader.take(published.frames[5]);
  // The reply: the latest frame, 5, as a key frame with its sequence.
  reader.take(delta_frame(5, published.states[5], true), /*key_reply=*/true);
  reader.take(published.frames[6]);
  reader.take(published.frames[7]);
  EXPECT_EQ(sequences(reader), (std::vector<std::uint64_t>{1, 2, 5, 6, 7}));
  expect_only_true_states(reader, published);
}

TEST(SequenceGate, FramesOvertakenByAKeyReplyAreNotShownAgain) {
  const Published published = ten_frames();
  Reader reader;
  reader.take(published.frames[2]);  // a change before anything: asks for a key frame
  reader.take(delta_frame(4, published.states[4], true), /*key_reply=*/true);
  for (std::uint64_t s = 3; s <= 6; ++s) reader.take(published.frames[s]);  // 3 and 4 were in flight
  EXPECT_EQ(sequences(reader), (std::vector<std::uint64_t>{4, 5, 6}));
  expect_only_true_states(reader, published);
}

TEST(SequenceGate, WholeFramesOvertakenByAKeyReplyDoNotTakeTheReaderBack) {
  Reader reader;
  const auto quantized = [](std::uint64_t sequence) {
    PoseFrame frame = delta_frame(sequence, {{1, 0.5 * static_cast<double>(sequence)}}, false);
    frame.set_encoding(tumble::v1::POSE_ENCODING_QUANTIZED);
    return frame;
  };
  reader.take(quantized(5), /*key_reply=*/true);  // the latest frame, asked for at the start
  reader.take(quantized(4));                      // published before it, delivered after
  reader.take(quantized(5));
  reader.take(quantized(6));
  EXPECT_EQ(sequences(reader), (std::vector<std::uint64_t>{5, 6}));
}

TEST(SequenceGate, AStaleKeyReplyIsIgnored) {
  const Published published = ten_frames();
  Reader reader;
  for (std::uint64_t s = 1; s <= 6; ++s) reader.take(published.frames[s]);
  reader.take(delta_frame(4, published.states[4], true), /*key_reply=*/true);  // older than what is shown
  reader.take(published.frames[7]);
  EXPECT_EQ(sequences(reader), (std::vector<std::uint64_t>{1, 2, 3, 4, 5, 6, 7}));
  expect_only_true_states(reader, published);
}

TEST(SequenceGate, AnUnansweredKeyRequestMayBeAskedAgain) {
  const Published published = ten_frames();
  Reader reader;
  reader.take(published.frames[2]);
  reader.take(published.frames[3]);
  EXPECT_EQ(reader.key_requests, 1);
  reader.gate.key_request_failed();
  reader.take(published.frames[4]);
  EXPECT_EQ(reader.key_requests, 2);
  EXPECT_TRUE(reader.shown.empty());
}

TEST(SequenceGate, ARestartedServerBeginsAgainAtItsKeyFrameOne) {
  const Published published = ten_frames();
  Reader reader;
  for (std::uint64_t s = 1; s <= 10; ++s) reader.take(published.frames[s]);
  const Published again = ten_frames();  // a restarted server: sequence 1 with a key frame
  for (std::uint64_t s = 1; s <= 3; ++s) reader.take(again.frames[s]);
  ASSERT_EQ(reader.shown.size(), 13u);
  EXPECT_EQ(reader.shown[10].first, 1u);
  EXPECT_EQ(reader.shown[12].first, 3u);
  expect_only_true_states(reader, published);
}

TEST(SequenceGate, WholeFramesAlwaysShowButAChangeInAKeyReplyNever) {
  Reader reader;
  PoseFrame quantized = delta_frame(7, {{1, 1.0}}, false);
  quantized.set_encoding(tumble::v1::POSE_ENCODING_QUANTIZED);
  reader.take(quantized);
  PoseFrame later = quantized;
  later.set_sequence(9);  // a gap means nothing to a whole frame
  reader.take(later);
  EXPECT_EQ(sequences(reader), (std::vector<std::uint64_t>{7, 9}));
  EXPECT_EQ(reader.key_requests, 0);

  Reader delta;
  delta.take(delta_frame(3, {{1, 1.0}}, false), /*key_reply=*/true);
  EXPECT_TRUE(delta.shown.empty());
}

}  // namespace
}  // namespace tumble::client
