#include "tumble_client/endpoint.h"

#include <gtest/gtest.h>

namespace tumble::client {
namespace {

TEST(ParseEndpoint, AcceptsHostAndPort) {
  auto endpoint = parse_endpoint("127.0.0.1:7400");
  ASSERT_TRUE(endpoint.ok()) << endpoint.failure().message;
  EXPECT_EQ(endpoint->host, "127.0.0.1");
  EXPECT_EQ(endpoint->port, 7400);

  endpoint = parse_endpoint("tumble.example.org:65535");
  ASSERT_TRUE(endpoint.ok()) << endpoint.failure().message;
  EXPECT_EQ(endpoint->host, "tumble.example.org");
  EXPECT_EQ(endpoint->port, 65535);
}

TEST(ParseEndpoint, AcceptsBracketedIpv6) {
  auto endpoint = parse_endpoint("[::1]:7401");
  ASSERT_TRUE(endpoint.ok()) << endpoint.failure().message;
  EXPECT_EQ(endpoint->host, "::1");
  EXPECT_EQ(endpoint->port, 7401);
}

TEST(ParseEndpoint, RejectsMissingColon) {
  auto endpoint = parse_endpoint("localhost");
  ASSERT_FALSE(endpoint.ok());
  EXPECT_EQ(endpoint.failure().kind, FailureKind::invalid_argument);
  EXPECT_NE(endpoint.failure().message.find("'localhost'"), std::string::npos) << endpoint.failure().message;
  EXPECT_NE(endpoint.failure().message.find("port is missing"), std::string::npos) << endpoint.failure().message;
}

TEST(ParseEndpoint, RejectsBadPorts) {
  for (const char* text : {"localhost:", "localhost:0", "localhost:65536", "localhost:99999999999", "localhost:12a",
                           "localhost:-1", "localhost: 80"}) {
    auto endpoint = parse_endpoint(text);
    ASSERT_FALSE(endpoint.ok()) << text;
    EXPECT_NE(endpoint.failure().message.find("1 to 65535"), std::string::npos) << endpoint.failure().message;
  }
}

TEST(ParseEndpoint, RejectsMissingHost) {
  EXPECT_FALSE(parse_endpoint(":7400").ok());
  EXPECT_FALSE(parse_endpoint("[]:7400").ok());
}

TEST(ParseEndpoint, RejectsUnbracketedOrUnbalancedIpv6) {
  auto bare = parse_endpoint("::1:7400");
  ASSERT_FALSE(bare.ok());
  EXPECT_NE(bare.failure().message.find("brackets"), std::string::npos) << bare.failure().message;
  EXPECT_FALSE(parse_endpoint("[::1:7400").ok());
  EXPECT_FALSE(parse_endpoint("::1]:7400").ok());
}

TEST(EndpointToString, BracketsIpv6Only) {
  EXPECT_EQ(to_string(Endpoint{"127.0.0.1", 7400}), "127.0.0.1:7400");
  EXPECT_EQ(to_string(Endpoint{"::1", 7400}), "[::1]:7400");
  auto round_trip = parse_endpoint(to_string(Endpoint{"fe80::1", 9}));
  ASSERT_TRUE(round_trip.ok());
  EXPECT_EQ(round_trip->host, "fe80::1");
  EXPECT_EQ(round_trip->port, 9);
}

}  // namespace
}  // namespace tumble::client
