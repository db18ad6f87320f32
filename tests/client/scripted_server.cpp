#include "scripted_server.h"

#include <chrono>

#include <gtest/gtest.h>

namespace tumble::client::testing {
namespace {

namespace asio = boost::asio;
using asio::ip::tcp;

// How long any one step of a script may wait for the client.
constexpr auto kStepLimit = std::chrono::seconds(5);

}  // namespace

ServerPeer::ServerPeer(asio::io_context& io, tcp::socket socket)
    : io_(io), socket_(std::move(socket)), reader_(wire::kDefaultMaxFrameBytes), buffer_{} {}

template <typename Start>
boost::system::error_code ServerPeer::run(Start start, std::size_t& transferred) {
  bool done = false;
  boost::system::error_code result = asio::error::timed_out;
  start([&](const boost::system::error_code& error, std::size_t bytes) {
    result = error;
    transferred = bytes;
    done = true;
  });
  io_.restart();
  io_.run_for(kStepLimit);
  if (!done) {
    boost::system::error_code ignored;
    socket_.cancel(ignored);
    io_.restart();
    io_.run();
    result = asio::error::timed_out;
  }
  return result;
}

std::optional<tumble::v1::ClientMessage> ServerPeer::receive() {
  for (;;) {
    std::string_view body;
    const wire::FrameStatus status = reader_.next(body);
    if (status == wire::FrameStatus::frame) {
      tumble::v1::ClientMessage message;
      if (!message.ParseFromArray(body.data(), static_cast<int>(body.size()))) return std::nullopt;
      return message;
    }
    if (status != wire::FrameStatus::need_more) return std::nullopt;
    std::size_t received = 0;
    const auto error = run([this](auto handler) { socket_.async_read_some(asio::buffer(buffer_), handler); }, received);
    if (error) return std::nullopt;
    reader_.append(buffer_, received);
  }
}

void ServerPeer::send(const tumble::v1::ServerMessage& message) { send_bytes(wire::encode_frame(message)); }

void ServerPeer::send_bytes(std::string_view bytes) {
  std::size_t sent = 0;
  const auto error = run(
      [this, bytes](auto handler) { asio::async_write(socket_, asio::buffer(bytes.data(), bytes.size()), handler); },
      sent);
  EXPECT_FALSE(error) << "scripted server could not send: " << error.message();
}

void ServerPeer::wait_for_close() {
  for (;;) {
    std::size_t received = 0;
    const auto error = run([this](auto handler) { socket_.async_read_some(asio::buffer(buffer_), handler); }, received);
    if (error) {
      EXPECT_NE(error, asio::error::timed_out) << "the client did not close the connection";
      return;
    }
  }
}

void ServerPeer::close() {
  boost::system::error_code ignored;
  socket_.shutdown(tcp::socket::shutdown_both, ignored);
  socket_.close(ignored);
}

ScriptedServer::ScriptedServer(Script script) : ScriptedServer(std::vector<Script>{std::move(script)}) {}

ScriptedServer::ScriptedServer(std::vector<Script> scripts, std::chrono::milliseconds refuse_for) : acceptor_(io_) {
  acceptor_.open(tcp::v4());
  acceptor_.bind(tcp::endpoint(asio::ip::make_address("127.0.0.1"), 0));
  endpoint_ = Endpoint{"127.0.0.1", acceptor_.local_endpoint().port()};
  if (refuse_for == std::chrono::milliseconds::zero()) acceptor_.listen();
  thread_ = std::thread([this, scripts = std::move(scripts), refuse_for] {
    if (refuse_for > std::chrono::milliseconds::zero()) {
      std::this_thread::sleep_for(refuse_for);
      acceptor_.listen();
    }
    for (std::size_t i = 0; i < scripts.size(); ++i) {
      tcp::socket socket(io_);
      bool accepted = false;
      boost::system::error_code error;
      acceptor_.async_accept(socket, [&](const boost::system::error_code& result) {
        error = result;
        accepted = true;
      });
      io_.restart();
      io_.run_for(kStepLimit);
      if (!accepted || error) {
        ADD_FAILURE() << "the client never made connection " << i + 1 << " to the scripted server";
        return;
      }
      ServerPeer peer(io_, std::move(socket));
      scripts[i](peer);
    }
  });
}

ScriptedServer::~ScriptedServer() { thread_.join(); }

}  // namespace tumble::client::testing
