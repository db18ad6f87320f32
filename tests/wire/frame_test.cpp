// Framing: protobuf's delimited format, checked byte for byte.
#include <gtest/gtest.h>

#include <string>

#include "tumble/v1/protocol.pb.h"
#include "wire/frame.h"

namespace tumble::wire {
namespace {

tumble::v1::ClientMessage hello(std::uint64_t request_id) {
  tumble::v1::ClientMessage message;
  message.set_request_id(request_id);
  message.mutable_hello()->set_protocol_version(1);
  message.mutable_hello()->set_client_name("test");
  return message;
}

TEST(Frame, PrefixIsTheVarintLengthOfTheSerializedMessage) {
  const auto message = hello(7);
  const std::string body = message.SerializeAsString();
  ASSERT_LT(body.size(), 128u);
  const std::string frame = encode_frame(message);
  ASSERT_EQ(frame.size(), body.size() + 1);
  EXPECT_EQ(static_cast<std::uint8_t>(frame[0]), body.size());
  EXPECT_EQ(frame.substr(1), body);
}

TEST(Frame, LongMessagesGetAMultiByteVarint) {
  tumble::v1::ClientMessage message = hello(1);
  message.mutable_hello()->set_client_name(std::string(300, 'x'));
  const std::string frame = encode_frame(message);
  const std::size_t size = message.ByteSizeLong();
  ASSERT_GT(size, 300u);
  EXPECT_EQ(static_cast<std::uint8_t>(frame[0]), (size & 0x7f) | 0x80);
  EXPECT_EQ(static_cast<std::uint8_t>(frame[1]), size >> 7);
  EXPECT_EQ(frame.size(), size + 2);
}

TEST(FrameReader, ReassemblesFramesFedOneByteAtATime) {
  const std::string stream = encode_frame(hello(1)) + encode_frame(hello(2)) + encode_frame(hello(3));
  FrameReader reader;
  std::vector<std::uint64_t> ids;
  std::string_view body;
  for (char byte : stream) {
    reader.append(&byte, 1);
    while (reader.next(body) == FrameStatus::frame) {
      tumble::v1::ClientMessage message;
      ASSERT_TRUE(message.ParseFromArray(body.data(), static_cast<int>(body.size())));
      ids.push_back(message.request_id());
    }
  }
  EXPECT_EQ(ids, (std::vector<std::uint64_t>{1, 2, 3}));
  EXPECT_EQ(reader.buffered_bytes(), 0u);
}

TEST(FrameReader, SplitsSeveralFramesArrivingTogether) {
  const std::string stream = encode_frame(hello(10)) + encode_frame(hello(11));
  FrameReader reader;
  reader.append(stream.data(), stream.size());
  std::string_view body;
  ASSERT_EQ(reader.next(body), FrameStatus::frame);
  ASSERT_EQ(reader.next(body), FrameStatus::frame);
  tumble::v1::ClientMessage second;
  ASSERT_TRUE(second.ParseFromArray(body.data(), static_cast<int>(body.size())));
  EXPECT_EQ(second.request_id(), 11u);
  EXPECT_EQ(reader.next(body), FrameStatus::need_more);
}

TEST(FrameReader, EmptyFrameIsAValidEmptyMessage) {
  FrameReader reader;
  const char zero = 0;
  reader.append(&zero, 1);
  std::string_view body;
  ASSERT_EQ(reader.next(body), FrameStatus::frame);
  EXPECT_TRUE(body.empty());
}

TEST(FrameReader, RefusesALengthOverTheLimitBeforeTheBodyArrives) {
  FrameReader reader(100);
  const std::string prefix = "\x65";  // 101
  reader.append(prefix.data(), prefix.size());
  std::string_view body;
  EXPECT_EQ(reader.next(body), FrameStatus::too_large);
  EXPECT_EQ(reader.declared_bytes(), 101u);
}

TEST(FrameReader, AcceptsAFrameExactlyAtTheLimit) {
  FrameReader reader(100);
  std::string frame = "\x64" + std::string(100, '\0');
  reader.append(frame.data(), frame.size());
  std::string_view body;
  EXPECT_EQ(reader.next(body), FrameStatus::frame);
  EXPECT_EQ(body.size(), 100u);
}

TEST(FrameReader, RefusesAFourGibibytePrefix) {
  FrameReader reader;
  // 2^32 as a varint: four bytes of 0x80 then 0x10.
  const std::string prefix = "\x80\x80\x80\x80\x10";
  reader.append(prefix.data(), prefix.size());
  std::string_view body;
  EXPECT_EQ(reader.next(body), FrameStatus::too_large);
  EXPECT_EQ(reader.declared_bytes(), std::uint64_t{1} << 32);
}

TEST(FrameReader, RefusesAVarintThatNeverEnds) {
  FrameReader reader;
  const std::string prefix(11, '\xff');
  reader.append(prefix.data(), prefix.size());
  std::string_view body;
  EXPECT_EQ(reader.next(body), FrameStatus::bad_length);
}

TEST(FrameReader, WaitsForTheRestOfAPartialPrefix) {
  FrameReader reader;
  const std::string prefix = "\x80";
  reader.append(prefix.data(), prefix.size());
  std::string_view body;
  EXPECT_EQ(reader.next(body), FrameStatus::need_more);
}

}  // namespace
}  // namespace tumble::wire
