// The Host names the HTTP endpoint answers to: the defaults for a bound
// address, and the three kinds of entry.
#include "net/allowed_hosts.h"

#include <gtest/gtest.h>

namespace tumble::net {
namespace {

TEST(AllowedHosts, TheDefaultsAreTheListenAddressAndLoopbackNamesWithThePort) {
  const AllowedHosts hosts = AllowedHosts::defaults("0.0.0.0", 8080);
  EXPECT_EQ(hosts.entries(),
            (std::vector<std::string>{"0.0.0.0:8080", "localhost:8080", "127.0.0.1:8080", "[::1]:8080"}));
  EXPECT_TRUE(hosts.allows("localhost:8080"));
  EXPECT_TRUE(hosts.allows("LOCALHOST:8080"));
  EXPECT_FALSE(hosts.allows("localhost"));  // port 80
  EXPECT_FALSE(hosts.allows("localhost:8081"));
  EXPECT_FALSE(hosts.allows("attacker.example:8080"));
  EXPECT_FALSE(hosts.allows(""));
  // An IPv6 listen address is bracketed; on port 80 the names without a port are served too.
  EXPECT_EQ(AllowedHosts::defaults("::1", 80).entries(),
            (std::vector<std::string>{"[::1]:80", "[::1]", "localhost:80", "localhost", "127.0.0.1:80", "127.0.0.1"}));
}

TEST(AllowedHosts, ANameWithoutAPortAllowsAnyAndStarAllowsEverything) {
  const AllowedHosts hosts({"viewer.example", "lab.example:9000", "[fe80::1]"});
  EXPECT_TRUE(hosts.allows("viewer.example"));
  EXPECT_TRUE(hosts.allows("Viewer.Example:1234"));
  EXPECT_TRUE(hosts.allows("lab.example:9000"));
  EXPECT_FALSE(hosts.allows("lab.example"));
  EXPECT_FALSE(hosts.allows("lab.example:90"));
  EXPECT_TRUE(hosts.allows("[fe80::1]:8080"));
  EXPECT_FALSE(hosts.allows("viewer.example.attacker.example"));
  EXPECT_TRUE(AllowedHosts({"*"}).allows("anything.example:1"));
}

}  // namespace
}  // namespace tumble::net
