// ScriptedServer: a TCP server on 127.0.0.1 that plays a test's scripts on
// its own thread, one connection per script, so Connection and the commands
// can be tested against exactly the messages, bytes and closes a script
// chooses.
//
// Every operation of the server side gives up after a few seconds, so a
// broken client fails its test instead of hanging it.
#pragma once

#include <chrono>
#include <functional>
#include <optional>
#include <string_view>
#include <thread>
#include <vector>

#include <boost/asio.hpp>

#include "tumble/endpoint.h"
#include "tumble/v1/protocol.pb.h"
#include "wire/frame.h"

namespace tumble::client::testing {

// The server's end of the one connection. Used only by the script's thread.
class ServerPeer {
 public:
  ServerPeer(boost::asio::io_context& io, boost::asio::ip::tcp::socket socket);

  // The next message from the client; none when the client closed, sent
  // something unparsable, or sent nothing in time.
  std::optional<tumble::v1::ClientMessage> receive();

  // Sends one framed message.
  void send(const tumble::v1::ServerMessage& message);

  // Sends raw bytes, framed or not.
  void send_bytes(std::string_view bytes);

  // Waits until the client closes its end (or the time limit passes).
  void wait_for_close();

  // Closes the connection.
  void close();

 private:
  // Starts one async operation through `start` and runs it to completion or
  // the time limit; returns its error (timed_out at the limit).
  template <typename Start>
  boost::system::error_code run(Start start, std::size_t& transferred);

  boost::asio::io_context& io_;
  boost::asio::ip::tcp::socket socket_;
  wire::FrameReader reader_;
  char buffer_[4096];
};

class ScriptedServer {
 public:
  using Script = std::function<void(ServerPeer& peer)>;

  // Listens on 127.0.0.1 at a free port, then on a thread accepts one
  // connection and runs `script` on it.
  explicit ScriptedServer(Script script);

  // Takes a free port of 127.0.0.1 at once but refuses connections to it
  // for `refuse_for` (bound, not listening); then listens and, on a thread,
  // accepts one connection per script in order, running each script to its
  // end before accepting the next.
  explicit ScriptedServer(std::vector<Script> scripts,
                          std::chrono::milliseconds refuse_for = std::chrono::milliseconds::zero());

  // Waits for the script to finish.
  ~ScriptedServer();

  ScriptedServer(const ScriptedServer&) = delete;
  ScriptedServer& operator=(const ScriptedServer&) = delete;

  // Where to connect.
  Endpoint endpoint() const { return endpoint_; }

 private:
  boost::asio::io_context io_;
  boost::asio::ip::tcp::acceptor acceptor_;
  Endpoint endpoint_;
  std::thread thread_;
};

}  // namespace tumble::client::testing
