// The token bucket behind the per-client request rate: a burst at once,
// then the rate, with time passed in.
#include <gtest/gtest.h>

#include "net/token_bucket.h"

namespace tumble::net {
namespace {

using Clock = TokenBucket::Clock;
using std::chrono::milliseconds;

// How many tokens can be taken at `now`, taking them all.
int drain(TokenBucket& bucket, Clock::time_point now) {
  int taken = 0;
  while (bucket.try_take(now)) ++taken;
  return taken;
}

TEST(TokenBucket, StartsFullAndLetsABurstThrough) {
  const Clock::time_point t0{};
  TokenBucket bucket(10, 5, t0);
  EXPECT_EQ(drain(bucket, t0), 5);
  EXPECT_FALSE(bucket.try_take(t0));
}

TEST(TokenBucket, RefillsAtTheRate) {
  const Clock::time_point t0{};
  TokenBucket bucket(10, 5, t0);
  drain(bucket, t0);
  EXPECT_FALSE(bucket.try_take(t0 + milliseconds(99)));  // 0.99 of a token
  EXPECT_TRUE(bucket.try_take(t0 + milliseconds(100)));
  EXPECT_FALSE(bucket.try_take(t0 + milliseconds(100)));
  EXPECT_EQ(drain(bucket, t0 + milliseconds(400)), 3);
}

TEST(TokenBucket, NeverHoldsMoreThanTheBurst) {
  const Clock::time_point t0{};
  TokenBucket bucket(1000, 20, t0);
  drain(bucket, t0);
  EXPECT_EQ(drain(bucket, t0 + std::chrono::hours(1)), 20);
}

TEST(TokenBucket, ARefusedTakeCostsNothing) {
  const Clock::time_point t0{};
  TokenBucket bucket(10, 1, t0);
  ASSERT_TRUE(bucket.try_take(t0));
  for (int i = 1; i < 100; ++i) EXPECT_FALSE(bucket.try_take(t0 + milliseconds(i)));
  EXPECT_TRUE(bucket.try_take(t0 + milliseconds(100)));
}

TEST(TokenBucket, SustainedRateOverALongRun) {
  // Asking every millisecond for 10 s at 50 per second with a burst of 50:
  // the burst, then 50 a second.
  const Clock::time_point t0{};
  TokenBucket bucket(50, 50, t0);
  int taken = 0;
  for (int ms = 0; ms <= 10000; ++ms) taken += bucket.try_take(t0 + milliseconds(ms)) ? 1 : 0;
  EXPECT_EQ(taken, 50 + 500);
}

TEST(TokenBucket, TimeStandingStillOrGoingBackGivesNothing) {
  const Clock::time_point t0 = Clock::time_point{} + std::chrono::seconds(5);
  TokenBucket bucket(10, 1, t0);
  ASSERT_TRUE(bucket.try_take(t0));
  EXPECT_FALSE(bucket.try_take(t0 - std::chrono::seconds(1)));
  EXPECT_FALSE(bucket.try_take(t0));
}

}  // namespace
}  // namespace tumble::net
