#include "net/tcp_transport.h"

#include <utility>

namespace tumble::net {

namespace asio = boost::asio;

std::string peer_of(const asio::ip::tcp::socket& socket) {
  boost::system::error_code error;
  const auto endpoint = socket.remote_endpoint(error);
  if (error) return "unknown";
  return endpoint.address().to_string() + ":" + std::to_string(endpoint.port());
}

TcpTransport::TcpTransport(asio::ip::tcp::socket socket) : socket_(std::move(socket)), peer_(peer_of(socket_)) {
  boost::system::error_code ignored;
  socket_.set_option(asio::ip::tcp::no_delay(true), ignored);
}

void TcpTransport::async_read_some(asio::mutable_buffer buffer, ReadHandler handler) {
  socket_.async_read_some(buffer, std::move(handler));
}

void TcpTransport::async_write(const std::vector<asio::const_buffer>& buffers, DoneHandler handler) {
  asio::async_write(
      socket_, buffers,
      [handler = std::move(handler)](const boost::system::error_code& error, std::size_t) { handler(error); });
}

void TcpTransport::async_shutdown(ShutdownCause /*cause*/, const std::string& /*reason*/, DoneHandler handler) {
  boost::system::error_code error;
  socket_.shutdown(asio::ip::tcp::socket::shutdown_send, error);
  asio::post(socket_.get_executor(), [handler = std::move(handler), error] { handler(error); });
}

void TcpTransport::close() {
  boost::system::error_code ignored;
  socket_.shutdown(asio::ip::tcp::socket::shutdown_both, ignored);
  socket_.close(ignored);
}

}  // namespace tumble::net
