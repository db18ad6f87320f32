// The one HOST:PORT parser of tumbled's --listen and --http and tumble's
// --server.
#include "tumble/endpoint.h"

#include <gtest/gtest.h>

namespace tumble {
namespace {

// The endpoint `text` reads as; fails the test when it reads as none.
Endpoint parsed(std::string_view text, PortZero port_zero = PortZero::refused) {
  const ParsedEndpoint result = parse_endpoint(text, port_zero);
  EXPECT_TRUE(result.endpoint.has_value()) << text << ": " << result.error;
  EXPECT_EQ(result.error, "") << text;
  return result.endpoint.value_or(Endpoint{});
}

// Why `text` is refused; fails the test when it is not.
std::string refusal(std::string_view text, PortZero port_zero = PortZero::refused) {
  const ParsedEndpoint result = parse_endpoint(text, port_zero);
  EXPECT_FALSE(result.endpoint.has_value()) << text;
  return result.error;
}

TEST(ParseEndpoint, AcceptsHostAndPort) {
  Endpoint endpoint = parsed("127.0.0.1:7400");
  EXPECT_EQ(endpoint.host, "127.0.0.1");
  EXPECT_EQ(endpoint.port, 7400);

  endpoint = parsed("tumble.example.org:65535");
  EXPECT_EQ(endpoint.host, "tumble.example.org");
  EXPECT_EQ(endpoint.port, 65535);
}

TEST(ParseEndpoint, AcceptsBracketedIpv6) {
  const Endpoint endpoint = parsed("[::1]:7401");
  EXPECT_EQ(endpoint.host, "::1");
  EXPECT_EQ(endpoint.port, 7401);
}

TEST(DefaultEndpoint, IsLoopbackPort7400) {
  EXPECT_EQ(default_endpoint().host, "127.0.0.1");
  EXPECT_EQ(default_endpoint().port, 7400);
  EXPECT_EQ(to_string(default_endpoint()), "127.0.0.1:7400");
}

TEST(ParseEndpoint, RejectsMissingColon) {
  EXPECT_EQ(refusal("localhost"), "'localhost' is not HOST:PORT: the port is missing");
}

TEST(ParseEndpoint, RejectsBadPorts) {
  for (const char* text : {"localhost:", "localhost:0", "localhost:65536", "localhost:99999999999", "localhost:12a",
                           "localhost:-1", "localhost: 80", "localhost:+80"}) {
    EXPECT_EQ(refusal(text), "'" + std::string(text) + "' is not HOST:PORT: the port must be a number from 1 to 65535");
  }
}

TEST(ParseEndpoint, PortZeroOnlyWhenAllowed) {
  const Endpoint endpoint = parsed("127.0.0.1:0", PortZero::allowed);
  EXPECT_EQ(endpoint.host, "127.0.0.1");
  EXPECT_EQ(endpoint.port, 0);
  EXPECT_EQ(parsed("[::1]:0", PortZero::allowed).host, "::1");
  EXPECT_EQ(parsed("localhost:65535", PortZero::allowed).port, 65535);
  EXPECT_EQ(refusal("127.0.0.1:0"),
            "'127.0.0.1:0' is not HOST:PORT: the port "
            "must be a number from 1 to 65535");
  for (const char* text : {"localhost:", "localhost:65536", "localhost:-0", "localhost:x"}) {
    EXPECT_EQ(refusal(text, PortZero::allowed),
              "'" + std::string(text) + "' is not HOST:PORT: the port must be a number from 0 to 65535");
  }
}

TEST(ParseEndpoint, RejectsMissingHost) {
  EXPECT_EQ(refusal(":7400"), "':7400' is not HOST:PORT: the host is missing");
  EXPECT_EQ(refusal("[]:7400"), "'[]:7400' is not HOST:PORT: the host is missing");
}

TEST(ParseEndpoint, RejectsUnbracketedOrUnbalancedIpv6) {
  EXPECT_EQ(refusal("::1:7400"),
            "'::1:7400' is not HOST:PORT: write an IPv6 "
            "address in brackets, as in [::1]:7400");
  EXPECT_EQ(refusal("[::1:7400"), "'[::1:7400' is not HOST:PORT: unbalanced '['");
  EXPECT_EQ(refusal("::1]:7400"),
            "'::1]:7400' is not HOST:PORT: write an IPv6 "
            "address in brackets, as in [::1]:7400");
}

TEST(EndpointToString, BracketsIpv6Only) {
  EXPECT_EQ(to_string(Endpoint{"127.0.0.1", 7400}), "127.0.0.1:7400");
  EXPECT_EQ(to_string(Endpoint{"::1", 7400}), "[::1]:7400");
  const Endpoint round_trip = parsed(to_string(Endpoint{"fe80::1", 9}));
  EXPECT_EQ(round_trip.host, "fe80::1");
  EXPECT_EQ(round_trip.port, 9);
}

}  // namespace
}  // namespace tumble
