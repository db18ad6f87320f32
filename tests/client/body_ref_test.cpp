#include "tumble_client/body_ref.h"

#include <gtest/gtest.h>

namespace tumble::client {
namespace {

TEST(ParseBodyRef, DigitsAreAnId) {
  auto ref = parse_body_ref("42");
  ASSERT_TRUE(ref.ok());
  ASSERT_EQ(ref->ref_case(), tumble::v1::BodyRef::kId);
  EXPECT_EQ(ref->id(), 42u);

  ref = parse_body_ref("007");
  ASSERT_TRUE(ref.ok());
  ASSERT_EQ(ref->ref_case(), tumble::v1::BodyRef::kId);
  EXPECT_EQ(ref->id(), 7u);

  ref = parse_body_ref("0");
  ASSERT_TRUE(ref.ok());
  ASSERT_EQ(ref->ref_case(), tumble::v1::BodyRef::kId);
  EXPECT_EQ(ref->id(), 0u);
}

TEST(ParseBodyRef, LargestIdFitsAndOneMoreFails) {
  auto largest = parse_body_ref("4294967295");
  ASSERT_TRUE(largest.ok());
  EXPECT_EQ(largest->id(), 4294967295u);

  auto too_big = parse_body_ref("4294967296");
  ASSERT_FALSE(too_big.ok());
  EXPECT_EQ(too_big.failure().kind, FailureKind::invalid_argument);
  EXPECT_NE(too_big.failure().message.find("out of range"), std::string::npos);
  EXPECT_FALSE(parse_body_ref("123456789012345678901234567890").ok());
}

TEST(ParseBodyRef, AnythingElseIsAName) {
  for (const char* text : {"crate", "crate7", "7crate", "-1", "1.5", " 1", "wheel left"}) {
    auto ref = parse_body_ref(text);
    ASSERT_TRUE(ref.ok()) << text;
    ASSERT_EQ(ref->ref_case(), tumble::v1::BodyRef::kName) << text;
    EXPECT_EQ(ref->name(), text);
  }
}

TEST(ParseBodyRef, EmptyIsRejected) {
  auto ref = parse_body_ref("");
  ASSERT_FALSE(ref.ok());
  EXPECT_EQ(ref.failure().kind, FailureKind::invalid_argument);
}

}  // namespace
}  // namespace tumble::client
