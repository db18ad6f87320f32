// The outbound queue: replies in order and never dropped, frames latest-wins.
#include <gtest/gtest.h>

#include "net/outbound_queue.h"

namespace tumble::net {
namespace {

std::shared_ptr<const std::string> bytes(const char* text) { return std::make_shared<const std::string>(text); }

std::string joined(const OutboundQueue::Batch& batch) {
  std::string out;
  for (std::string_view piece : batch.pieces) out += piece;
  return out;
}

TEST(OutboundQueue, MessagesComeFirstAndInOrder) {
  OutboundQueue queue;
  queue.offer_frame(1, bytes("[f1]"));
  queue.push_message("<a>");
  queue.push_message("<b>");
  OutboundQueue::Batch batch;
  queue.take_batch(batch);
  EXPECT_EQ(joined(batch), "<a><b>[f1]");
  EXPECT_EQ(batch.bytes, 10u);
  EXPECT_TRUE(queue.empty());
}

TEST(OutboundQueue, ANewerFrameReplacesTheUnsentOneOfItsStream) {
  OutboundQueue queue;
  queue.offer_frame(1, bytes("[1@t1]"));
  queue.offer_frame(2, bytes("[2@t1]"));
  queue.offer_frame(1, bytes("[1@t2]"));
  EXPECT_EQ(queue.frames_replaced(), 1u);
  OutboundQueue::Batch batch;
  queue.take_batch(batch);
  EXPECT_EQ(joined(batch), "[1@t2][2@t1]");
}

TEST(OutboundQueue, FramesNeverAccumulateForASlowReader) {
  OutboundQueue queue;
  for (int tick = 0; tick < 10000; ++tick) queue.offer_frame(7, bytes("frame"));
  OutboundQueue::Batch batch;
  queue.take_batch(batch);
  EXPECT_EQ(batch.pieces.size(), 1u);
  EXPECT_EQ(queue.pending_message_bytes(), 0u);
}

TEST(OutboundQueue, CountsPendingMessageBytes) {
  OutboundQueue queue;
  queue.push_message(std::string(100, 'x'));
  queue.push_message(std::string(50, 'y'));
  queue.offer_frame(1, bytes("frames do not count"));
  EXPECT_EQ(queue.pending_message_bytes(), 150u);
}

TEST(OutboundQueue, DroppedStreamLosesItsUnsentFrame) {
  OutboundQueue queue;
  queue.offer_frame(3, bytes("[3]"));
  queue.drop_stream(3);
  EXPECT_TRUE(queue.empty());
}

}  // namespace
}  // namespace tumble::net
