// The HTTP endpoint on a real socket: the embedded files byte for byte with
// their headers, HEAD, keep-alive, and the requests it refuses while it
// (and the TCP protocol) goes on serving everyone else.
#include <gtest/gtest.h>

#include <filesystem>

#include "http_client.h"
#include "process.h"
#include "raw_client.h"
#include "test_paths.h"
#include "test_scenes.h"
#include "test_server.h"
#include "web/embedded_files.h"

namespace tumble::test {
namespace {

namespace http = boost::beast::http;

// A file of web/dist as it is in the source tree.
std::string dist_file(const std::string& path) { return read_file(std::string(web_dist_dir()) + "/" + path); }

// The headers every response has, whatever its status.
void ExpectCommonHeaders(const HttpResponse& response) {
  EXPECT_EQ(response[http::field::cache_control], "no-cache");
  EXPECT_EQ(response["X-Content-Type-Options"], "nosniff");
}

class HttpEndpointTest : public ::testing::Test {
 protected:
  TestServer server_{kCrateScene, 240, with_http()};
};

TEST_F(HttpEndpointTest, RootServesIndexHtmlExactly) {
  const std::string index = dist_file("index.html");
  ASSERT_FALSE(index.empty()) << "web/dist/index.html is missing";
  const auto response = http_request(server_.http_port(), "GET", "/");
  ASSERT_TRUE(response);
  EXPECT_EQ(response->result(), http::status::ok);
  EXPECT_EQ(response->body(), index);
  EXPECT_EQ((*response)[http::field::content_type], "text/html; charset=utf-8");
  EXPECT_EQ((*response)[http::field::content_length], std::to_string(index.size()));
  ExpectCommonHeaders(*response);
  // The same page by its own name, and with a query string.
  EXPECT_EQ(http_request(server_.http_port(), "GET", "/index.html")->body(), index);
  EXPECT_EQ(http_request(server_.http_port(), "GET", "/?from=test")->body(), index);
}

TEST_F(HttpEndpointTest, EveryFileOfWebDistIsEmbeddedAndServed) {
  std::size_t on_disk = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(web_dist_dir())) {
    const std::string relative = std::filesystem::relative(entry.path(), web_dist_dir()).generic_string();
    if (!entry.is_regular_file() || relative.front() == '.' || relative.find("/.") != std::string::npos) continue;
    ++on_disk;
    const auto response = http_request(server_.http_port(), "GET", "/" + relative);
    ASSERT_TRUE(response) << relative;
    EXPECT_EQ(response->result(), http::status::ok) << relative;
    EXPECT_EQ(response->body(), dist_file(relative)) << relative;
    ExpectCommonHeaders(*response);
  }
  EXPECT_EQ(web::embedded_files().size(), on_disk);
  const auto script = http_request(server_.http_port(), "GET", "/viewer.js");
  ASSERT_TRUE(script);
  EXPECT_EQ((*script)[http::field::content_type], "text/javascript; charset=utf-8");
}

TEST_F(HttpEndpointTest, HeadTellsTheLengthAndSendsNoBody) {
  const std::string script = dist_file("viewer.js");
  HttpClient client(server_.http_port());
  ASSERT_TRUE(client.connected());
  ASSERT_TRUE(client.send_request("HEAD", "/viewer.js"));
  const auto head = client.read_response(/*to_head=*/true);
  ASSERT_TRUE(head);
  EXPECT_EQ(head->result(), http::status::ok);
  EXPECT_EQ((*head)[http::field::content_length], std::to_string(script.size()));
  EXPECT_EQ((*head)[http::field::content_type], "text/javascript; charset=utf-8");
  ExpectCommonHeaders(*head);
  // Had any body bytes followed, this response would not parse.
  ASSERT_TRUE(client.send_request("GET", "/"));
  const auto next = client.read_response();
  ASSERT_TRUE(next);
  EXPECT_EQ(next->result(), http::status::ok);
  EXPECT_EQ(next->body(), dist_file("index.html"));
}

TEST_F(HttpEndpointTest, KeptAliveConnectionServesPipelinedRequests) {
  HttpClient client(server_.http_port());
  const std::string host = "Host: 127.0.0.1:" + std::to_string(server_.http_port()) + "\r\n";
  ASSERT_TRUE(client.send_bytes("GET /viewer.js HTTP/1.1\r\n" + host + "\r\nGET / HTTP/1.1\r\n" + host + "\r\n"));
  const auto first = client.read_response();
  const auto second = client.read_response();
  ASSERT_TRUE(first && second);
  EXPECT_EQ(first->body(), dist_file("viewer.js"));
  EXPECT_EQ(second->body(), dist_file("index.html"));
  EXPECT_TRUE(second->keep_alive());
}

TEST_F(HttpEndpointTest, ConnectionCloseAndHttp10EndTheConnection) {
  HttpClient closing(server_.http_port());
  ASSERT_TRUE(closing.send_request("GET", "/", "Connection: close\r\n"));
  const auto response = closing.read_response();
  ASSERT_TRUE(response);
  EXPECT_FALSE(response->keep_alive());
  EXPECT_TRUE(closing.closed_by_server());

  HttpClient old(server_.http_port());
  ASSERT_TRUE(old.send_bytes("GET / HTTP/1.0\r\n\r\n"));
  const auto old_response = old.read_response();
  ASSERT_TRUE(old_response);
  EXPECT_EQ(old_response->version(), 10u);
  EXPECT_EQ(old_response->body(), dist_file("index.html"));
  EXPECT_TRUE(old.closed_by_server());
}

TEST_F(HttpEndpointTest, UnknownPathIs404AndTheConnectionGoesOn) {
  HttpClient client(server_.http_port());
  ASSERT_TRUE(client.send_request("GET", "/no-such-file.js"));
  const auto missing = client.read_response();
  ASSERT_TRUE(missing);
  EXPECT_EQ(missing->result(), http::status::not_found);
  EXPECT_EQ(missing->body(), "no such file: /no-such-file.js\n");
  EXPECT_EQ((*missing)[http::field::content_type], "text/plain; charset=utf-8");
  ExpectCommonHeaders(*missing);
  // Nothing outside the embedded files, however the path is spelt.
  for (const char* target : {"/../CMakeLists.txt", "/web/dist/index.html", "/%69ndex.html", "//index.html"}) {
    const auto response = http_request(server_.http_port(), "GET", target);
    ASSERT_TRUE(response) << target;
    EXPECT_EQ(response->result(), http::status::not_found) << target;
  }
  ASSERT_TRUE(client.send_request("GET", "/"));
  const auto found = client.read_response();
  ASSERT_TRUE(found);
  EXPECT_EQ(found->result(), http::status::ok);
}

TEST_F(HttpEndpointTest, OtherMethodsAre405WithAllow) {
  for (const char* method : {"POST", "PUT", "DELETE", "OPTIONS"}) {
    const auto response = http_request(server_.http_port(), method, "/");
    ASSERT_TRUE(response) << method;
    EXPECT_EQ(response->result(), http::status::method_not_allowed) << method;
    EXPECT_EQ((*response)[http::field::allow], "GET, HEAD") << method;
    ExpectCommonHeaders(*response);
  }
}

TEST_F(HttpEndpointTest, ARequestWithABodyIsRefusedAndTheConnectionClosed) {
  HttpClient client(server_.http_port());
  ASSERT_TRUE(client.send_request("GET", "/", "Content-Length: 5\r\n"));
  ASSERT_TRUE(client.send_bytes("hello"));
  const auto response = client.read_response();
  ASSERT_TRUE(response);
  EXPECT_EQ(response->result(), http::status::payload_too_large);
  EXPECT_FALSE(response->keep_alive());
  EXPECT_TRUE(client.closed_by_server());

  HttpClient chunked(server_.http_port());
  ASSERT_TRUE(chunked.send_request("POST", "/", "Transfer-Encoding: chunked\r\n"));
  ASSERT_TRUE(chunked.send_bytes("5\r\nhello\r\n0\r\n\r\n"));
  const auto refused = chunked.read_response();
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->result(), http::status::method_not_allowed);
  EXPECT_FALSE(refused->keep_alive());
  EXPECT_TRUE(chunked.closed_by_server());
}

TEST_F(HttpEndpointTest, OversizedHeaderIs431AndTheServerServesOn) {
  HttpClient client(server_.http_port());
  ASSERT_TRUE(client.send_request("GET", "/", "X-Padding: " + std::string(20000, 'a') + "\r\n"));
  const auto response = client.read_response();
  ASSERT_TRUE(response);
  EXPECT_EQ(response->result(), http::status::request_header_fields_too_large);
  EXPECT_EQ(response->body(), "the request's header is over the limit of 8192 bytes\n");
  EXPECT_TRUE(client.closed_by_server());

  const auto next = http_request(server_.http_port(), "GET", "/");
  ASSERT_TRUE(next);
  EXPECT_EQ(next->result(), http::status::ok);
  RawClient tcp(server_.port());
  const auto welcome = tcp.handshake();
  EXPECT_TRUE(welcome && welcome->has_welcome());
}

TEST_F(HttpEndpointTest, BytesThatAreNotHttpAre400) {
  HttpClient client(server_.http_port());
  // A TLS ClientHello's first bytes: someone tried https://.
  ASSERT_TRUE(client.send_bytes(std::string("\x16\x03\x01\x02\x00\x01\x00\x01\xfc\x03\x03", 11) + "\r\n\r\n"));
  const auto response = client.read_response();
  ASSERT_TRUE(response);
  EXPECT_EQ(response->result(), http::status::bad_request);
  EXPECT_TRUE(client.closed_by_server());

  HttpClient bad_version(server_.http_port());
  ASSERT_TRUE(bad_version.send_bytes("GET / HTTP/9\r\n\r\n"));
  const auto refused = bad_version.read_response();
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->result(), http::status::bad_request);

  const auto next = http_request(server_.http_port(), "GET", "/");
  ASSERT_TRUE(next);
  EXPECT_EQ(next->result(), http::status::ok);
}

TEST_F(HttpEndpointTest, WebSocketPathWithoutUpgradeIs426) {
  const auto response = http_request(server_.http_port(), "GET", "/ws");
  ASSERT_TRUE(response);
  EXPECT_EQ(response->result(), http::status::upgrade_required);
  EXPECT_EQ((*response)[http::field::upgrade], "websocket");
}

// RFC 9112 3.2: a server answers an HTTP/1.1 request without Host with 400.
TEST_F(HttpEndpointTest, Http11WithoutHostIs400) {
  HttpClient client(server_.http_port());
  ASSERT_TRUE(client.send_bytes("GET / HTTP/1.1\r\n\r\n"));
  const auto response = client.read_response();
  ASSERT_TRUE(response);
  EXPECT_EQ(response->result(), http::status::bad_request);
  EXPECT_EQ(response->body(), "an HTTP/1.1 request must have a Host header (RFC 9112 section 3.2)\n");

  // HTTP/1.0 had no Host: such a request is served.
  HttpClient old(server_.http_port());
  ASSERT_TRUE(old.send_bytes("GET / HTTP/1.0\r\n\r\n"));
  const auto served = old.read_response();
  ASSERT_TRUE(served);
  EXPECT_EQ(served->result(), http::status::ok);
}

// A page that rebinds its own name to 127.0.0.1 sends that name as Host,
// and an Origin that matches it: the page and the WebSocket are refused.
TEST_F(HttpEndpointTest, AHostNotAllowedIs421ForPagesAndWebSockets) {
  const std::string port = std::to_string(server_.http_port());
  HttpClient page(server_.http_port());
  ASSERT_TRUE(page.send_bytes("GET / HTTP/1.1\r\nHost: rebound.example:" + port + "\r\n\r\n"));
  const auto refused = page.read_response();
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->result(), http::status::misdirected_request);
  EXPECT_EQ(refused->body(), "this server does not answer to the host name 'rebound.example:" + port +
                                 "' (see tumbled's --http-allowed-hosts)\n");
  EXPECT_TRUE(page.closed_by_server());

  HttpClient socket(server_.http_port());
  ASSERT_TRUE(socket.send_bytes("GET /ws HTTP/1.1\r\nHost: rebound.example:" + port +
                                "\r\nOrigin: http://rebound.example:" + port +
                                "\r\nConnection: Upgrade\r\nUpgrade: websocket\r\nSec-WebSocket-Version: 13\r\n"
                                "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n\r\n"));
  const auto no_upgrade = socket.read_response();
  ASSERT_TRUE(no_upgrade);
  EXPECT_EQ(no_upgrade->result(), http::status::misdirected_request);

  // The defaults: localhost and any IP address, at any port (a container's published one), in any case.
  for (const std::string& host : {"127.0.0.1:" + port, "LocalHost:" + port, "[::1]:" + port, std::string("localhost:1"),
                                  std::string("127.0.0.1:33005")}) {
    HttpClient allowed(server_.http_port());
    ASSERT_TRUE(allowed.send_bytes("GET / HTTP/1.1\r\nHost: " + host + "\r\n\r\n"));
    const auto served = allowed.read_response();
    ASSERT_TRUE(served) << host;
    EXPECT_EQ(served->result(), http::status::ok) << host;
  }
}

TEST(HttpEndpoint, AllowedHostsReplaceTheDefaults) {
  net::ServerConfig config = with_http();
  config.http_limits.allowed_hosts = {"viewer.example", "lab.example:9000"};
  TestServer server(kCrateScene, 240, config);
  const auto status_for = [&](const std::string& host) {
    HttpClient client(server.http_port());
    client.send_bytes("GET / HTTP/1.1\r\nHost: " + host + "\r\n\r\n");
    const auto response = client.read_response();
    return response ? response->result_int() : 0u;
  };
  EXPECT_EQ(status_for("viewer.example"), 200u);
  EXPECT_EQ(status_for("VIEWER.example:8443"), 200u);  // a name without a port allows any
  EXPECT_EQ(status_for("lab.example:9000"), 200u);
  EXPECT_EQ(status_for("lab.example:9001"), 421u);
  EXPECT_EQ(status_for("127.0.0.1:" + std::to_string(server.http_port())), 421u);
}

TEST(HttpEndpoint, AHeaderThatDoesNotArriveInTimeIs408AndAnIdleConnectionIsClosed) {
  net::ServerConfig config = with_http();
  config.http_limits.header_timeout = std::chrono::milliseconds(300);
  TestServer server(kCrateScene, 240, config);

  HttpClient slow(server.http_port());
  ASSERT_TRUE(slow.send_bytes("GET / HTTP/1.1\r\nHost: 127.0.0.1\r\n"));  // no blank line: never ends
  const auto response = slow.read_response();
  ASSERT_TRUE(response);
  EXPECT_EQ(response->result(), http::status::request_timeout);
  EXPECT_EQ(response->body(), "the request's header did not arrive whole within 0.3 s\n");
  EXPECT_TRUE(slow.closed_by_server());

  // Nothing sent: closed without an answer.
  HttpClient idle(server.http_port());
  ASSERT_TRUE(idle.connected());
  const auto bytes = idle.bytes_until_closed();
  ASSERT_TRUE(bytes) << "the idle connection was not closed";
  EXPECT_EQ(*bytes, "");

  const auto next = http_request(server.http_port(), "GET", "/");
  ASSERT_TRUE(next);
  EXPECT_EQ(next->result(), http::status::ok);
}

// Half-sent requests hold HTTP connections: at the HTTP limit one more is
// closed and counted, and TCP clients, under a limit of their own, are served.
TEST(HttpEndpoint, HttpConnectionsHaveALimitOfTheirOwn) {
  net::ServerConfig config = with_http();
  config.http_limits.max_connections = 2;
  config.max_connections = 4;
  TestServer server(kCrateScene, 240, config);

  HttpClient first(server.http_port());
  HttpClient second(server.http_port());
  ASSERT_TRUE(first.send_bytes("GET / HTTP/1.1\r\n"));  // half a request each
  ASSERT_TRUE(second.send_bytes("GET / HTTP/1.1\r\n"));
  // Connections are accepted in order: the third comes after the two are held.
  HttpClient third(server.http_port());
  ASSERT_TRUE(third.connected());
  const auto bytes = third.bytes_until_closed();
  ASSERT_TRUE(bytes) << "the connection over the HTTP limit was not closed";
  EXPECT_EQ(*bytes, "");

  RawClient tcp(server.port());
  ASSERT_TRUE(tcp.handshake());
  tumble::v1::ClientMessage stats;
  stats.set_request_id(2);
  stats.mutable_get_stats();
  ASSERT_TRUE(tcp.send(stats));
  const auto reply = tcp.read_until([](const tumble::v1::ServerMessage& m) { return m.has_stats(); });
  ASSERT_TRUE(reply);
  EXPECT_EQ(reply->stats().connections_refused(), 1u);

  // The two held ones are still served once they finish their requests.
  ASSERT_TRUE(first.send_bytes("Host: 127.0.0.1:" + std::to_string(server.http_port()) + "\r\n\r\n"));
  const auto served = first.read_response();
  ASSERT_TRUE(served);
  EXPECT_EQ(served->result(), http::status::ok);
}

TEST(HttpEndpoint, IsOffUnlessAskedFor) {
  TestServer server(kCrateScene);
  EXPECT_EQ(server.http_port(), 0);
}

}  // namespace
}  // namespace tumble::test
