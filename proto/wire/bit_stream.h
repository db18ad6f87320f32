// Bit-level packing for the quantized pose encodings: a writer that appends
// fields of any width up to 64 bits, and a reader that takes them back, plus
// the base-128 varints and zigzag mapping the same layouts use for whole
// bytes. Pure byte handling, shared by the server and the client.
//
// Bit order: fields are packed least significant bit first, starting at
// bit 0 of byte 0; a field may straddle bytes. The last byte is padded with
// zero bits.
//
// Thread: each writer and reader is used by one thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace tumble::wire {

// Appends bit fields to a byte string.
class BitWriter {
 public:
  explicit BitWriter(std::string& out) : out_(out) {}

  // Appends the low `bits` bits of `value` (0 <= bits <= 64); higher bits of
  // `value` must be zero.
  void write(std::uint64_t value, unsigned bits);

 private:
  std::string& out_;
  unsigned used_in_last_ = 8;  // bits of out_.back() already taken; 8: start a new byte
};

// Reads bit fields in the order a BitWriter wrote them.
class BitReader {
 public:
  explicit BitReader(std::string_view bytes) : bytes_(bytes) {}

  // The next `bits` bits (0 <= bits <= 64); nullopt when fewer remain.
  std::optional<std::uint64_t> read(unsigned bits);

 private:
  std::string_view bytes_;
  std::size_t bit_ = 0;  // next bit to read, counted from bit 0 of byte 0
};

// Appends `value` as a base-128 varint (7 bits a byte, low group first, high
// bit set on every byte but the last).
void append_varint(std::uint64_t value, std::string& out);

// Reads a varint at the front of `bytes` and drops it from the view; nullopt
// when the bytes end first or it is longer than 10 bytes.
std::optional<std::uint64_t> take_varint(std::string_view& bytes);

// Zigzag: 0, -1, 1, -2, ... map to 0, 1, 2, 3, ..., so small magnitudes of
// either sign make short varints.
constexpr std::uint64_t zigzag(std::int64_t value) {
  return (static_cast<std::uint64_t>(value) << 1) ^ static_cast<std::uint64_t>(value >> 63);
}
constexpr std::int64_t unzigzag(std::uint64_t value) {
  return static_cast<std::int64_t>(value >> 1) ^ -static_cast<std::int64_t>(value & 1);
}

}  // namespace tumble::wire
