// CRC32C: the Castagnoli CRC (polynomial 0x1EDC6F41, reflected, initial
// value and final XOR all ones), as iSCSI (RFC 3720) and LevelDB's log use.
// It detects every error burst of up to 32 bits, so every damaged byte, in
// the state files and journal records that carry it.
//
// A CRC stored in a file is masked (as LevelDB does): the CRC of bytes that
// end in their own unmasked CRC is one constant, whatever the bytes, so a
// checksum over data that embeds checksums would lose strength. Masking
// makes the stored value differ from the CRC the bytes would produce.
//
// Thread: any; pure functions over a constant table.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace tumble::sim::crc32c {

// The CRC32C of `crc`'s bytes followed by `data`: extend(value(a), b) ==
// value(a + b). value(empty) is 0.
std::uint32_t extend(std::uint32_t crc, std::string_view data);
inline std::uint32_t value(std::string_view data) { return extend(0, data); }

// The stored form of a CRC, and back.
inline constexpr std::uint32_t kMaskDelta = 0xa282ead8u;
inline std::uint32_t mask(std::uint32_t crc) { return ((crc >> 15) | (crc << 17)) + kMaskDelta; }
inline std::uint32_t unmask(std::uint32_t masked) {
  const std::uint32_t rotated = masked - kMaskDelta;
  return (rotated >> 17) | (rotated << 15);
}

}  // namespace tumble::sim::crc32c
