// The Host names the HTTP endpoint answers to: the defaults for a bound
// address, and the three kinds of entry.
#include "net/allowed_hosts.h"

#include <gtest/gtest.h>

namespace tumble::net {
namespace {

TEST(AllowedHosts, TheDefaultsAreLocalhostTheListenNameAndAnyAddressAtAnyPort) {
  const AllowedHosts hosts = AllowedHosts::defaults("0.0.0.0");
  EXPECT_EQ(hosts.entries(), (std::vector<std::string>{"localhost"}));
  EXPECT_TRUE(hosts.any_ip_address());
  EXPECT_TRUE(hosts.allows("localhost:8080"));
  EXPECT_TRUE(hosts.allows("LOCALHOST"));
  // A container's published port or a proxy's: the name decides, not the port.
  EXPECT_TRUE(hosts.allows("127.0.0.1:33005"));
  EXPECT_TRUE(hosts.allows("192.168.1.20:8080"));
  EXPECT_TRUE(hosts.allows("[::1]:9000"));
  EXPECT_TRUE(hosts.allows("[fe80::1]"));
  // A rebinding page sends its own name.
  EXPECT_FALSE(hosts.allows("attacker.example:8080"));
  EXPECT_FALSE(hosts.allows("127.0.0.1.attacker.example"));
  EXPECT_FALSE(hosts.allows("localhost.attacker.example:8080"));
  EXPECT_FALSE(hosts.allows("1.2.3"));
  EXPECT_FALSE(hosts.allows("256.1.1.1:80"));
  EXPECT_FALSE(hosts.allows("[attacker]:80"));
  EXPECT_FALSE(hosts.allows(""));
  // A listen name is served; a listen address adds nothing to any IP address.
  EXPECT_EQ(AllowedHosts::defaults("tumble.lan").entries(), (std::vector<std::string>{"localhost", "tumble.lan"}));
  EXPECT_TRUE(AllowedHosts::defaults("tumble.lan").allows("Tumble.LAN:8080"));
  EXPECT_EQ(AllowedHosts::defaults("::1").entries(), (std::vector<std::string>{"localhost"}));
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
  EXPECT_FALSE(hosts.any_ip_address());  // a list is exactly what it says
  EXPECT_FALSE(hosts.allows("127.0.0.1:8080"));
  EXPECT_TRUE(AllowedHosts({"*"}).allows("anything.example:1"));
}

}  // namespace
}  // namespace tumble::net
