// Length-delimited framing: protobuf's delimited format, a varint length
// followed by that many bytes of one serialized message. Pure byte handling,
// no I/O, so the server, the client and the tests share one implementation.
//
// Thread: none of these functions or types are shared between threads; each
// connection owns its FrameReader.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include <google/protobuf/message_lite.h>

namespace tumble::wire {

// The default largest frame body a peer accepts, in bytes (1 MiB).
inline constexpr std::size_t kDefaultMaxFrameBytes = std::size_t{1} << 20;

// A varint holds 7 bits a byte; a 64-bit value needs at most 10.
inline constexpr std::size_t kMaxVarintBytes = 10;

// Appends `message` to `out` as one frame: varint length, then the bytes.
void append_frame(const google::protobuf::MessageLite& message, std::string& out);

// `message` as one frame.
std::string encode_frame(const google::protobuf::MessageLite& message);

// What FrameReader::next found at the front of its buffer.
enum class FrameStatus {
  frame,       // a whole frame body is ready
  need_more,   // the prefix or the body is not complete yet
  too_large,   // the length prefix exceeds the limit; the stream is unusable
  bad_length,  // the length prefix is not a valid varint; the stream is unusable
};

// Splits a byte stream into frame bodies. Feed it whatever arrived with
// append(); call next() until it stops returning `frame`. Bytes of a frame
// that is refused are never buffered beyond the limit: the length prefix is
// checked before the body is waited for.
class FrameReader {
 public:
  explicit FrameReader(std::size_t max_frame_bytes = kDefaultMaxFrameBytes);

  // Copies `size` bytes that arrived from the peer.
  void append(const char* data, std::size_t size);

  // Takes the next frame. On `frame`, `body` views the frame's bytes, valid
  // until the next call to append() or next(). On too_large,
  // `declared_bytes` holds the length the peer announced.
  FrameStatus next(std::string_view& body);

  // The length announced by the last prefix that was refused as too large.
  std::uint64_t declared_bytes() const { return declared_bytes_; }

  // Bytes held that do not yet form a whole frame.
  std::size_t buffered_bytes() const { return buffer_.size() - start_; }

  std::size_t max_frame_bytes() const { return max_frame_bytes_; }

 private:
  std::string buffer_;
  std::size_t start_ = 0;  // offset of the first unconsumed byte
  std::size_t max_frame_bytes_;
  std::uint64_t declared_bytes_ = 0;
};

}  // namespace tumble::wire
