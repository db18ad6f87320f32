#include "tumble_client/connection.h"

#include <array>
#include <deque>
#include <optional>
#include <sstream>
#include <string_view>
#include <utility>
#include <vector>

#include <boost/asio.hpp>

#include "tumble_client/deadline.h"
#include "wire/frame.h"

namespace tumble::client {
namespace {

namespace asio = boost::asio;
using asio::ip::tcp;
using Clock = std::chrono::steady_clock;
using ErrorCode = boost::system::error_code;
using tumble::v1::ClientMessage;
using tumble::v1::ServerMessage;

// "timed out after 5 s waiting for the reply to ListBodies".
Failure timed_out(const Deadline& deadline, const std::string& activity) {
  std::ostringstream text;
  text << "timed out after " << std::chrono::duration<double>(deadline.timeout).count() << " s " << activity;
  return Failure{FailureKind::timeout, text.str()};
}

// Whether a message is one next_message() hands over: a pose frame, a
// world event or a connection-level error (anything else is a late reply).
bool is_unsolicited(const ServerMessage& message) {
  return message.has_pose_frame() || message.has_world_event() ||
         (message.has_error() && message.error().request_id() == 0);
}

}  // namespace

// Everything a connection owns. Lives on the heap so Connection can move
// while Asio objects stay where their handlers expect them.
struct Connection::State {
  explicit State(Endpoint to) : endpoint(std::move(to)) {}

  // Runs the I/O context until `done` or the deadline. When the deadline
  // passes first, calls `cancel` and runs on until the cancelled operation's
  // handler has run (it may still have completed normally).
  template <typename Cancel>
  void run(const bool& done, const Deadline& deadline, Cancel cancel);

  // Remembers `failure` as the reason the stream is unusable and returns it.
  Failure fail(Failure failure) {
    broken = failure;
    return failure;
  }

  // Writes one frame. A write cut short leaves half a frame on the wire, so
  // any failure here breaks the connection.
  std::optional<Failure> write(const ClientMessage& message, const Deadline& deadline);

  // Reads the next whole message. A timeout leaves the connection usable:
  // no bytes are lost, a partial frame stays buffered.
  Result<ServerMessage> read(const Deadline& deadline, const std::string& activity);

  // The oldest message a request queued while it waited for its reply.
  std::optional<ServerMessage> take_queued() {
    if (unsolicited.empty()) return std::nullopt;
    ServerMessage message = std::move(unsolicited.front());
    unsolicited.pop_front();
    return message;
  }

  // The next whole message among the bytes read so far; none while they do
  // not make one. A malformed frame breaks the connection.
  std::optional<Result<ServerMessage>> take_buffered();

  // Reads what has arrived, without waiting, until a message is whole;
  // fails with kind timeout when none is, and the connection stays usable.
  Result<ServerMessage> read_available();

  Endpoint endpoint;
  asio::io_context io{1};
  tcp::socket socket{io};
  wire::FrameReader reader{kMaxInboundFrameBytes};
  std::array<char, 64 * 1024> read_buffer{};
  std::deque<ServerMessage> unsolicited;  // pose frames, world events and connection errors not yet handed over
  std::uint64_t next_request_id = 1;
  tumble::v1::Welcome welcome;
  std::optional<Failure> broken;  // set once the stream cannot be used; every later call returns it
};

template <typename Cancel>
void Connection::State::run(const bool& done, const Deadline& deadline, Cancel cancel) {
  io.restart();
  while (!done) {
    const std::size_t ran = deadline.at ? io.run_one_until(*deadline.at) : io.run_one();
    if (ran == 0) break;
  }
  if (done) return;
  cancel();
  io.restart();
  while (!done && io.run_one() != 0) {
  }
}

std::optional<Failure> Connection::State::write(const ClientMessage& message, const Deadline& deadline) {
  if (broken) return broken;
  const std::string bytes = wire::encode_frame(message);
  bool done = false;
  ErrorCode error = asio::error::operation_aborted;
  asio::async_write(socket, asio::buffer(bytes), [&](const ErrorCode& result, std::size_t) {
    error = result;
    done = true;
  });
  run(done, deadline, [this] {
    ErrorCode ignored;
    socket.cancel(ignored);
  });
  if (error == asio::error::operation_aborted) return fail(timed_out(deadline, "sending " + kind_name(message)));
  if (error) {
    return fail(Failure{FailureKind::closed, "connection to " + to_string(endpoint) + " lost: " + error.message()});
  }
  return std::nullopt;
}

std::optional<Result<ServerMessage>> Connection::State::take_buffered() {
  std::string_view body;
  switch (reader.next(body)) {
    case wire::FrameStatus::frame: {
      ServerMessage message;
      if (!message.ParseFromArray(body.data(), static_cast<int>(body.size()))) {
        return fail(Failure{FailureKind::protocol, "the server sent a frame of " + std::to_string(body.size()) +
                                                       " bytes that is not a tumble.v1.ServerMessage"});
      }
      return message;
    }
    case wire::FrameStatus::too_large:
      return fail(Failure{FailureKind::protocol, "the server announced a frame of " +
                                                     std::to_string(reader.declared_bytes()) +
                                                     " bytes, over the client's limit of " +
                                                     std::to_string(reader.max_frame_bytes()) + " bytes"});
    case wire::FrameStatus::bad_length:
      return fail(Failure{FailureKind::protocol, "the server sent a frame length that is not a valid varint"});
    case wire::FrameStatus::need_more:
      break;
  }
  return std::nullopt;
}

Result<ServerMessage> Connection::State::read_available() {
  for (;;) {
    if (broken) return *broken;
    if (auto buffered = take_buffered()) return std::move(*buffered);
    // Asio's synchronous read then returns would_block instead of waiting;
    // its asynchronous operations, which the other calls use, are unaffected.
    ErrorCode error;
    socket.non_blocking(true, error);
    const std::size_t received = error ? 0 : socket.read_some(asio::buffer(read_buffer), error);
    if (error == asio::error::would_block || error == asio::error::try_again) {
      return Failure{FailureKind::timeout, "no whole message has arrived from " + to_string(endpoint)};
    }
    if (error == asio::error::eof) return fail(Failure{FailureKind::closed, "connection closed by the server"});
    if (error) {
      return fail(Failure{FailureKind::closed, "connection to " + to_string(endpoint) + " lost: " + error.message()});
    }
    reader.append(read_buffer.data(), received);
  }
}

Result<ServerMessage> Connection::State::read(const Deadline& deadline, const std::string& activity) {
  for (;;) {
    if (broken) return *broken;
    if (auto buffered = take_buffered()) return std::move(*buffered);

    bool done = false;
    ErrorCode error = asio::error::operation_aborted;
    std::size_t received = 0;
    socket.async_read_some(asio::buffer(read_buffer), [&](const ErrorCode& result, std::size_t bytes) {
      error = result;
      received = bytes;
      done = true;
    });
    run(done, deadline, [this] {
      ErrorCode ignored;
      socket.cancel(ignored);
    });
    if (error == asio::error::operation_aborted) return timed_out(deadline, activity);
    if (error == asio::error::eof) return fail(Failure{FailureKind::closed, "connection closed by the server"});
    if (error) {
      return fail(Failure{FailureKind::closed, "connection to " + to_string(endpoint) + " lost: " + error.message()});
    }
    reader.append(read_buffer.data(), received);
  }
}

Result<Connection> Connection::connect(const Endpoint& endpoint, const std::string& client_name,
                                       const std::string& token, Timeout timeout) {
  auto state = std::make_unique<State>(endpoint);
  const Deadline deadline = Deadline::after(timeout);
  const std::string where = to_string(endpoint);

  // An address is used as it is. A host name goes to the system resolver,
  // which runs on a thread of Asio's and cannot be interrupted: its own
  // timeouts bound a hung lookup.
  std::vector<tcp::endpoint> addresses;
  ErrorCode not_an_address;
  const asio::ip::address address = asio::ip::make_address(endpoint.host, not_an_address);
  if (!not_an_address) {
    addresses.emplace_back(address, endpoint.port);
  } else {
    tcp::resolver resolver(state->io);
    bool done = false;
    ErrorCode error = asio::error::operation_aborted;
    resolver.async_resolve(endpoint.host, std::to_string(endpoint.port), tcp::resolver::numeric_service,
                           [&](const ErrorCode& result, const tcp::resolver::results_type& found) {
                             error = result;
                             for (const auto& entry : found) addresses.push_back(entry.endpoint());
                             done = true;
                           });
    state->run(done, deadline, [&resolver] { resolver.cancel(); });
    if (error == asio::error::operation_aborted) return timed_out(deadline, "resolving '" + endpoint.host + "'");
    if (error) return Failure{FailureKind::connect, "cannot resolve '" + endpoint.host + "': " + error.message()};
  }
  {
    bool done = false;
    ErrorCode error = asio::error::operation_aborted;
    asio::async_connect(state->socket, addresses, [&](const ErrorCode& result, const tcp::endpoint&) {
      error = result;
      done = true;
    });
    // Closing, not cancelling: a cancelled attempt would move on to the
    // next address instead of stopping.
    state->run(done, deadline, [&state] {
      ErrorCode ignored;
      state->socket.close(ignored);
    });
    if (error == asio::error::operation_aborted) return timed_out(deadline, "connecting to " + where);
    if (error) return Failure{FailureKind::connect, "cannot connect to " + where + ": " + error.message()};
  }
  ErrorCode ignored;
  state->socket.set_option(tcp::no_delay(true), ignored);

  ClientMessage hello;
  hello.set_request_id(state->next_request_id++);
  hello.mutable_hello()->set_protocol_version(tumble::v1::PROTOCOL_VERSION_CURRENT);
  hello.mutable_hello()->set_client_name(client_name);
  hello.mutable_hello()->set_token(token);
  if (auto failure = state->write(hello, deadline)) return *failure;

  auto reply = state->read(deadline, "waiting for the server's Welcome");
  if (!reply) return reply.failure();
  if (reply->has_error()) return server_failure(reply->error());
  if (!reply->has_welcome()) {
    return Failure{FailureKind::protocol, "the server answered Hello with " + kind_name(reply.value())};
  }
  state->welcome = std::move(*reply->mutable_welcome());
  return Connection(std::move(state));
}

Connection::Connection(std::unique_ptr<State> state) : state_(std::move(state)) {}
Connection::Connection(Connection&& other) noexcept = default;
Connection& Connection::operator=(Connection&& other) noexcept = default;
Connection::~Connection() = default;

const tumble::v1::Welcome& Connection::welcome() const { return state_->welcome; }

const Endpoint& Connection::endpoint() const { return state_->endpoint; }

std::string Connection::describe() const { return to_string(state_->endpoint); }

Result<ServerMessage> Connection::request(ClientMessage message, Timeout timeout) {
  State& state = *state_;
  const std::uint64_t id = state.next_request_id++;
  message.set_request_id(id);
  const Deadline deadline = Deadline::after(timeout);
  if (auto failure = state.write(message, deadline)) return *failure;

  const std::string name = kind_name(message);
  const std::string activity = "waiting for the reply to " + name;
  for (;;) {
    auto received = state.read(deadline, activity);
    if (!received) return received;
    ServerMessage& reply = received.value();
    if (reply.has_pose_frame() || reply.has_world_event()) {
      state.unsolicited.push_back(std::move(reply));
      continue;
    }
    const std::uint64_t echoed = echoed_request_id(reply);
    if (reply.has_error() && echoed == 0) return server_failure(reply.error());
    if (echoed != id) continue;  // a late reply to a request that timed out
    if (reply.has_error()) return server_failure(reply.error());
    const ServerMessage::KindCase expected = expected_reply(message.kind_case());
    if (expected != ServerMessage::KIND_NOT_SET && reply.kind_case() != expected) {
      return state.fail(Failure{FailureKind::protocol, "the server answered " + name + " with " + kind_name(reply)});
    }
    return received;
  }
}

Result<ServerMessage> Connection::next_message(Timeout timeout) {
  State& state = *state_;
  if (auto queued = state.take_queued()) return std::move(*queued);
  const Deadline deadline = Deadline::after(timeout);
  for (;;) {
    auto received = state.read(deadline, "waiting for a message from the server");
    if (!received || is_unsolicited(received.value())) return received;
    // Anything else is a late reply to a request that timed out.
  }
}

Result<ServerMessage> Connection::poll_message() {
  State& state = *state_;
  if (auto queued = state.take_queued()) return std::move(*queued);
  for (;;) {
    auto received = state.read_available();
    if (!received || is_unsolicited(received.value())) return received;
  }
}

int Connection::native_handle() { return state_->socket.native_handle(); }

}  // namespace tumble::client
