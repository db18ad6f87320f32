// Bit fields, varints and zigzag: exact bytes and round trips.
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "wire/bit_stream.h"

namespace tumble::wire {
namespace {

TEST(BitStream, FieldsArePackedLeastSignificantBitFirst) {
  std::string out;
  BitWriter writer(out);
  writer.write(0b101, 3);    // bits 0-2
  writer.write(0b11110, 5);  // bits 3-7
  writer.write(0xABC, 12);   // bits 8-19, straddling two bytes
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(static_cast<unsigned char>(out[0]), 0b11110101);
  EXPECT_EQ(static_cast<unsigned char>(out[1]), 0xBC);
  EXPECT_EQ(static_cast<unsigned char>(out[2]), 0x0A);  // the top four bits are padding
}

TEST(BitStream, RandomFieldsOfEveryWidthRoundTrip) {
  std::mt19937_64 random(7);
  std::vector<std::pair<std::uint64_t, unsigned>> fields;
  std::string out;
  BitWriter writer(out);
  for (int i = 0; i < 2000; ++i) {
    const auto bits = static_cast<unsigned>(random() % 65);
    const std::uint64_t value = bits == 64 ? random() : random() & ((std::uint64_t{1} << bits) - 1);
    writer.write(value, bits);
    fields.emplace_back(value, bits);
  }
  BitReader reader(out);
  for (const auto& [value, bits] : fields) {
    const auto read = reader.read(bits);
    ASSERT_TRUE(read.has_value());
    EXPECT_EQ(*read, value);
  }
}

TEST(BitStream, ReadingPastTheEndFails) {
  std::string out;
  BitWriter(out).write(0x3f, 6);
  BitReader reader(out);
  EXPECT_EQ(reader.read(8), 0x3fu);  // padding bits read as zero
  EXPECT_FALSE(reader.read(1).has_value());
}

TEST(BitStream, VarintsMatchProtobufAndRoundTrip) {
  std::string out;
  append_varint(300, out);
  EXPECT_EQ(out, std::string("\xac\x02", 2));
  for (const std::uint64_t value : {std::uint64_t{0}, std::uint64_t{127}, std::uint64_t{128}, ~std::uint64_t{0}}) {
    std::string bytes;
    append_varint(value, bytes);
    std::string_view view(bytes);
    EXPECT_EQ(take_varint(view), value);
    EXPECT_TRUE(view.empty());
  }
  std::string_view cut("\x80\x80", 2);
  EXPECT_FALSE(take_varint(cut).has_value());
}

TEST(BitStream, ZigzagMapsSmallMagnitudesToSmallCodes) {
  EXPECT_EQ(zigzag(0), 0u);
  EXPECT_EQ(zigzag(-1), 1u);
  EXPECT_EQ(zigzag(1), 2u);
  EXPECT_EQ(zigzag(-2), 3u);
  for (const std::int64_t v : {std::int64_t{0}, std::int64_t{-5}, std::int64_t{1} << 40, INT64_MIN, INT64_MAX}) {
    EXPECT_EQ(unzigzag(zigzag(v)), v);
  }
}

}  // namespace
}  // namespace tumble::wire
