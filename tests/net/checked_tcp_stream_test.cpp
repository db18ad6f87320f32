// The WebSocket frame-header scanner under the server's WebSockets: it
// follows frames of every length form, wherever reads cut them, and stops
// at the first 64-bit length with its top bit set, saying how many bytes
// came before that header.
#include "net/checked_tcp_stream.h"

#include <gtest/gtest.h>

#include <string>

namespace tumble::net {
namespace {

// A masked client frame (zero mask key) whose payload is `size` bytes of 'x'.
std::string frame(std::size_t size) {
  std::string bytes("\x82", 1);
  if (size < 126) {
    bytes += static_cast<char>(0x80 | size);
  } else if (size <= 0xFFFF) {
    bytes += static_cast<char>(0x80 | 126);
    for (int shift = 8; shift >= 0; shift -= 8) bytes += static_cast<char>((size >> shift) & 0xFF);
  } else {
    bytes += static_cast<char>(0x80 | 127);
    for (int shift = 56; shift >= 0; shift -= 8) bytes += static_cast<char>((std::uint64_t{size} >> shift) & 0xFF);
  }
  return bytes + std::string(4, '\0') + std::string(size, 'x');
}

const std::string kIllegal = std::string("\x82\xff\x80\x00\x00\x00\x00\x00\x00\x05", 10) + std::string(4, '\0');

std::size_t scan(FrameHeaderScanner& scanner, const std::string& bytes) {
  return scanner.scan(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size());
}

TEST(FrameHeaderScanner, FollowsFramesOfEveryLengthFormByteByByte) {
  const std::string stream = frame(5) + frame(300) + frame(70000) + frame(0);
  FrameHeaderScanner scanner;
  for (const char c : stream) ASSERT_EQ(scan(scanner, std::string(1, c)), 1u);
  EXPECT_FALSE(scanner.illegal());
  // Then an illegal header, cut after its third byte: it is judged once whole.
  EXPECT_EQ(scan(scanner, kIllegal.substr(0, 3)), 3u);
  EXPECT_FALSE(scanner.illegal());
  EXPECT_EQ(scan(scanner, kIllegal.substr(3)), 0u);
  EXPECT_TRUE(scanner.illegal());
  EXPECT_EQ(scan(scanner, frame(1)), 0u);
}

TEST(FrameHeaderScanner, SaysHowManyBytesCameBeforeAnIllegalHeader) {
  const std::string legal = frame(5) + frame(300);
  FrameHeaderScanner whole;
  EXPECT_EQ(scan(whole, legal + kIllegal + "rest"), legal.size());
  EXPECT_TRUE(whole.illegal());

  // A header begun in one read and found illegal in the next: nothing of the second is legal.
  FrameHeaderScanner split;
  EXPECT_EQ(scan(split, legal + kIllegal.substr(0, 2)), legal.size() + 2);
  EXPECT_FALSE(split.illegal());
  EXPECT_EQ(scan(split, kIllegal.substr(2)), 0u);
  EXPECT_TRUE(split.illegal());

  // 2^63 - 1 is the largest legal length.
  FrameHeaderScanner largest;
  const std::string header = std::string("\x82\xff\x7f\xff\xff\xff\xff\xff\xff\xff", 10) + std::string(4, '\0');
  EXPECT_EQ(scan(largest, header + "abc"), header.size() + 3);
  EXPECT_FALSE(largest.illegal());
}

}  // namespace
}  // namespace tumble::net
