// CRC32C against the published test vectors: the check value of the CRC
// catalogue and the iSCSI examples of RFC 3720 appendix B.4 (as LevelDB's
// crc32c test has them); extension and masking.
#include "sim/crc32c.h"

#include <gtest/gtest.h>

#include <string>

namespace tumble::sim {
namespace {

std::string bytes_of(std::initializer_list<int> values) {
  std::string out;
  for (const int v : values) out.push_back(static_cast<char>(v));
  return out;
}

TEST(Crc32c, MatchesTheStandardCheckValue) { EXPECT_EQ(crc32c::value("123456789"), 0xe3069283u); }

TEST(Crc32c, MatchesTheIscsiVectorsOfRfc3720) {
  EXPECT_EQ(crc32c::value(std::string(32, '\0')), 0x8a9136aau);
  EXPECT_EQ(crc32c::value(std::string(32, '\xff')), 0x62a8ab43u);
  std::string ascending;
  std::string descending;
  for (int i = 0; i < 32; ++i) {
    ascending.push_back(static_cast<char>(i));
    descending.push_back(static_cast<char>(31 - i));
  }
  EXPECT_EQ(crc32c::value(ascending), 0x46dd794eu);
  EXPECT_EQ(crc32c::value(descending), 0x113fdb5cu);
  // An iSCSI SCSI Read (10) command PDU.
  const std::string read_command =
      bytes_of({0x01, 0xc0, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
                0x14, 0x00, 0x00, 0x00, 0x00, 0x00, 0x04, 0x00, 0x00, 0x00, 0x00, 0x14, 0x00, 0x00, 0x00, 0x18,
                0x28, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00});
  EXPECT_EQ(crc32c::value(read_command), 0xd9963a56u);
}

TEST(Crc32c, ExtendingEqualsTheCrcOfTheWhole) {
  EXPECT_EQ(crc32c::value(""), 0u);
  EXPECT_EQ(crc32c::extend(crc32c::value("hello "), "world"), crc32c::value("hello world"));
  EXPECT_NE(crc32c::value("a"), crc32c::value("foo"));
}

TEST(Crc32c, MaskingChangesTheValueAndIsUndone) {
  const std::uint32_t crc = crc32c::value("foo");
  EXPECT_NE(crc32c::mask(crc), crc);
  EXPECT_NE(crc32c::mask(crc32c::mask(crc)), crc);
  EXPECT_EQ(crc32c::unmask(crc32c::mask(crc)), crc);
  EXPECT_EQ(crc32c::unmask(crc32c::unmask(crc32c::mask(crc32c::mask(crc)))), crc);
}

}  // namespace
}  // namespace tumble::sim
