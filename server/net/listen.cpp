#include "net/listen.h"

namespace tumble::net {

namespace asio = boost::asio;
using asio::ip::tcp;

sim::Status listen_on(tcp::acceptor& acceptor, const std::string& host, std::uint16_t port) {
  boost::system::error_code error;
  const asio::ip::address address = asio::ip::make_address(host, error);
  if (error) return sim::Status::error("'" + host + "' is not an IP address");
  const tcp::endpoint endpoint(address, port);
  const std::string where = host + ":" + std::to_string(port);
  if (acceptor.open(endpoint.protocol(), error); error) {
    return sim::Status::error("cannot open a socket for " + where + ": " + error.message());
  }
  acceptor.set_option(tcp::acceptor::reuse_address(true), error);
  if (acceptor.bind(endpoint, error); error) return sim::Status::error("cannot bind " + where + ": " + error.message());
  if (acceptor.listen(asio::socket_base::max_listen_connections, error); error) {
    return sim::Status::error("cannot listen on " + where + ": " + error.message());
  }
  return {};
}

}  // namespace tumble::net
