// A Session's stream over a plain TCP socket: the protocol's bytes as they
// are, Nagle off.
//
// Thread: the I/O thread only.
#pragma once

#include <string>
#include <vector>

#include "net/asio.h"
#include "net/transport.h"

namespace tumble::net {

class TcpTransport final : public Transport {
 public:
  explicit TcpTransport(boost::asio::ip::tcp::socket socket);

  void async_read_some(boost::asio::mutable_buffer buffer, ReadHandler handler) override;
  void async_write(const std::vector<boost::asio::const_buffer>& buffers, DoneHandler handler) override;
  // Shuts down the sending side at once; the handler is posted.
  void async_shutdown(ShutdownCause cause, const std::string& reason, DoneHandler handler) override;
  void close() override;
  const std::string& peer() const override { return peer_; }
  const char* kind() const override { return "TCP"; }
  std::size_t wire_size(std::size_t payload) const override { return payload; }

 private:
  boost::asio::ip::tcp::socket socket_;
  std::string peer_;
};

// "ADDRESS:PORT" of a connected socket's peer, or "unknown".
std::string peer_of(const boost::asio::ip::tcp::socket& socket);

}  // namespace tumble::net
