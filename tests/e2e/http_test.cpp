// tumbled --http as a user runs it: the page over HTTP, a WebSocket client
// that sees the crate move when the CLI pushes it over TCP, and no HTTP
// listener at all without the flag.
#include <gtest/gtest.h>

#include <dirent.h>
#include <unistd.h>

#include <climits>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "cli_helpers.h"
#include "http_client.h"
#include "poll_until.h"
#include "test_paths.h"
#include "tumbled_process.h"
#include "ws_client.h"

namespace tumble::test {
namespace {

using nlohmann::json;
using tumble::v1::ClientMessage;
using tumble::v1::ServerMessage;

// The TCP ports process `pid` listens on, from its socket descriptors and
// the kernel's tables of TCP sockets (IPv4 and IPv6).
std::set<std::uint16_t> listening_ports(pid_t pid) {
  std::set<std::string> inodes;  // "socket:[N]" of the process's descriptors
  const std::string fd_dir = "/proc/" + std::to_string(pid) + "/fd";
  if (DIR* dir = ::opendir(fd_dir.c_str())) {
    while (const dirent* entry = ::readdir(dir)) {
      char target[PATH_MAX];
      const ssize_t n = ::readlink((fd_dir + "/" + entry->d_name).c_str(), target, sizeof target - 1);
      if (n > 0) inodes.insert(std::string(target, static_cast<std::size_t>(n)));
    }
    ::closedir(dir);
  }
  std::set<std::uint16_t> ports;
  for (const char* table : {"/proc/net/tcp", "/proc/net/tcp6"}) {
    std::istringstream lines(read_file(table));
    std::string line;
    std::getline(lines, line);  // the column titles
    while (std::getline(lines, line)) {
      // sl local_address rem_address st tx_queue:rx_queue tr:tm->when retrnsmt uid timeout inode
      std::istringstream fields(line);
      std::string slot, local, remote, state, queues, timer, retransmits, uid, timeout, inode;
      fields >> slot >> local >> remote >> state >> queues >> timer >> retransmits >> uid >> timeout >> inode;
      if (state != "0A" || !inodes.count("socket:[" + inode + "]")) continue;  // 0A: LISTEN
      ports.insert(static_cast<std::uint16_t>(std::stoul(local.substr(local.find(':') + 1), nullptr, 16)));
    }
  }
  return ports;
}

// tumbled on the scene with --http on an ephemeral port, and that port.
struct HttpTumbled {
  explicit HttpTumbled(std::vector<std::string> extra_args = {})
      : process(kFloatingScene, with_http(std::move(extra_args))) {
    const std::string text = read_file(port_file());  // written before --port-file, which started() waited for
    if (!text.empty()) http_port = static_cast<std::uint16_t>(std::stoul(text));
  }
  std::string port_file() const { return dir + "/http-port"; }
  std::vector<std::string> with_http(std::vector<std::string> args) const {
    args.insert(args.begin(), {"--http", "127.0.0.1:0", "--http-port-file", port_file()});
    return args;
  }

  std::string dir = make_temp_dir();
  TumbledProcess process;
  std::uint16_t http_port = 0;
};

TEST(TumbledHttp, ServesThePageItWasBuiltWith) {
  HttpTumbled server;
  ASSERT_TRUE(server.process.started()) << server.process.log();
  ASSERT_NE(server.http_port, 0) << server.process.log();
  const auto page = http_request(server.http_port, "GET", "/");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->result_int(), 200u);
  EXPECT_EQ(page->body(), read_file(std::string(web_dist_dir()) + "/index.html"));
  EXPECT_EQ(page->at(boost::beast::http::field::content_type), "text/html; charset=utf-8");
  const auto script = http_request(server.http_port, "HEAD", "/viewer.js");
  ASSERT_TRUE(script);
  EXPECT_EQ(script->result_int(), 200u);
}

// The CLI pushes the crate over TCP; a WebSocket subscriber sees it move
// exactly as the integrator says: 2 N s on 2 kg is 1 m/s from the impulse's
// tick on, and x then grows by 1/240 m a tick. (Frames are latest-wins: the
// subscriber, not reading while the CLI runs, may skip the impulse's tick.)
TEST(TumbledHttp, AWebSocketSubscriberSeesTheCliPushTheCrate) {
  HttpTumbled server;
  ASSERT_TRUE(server.process.started()) << server.process.log();
  WsClient viewer(server.http_port);
  ASSERT_TRUE(viewer.connected()) << "handshake status " << viewer.handshake_status();
  const auto welcome = viewer.handshake("e2e-viewer");
  ASSERT_TRUE(welcome && welcome->has_welcome());
  ClientMessage subscribe;
  subscribe.set_request_id(2);
  subscribe.mutable_subscribe()->set_rate_hz(0);  // every tick
  subscribe.mutable_subscribe()->add_bodies()->set_name("crate");
  ASSERT_TRUE(viewer.send(subscribe));
  const auto at_rest = viewer.read_until([](const ServerMessage& m) { return m.has_pose_frame(); });
  ASSERT_TRUE(at_rest);
  EXPECT_EQ(at_rest->pose_frame().linear_velocities(0), 0.0f);

  const json ack = run_json(server.process, {"impulse", "crate", "--impulse", "2", "0", "0"});
  ASSERT_TRUE(ack.contains("applied_tick")) << ack;
  const auto applied = ack["applied_tick"].get<std::uint64_t>();

  const auto first =
      viewer.read_until([&](const ServerMessage& m) { return m.has_pose_frame() && m.pose_frame().tick() >= applied; });
  ASSERT_TRUE(first);
  EXPECT_FLOAT_EQ(first->pose_frame().linear_velocities(0), 1.0f);
  const std::uint64_t first_tick = first->pose_frame().tick();
  const auto later = viewer.read_until(
      [&](const ServerMessage& m) { return m.has_pose_frame() && m.pose_frame().tick() >= first_tick + 48; });
  ASSERT_TRUE(later);
  const double ticks = static_cast<double>(later->pose_frame().tick() - first_tick);
  EXPECT_NEAR(static_cast<double>(later->pose_frame().positions(0) - first->pose_frame().positions(0)), ticks * kDt,
              1e-5);
  EXPECT_FLOAT_EQ(later->pose_frame().linear_velocities(0), 1.0f);
}

TEST(TumbledHttp, WithoutTheFlagNothingListensForHttp) {
  TumbledProcess plain(kFloatingScene);
  ASSERT_TRUE(plain.started()) << plain.log();
  EXPECT_EQ(listening_ports(plain.process().pid()), std::set<std::uint16_t>{plain.port()});

  HttpTumbled with_http;
  ASSERT_TRUE(with_http.process.started()) << with_http.process.log();
  EXPECT_EQ(listening_ports(with_http.process.process().pid()),
            (std::set<std::uint16_t>{with_http.process.port(), with_http.http_port}));
}

// The HTTP endpoint's own limits, set by their flags: the Host names it
// answers to, the header deadline, and the connections it holds.
TEST(TumbledHttp, TheHttpLimitsComeFromTheirFlags) {
  HttpTumbled named_server({"--http-allowed-hosts", "viewer.example"});
  ASSERT_TRUE(named_server.process.started()) << named_server.process.log();
  // Each request on a connection of its own, one after the other.
  HttpClient named(named_server.http_port);
  ASSERT_TRUE(named.send_bytes("GET / HTTP/1.1\r\nHost: viewer.example:8080\r\n\r\n"));
  const auto served = named.read_response();
  ASSERT_TRUE(served);
  EXPECT_EQ(served->result_int(), 200u);
  HttpClient by_address(named_server.http_port);  // the default names are replaced
  ASSERT_TRUE(by_address.send_request("GET", "/"));
  const auto refused = by_address.read_response();
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->result_int(), 421u);

  HttpTumbled server({"--http-header-timeout", "0.3", "--max-http-connections", "1"});
  ASSERT_TRUE(server.process.started()) << server.process.log();
  HttpClient slow(server.http_port);
  ASSERT_TRUE(slow.send_bytes("GET / HTTP/1.1\r\n"));
  // While the slow one is held, it is the one HTTP connection allowed.
  HttpClient over(server.http_port);
  const auto nothing = over.bytes_until_closed();
  ASSERT_TRUE(nothing) << "the connection over --max-http-connections was not closed";
  EXPECT_EQ(*nothing, "");
  const auto timed_out = slow.read_response();
  ASSERT_TRUE(timed_out);
  EXPECT_EQ(timed_out->result_int(), 408u);
  EXPECT_TRUE(poll_until([&] {
    return server.process.log().find("refused 1 HTTP connections over the limit of 1 in the last second") !=
           std::string::npos;
  })) << server.process.log();
}

TEST(TumbledHttp, BadHttpFlagsAreErrors) {
  EXPECT_EQ(run_command({tumbled_path(), "--listen", "127.0.0.1:0", "--http", "no-port"}).exit_code, 2);
  EXPECT_EQ(run_command({tumbled_path(), "--listen", "127.0.0.1:0", "--http-port-file", "/tmp/x"}).exit_code, 2);

  HttpTumbled first;
  ASSERT_TRUE(first.process.started()) << first.process.log();
  const CommandResult taken = run_command(
      {tumbled_path(), "--listen", "127.0.0.1:0", "--http", "127.0.0.1:" + std::to_string(first.http_port)});
  EXPECT_EQ(taken.exit_code, 1);
  EXPECT_NE(taken.err.find("the HTTP endpoint: cannot bind"), std::string::npos) << taken.err;
}

}  // namespace
}  // namespace tumble::test
