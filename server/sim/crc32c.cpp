#include "sim/crc32c.h"

#include <array>

namespace tumble::sim::crc32c {
namespace {

// 0x1EDC6F41 with its bits reversed: the CRC runs least significant bit first.
constexpr std::uint32_t kReversedPolynomial = 0x82f63b78u;

// kTable[b]: the CRC register after shifting the byte b through it, one bit at a time.
constexpr std::array<std::uint32_t, 256> make_table() {
  std::array<std::uint32_t, 256> table{};
  for (std::uint32_t byte = 0; byte < 256; ++byte) {
    std::uint32_t crc = byte;
    for (int bit = 0; bit < 8; ++bit) crc = (crc >> 1) ^ ((crc & 1u) != 0 ? kReversedPolynomial : 0u);
    table[byte] = crc;
  }
  return table;
}

constexpr std::array<std::uint32_t, 256> kTable = make_table();

}  // namespace

std::uint32_t extend(std::uint32_t crc, std::string_view data) {
  std::uint32_t state = ~crc;  // undo the final XOR of the CRC being extended
  for (const char c : data) state = (state >> 8) ^ kTable[(state ^ static_cast<unsigned char>(c)) & 0xffu];
  return ~state;
}

}  // namespace tumble::sim::crc32c
