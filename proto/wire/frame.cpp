#include "wire/frame.h"

#include <cstring>

#include "wire/bit_stream.h"

namespace tumble::wire {
namespace {

enum class VarintStatus { ok, need_more, bad };

// Reads a little-endian base-128 varint from the front of `data`.
VarintStatus read_varint(std::string_view data, std::uint64_t& value, std::size_t& used) {
  value = 0;
  for (std::size_t i = 0; i < data.size(); ++i) {
    if (i == kMaxVarintBytes) return VarintStatus::bad;
    const auto byte = static_cast<std::uint8_t>(data[i]);
    // The tenth byte may only hold the top bit of a 64-bit value.
    if (i == kMaxVarintBytes - 1 && byte > 1) return VarintStatus::bad;
    value |= std::uint64_t{byte & 0x7fu} << (7 * i);
    if ((byte & 0x80) == 0) {
      used = i + 1;
      return VarintStatus::ok;
    }
  }
  return data.size() >= kMaxVarintBytes ? VarintStatus::bad : VarintStatus::need_more;
}

}  // namespace

void append_frame(const google::protobuf::MessageLite& message, std::string& out) {
  const std::size_t size = message.ByteSizeLong();
  append_varint(size, out);
  const std::size_t offset = out.size();
  out.resize(offset + size);
  message.SerializeWithCachedSizesToArray(reinterpret_cast<std::uint8_t*>(out.data() + offset));
}

std::string encode_frame(const google::protobuf::MessageLite& message) {
  std::string out;
  append_frame(message, out);
  return out;
}

FrameReader::FrameReader(std::size_t max_frame_bytes) : max_frame_bytes_(max_frame_bytes) {}

void FrameReader::append(const char* data, std::size_t size) {
  // Drop consumed bytes before growing, so the buffer never holds more than
  // one partial frame plus what just arrived.
  if (start_ > 0 && (start_ == buffer_.size() || start_ >= buffer_.size() / 2)) {
    buffer_.erase(0, start_);
    start_ = 0;
  }
  buffer_.append(data, size);
}

FrameStatus FrameReader::next(std::string_view& body) {
  const std::string_view pending(buffer_.data() + start_, buffer_.size() - start_);
  std::uint64_t length = 0;
  std::size_t prefix = 0;
  switch (read_varint(pending, length, prefix)) {
    case VarintStatus::need_more:
      return FrameStatus::need_more;
    case VarintStatus::bad:
      return FrameStatus::bad_length;
    case VarintStatus::ok:
      break;
  }
  if (length > max_frame_bytes_) {
    declared_bytes_ = length;
    return FrameStatus::too_large;
  }
  if (pending.size() - prefix < length) return FrameStatus::need_more;
  body = pending.substr(prefix, static_cast<std::size_t>(length));
  start_ += prefix + static_cast<std::size_t>(length);
  return FrameStatus::frame;
}

}  // namespace tumble::wire
