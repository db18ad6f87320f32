#include "wire/bit_stream.h"

#include <algorithm>

namespace tumble::wire {

void BitWriter::write(std::uint64_t value, unsigned bits) {
  while (bits > 0) {
    if (used_in_last_ == 8) {
      out_.push_back('\0');
      used_in_last_ = 0;
    }
    const unsigned take = std::min(bits, 8 - used_in_last_);
    const auto piece = static_cast<unsigned>(value & ((1u << take) - 1));
    out_.back() = static_cast<char>(static_cast<unsigned char>(out_.back()) | (piece << used_in_last_));
    used_in_last_ += take;
    value = take < 64 ? value >> take : 0;
    bits -= take;
  }
}

std::optional<std::uint64_t> BitReader::read(unsigned bits) {
  if (bits > 64 || bit_ + bits > 8 * bytes_.size()) return std::nullopt;
  std::uint64_t value = 0;
  unsigned done = 0;
  while (done < bits) {
    const auto byte = static_cast<unsigned char>(bytes_[bit_ / 8]);
    const unsigned offset = bit_ % 8;
    const unsigned take = std::min(bits - done, 8 - offset);
    const std::uint64_t piece = (byte >> offset) & ((1u << take) - 1);
    value |= piece << done;
    done += take;
    bit_ += take;
  }
  return value;
}

void append_varint(std::uint64_t value, std::string& out) {
  while (value >= 0x80) {
    out.push_back(static_cast<char>((value & 0x7f) | 0x80));
    value >>= 7;
  }
  out.push_back(static_cast<char>(value));
}

std::optional<std::uint64_t> take_varint(std::string_view& bytes) {
  std::uint64_t value = 0;
  for (std::size_t i = 0; i < bytes.size() && i < 10; ++i) {
    const auto byte = static_cast<unsigned char>(bytes[i]);
    value |= static_cast<std::uint64_t>(byte & 0x7f) << (7 * i);
    if ((byte & 0x80) == 0) {
      bytes.remove_prefix(i + 1);
      return value;
    }
  }
  return std::nullopt;
}

}  // namespace tumble::wire
