// The HTTP endpoint on a real socket: the embedded files byte for byte with
// their headers, HEAD, keep-alive, and the requests it refuses while it
// (and the TCP protocol) goes on serving everyone else.
#include <gtest/gtest.h>

#include <filesystem>

#include "http_client.h"
#include "process.h"
#include "raw_client.h"
#include "test_server.h"
#include "web/embedded_files.h"

namespace tumble::test {
namespace {

namespace http = boost::beast::http;

const char* kScene = R"({"gravity": [0, 0, 0], "bodies": [
    {"name": "crate", "shape": {"box": {"half_extents": [0.5, 0.5, 0.5]}}, "mass": 2}]})";

net::ServerConfig with_http() {
  net::ServerConfig config;
  config.serve_http = true;
  return config;
}

// A file of web/dist as it is in the source tree.
std::string dist_file(const std::string& path) { return read_file(std::string(TUMBLE_WEB_DIST) + "/" + path); }

// The headers every response has, whatever its status.
void ExpectCommonHeaders(const HttpResponse& response) {
  EXPECT_EQ(response[http::field::cache_control], "no-cache");
  EXPECT_EQ(response["X-Content-Type-Options"], "nosniff");
}

class HttpEndpointTest : public ::testing::Test {
 protected:
  TestServer server_{kScene, 240, with_http()};
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
  for (const auto& entry : std::filesystem::recursive_directory_iterator(TUMBLE_WEB_DIST)) {
    const std::string relative = std::filesystem::relative(entry.path(), TUMBLE_WEB_DIST).generic_string();
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
  ASSERT_TRUE(client.send_bytes("GET /viewer.js HTTP/1.1\r\nHost: x\r\n\r\nGET / HTTP/1.1\r\nHost: x\r\n\r\n"));
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

TEST(HttpEndpoint, IsOffUnlessAskedFor) {
  TestServer server(kScene);
  EXPECT_EQ(server.http_port(), 0);
}

}  // namespace
}  // namespace tumble::test
