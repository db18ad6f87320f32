#include "net/session.h"

#include <optional>

#include <spdlog/fmt/fmt.h>

#include "net/log.h"
#include "net/publisher.h"
#include "sim/log_text.h"
#include "sim/request_check.h"
#include "sim/simulation.h"
#include "wire/quantized_poses.h"

namespace tumble::net {

namespace asio = boost::asio;
using tumble::v1::ClientMessage;
using tumble::v1::ServerMessage;
using Clock = std::chrono::steady_clock;

namespace {

// "10 s", "0.5 s", "12.3457 s": a duration in the sentences clients and the log see.
std::string seconds_text(Clock::duration duration) {
  return fmt::format("{:g} s", std::chrono::duration<double>(duration).count());
}

}  // namespace

Session::Session(std::unique_ptr<Transport> transport, std::uint64_t id, SessionContext& context, ClosedFn on_closed)
    : transport_(std::move(transport)),
      id_(id),
      context_(context),
      on_closed_(std::move(on_closed)),
      peer_(transport_->peer()),
      reader_(context.limits.max_frame_bytes),
      connected_at_(Clock::now()),
      command_budget_(context.limits.commands_per_second, context.limits.command_burst, connected_at_),
      error_budget_(context.limits.errors_per_second, context.limits.error_burst, connected_at_),
      linger_timer_(context.io) {
  ++context_.counters.clients;
}

Session::~Session() {
  if (!closed_) --context_.counters.clients;
}

void Session::start() {
  net_log().debug("session {}: connected from {} over {}", id_, peer_, transport_->kind());
  read_more();
}

void Session::read_more() {
  if (closed_ || reading_stopped_) return;
  read_in_flight_ = true;
  transport_->async_read_some(asio::buffer(read_buffer_),
                              [self = shared_from_this()](const boost::system::error_code& error, std::size_t bytes) {
                                self->on_read(error, bytes);
                              });
}

void Session::on_read(const boost::system::error_code& error, std::size_t bytes) {
  read_in_flight_ = false;
  if (closed_) return;
  if (reading_stopped_) {
    // The session refused the client (a deadline passed) while this read
    // was under way: what it brought is discarded, as in linger().
    if (error) {
      close(close_reason_);
    } else {
      linger_read();
    }
    return;
  }
  if (error.category() == transport_category()) {
    // The client broke its transport's rules (a WebSocket text message).
    fail(tumble::v1::MALFORMED_FRAME, error.message());
    return;
  }
  if (error) {
    close(error == asio::error::eof ? "client closed the connection" : "read failed: " + error.message());
    return;
  }
  reader_.append(read_buffer_.data(), bytes);
  std::string_view body;
  bool took_frame = false;
  for (;;) {
    switch (reader_.next(body)) {
      case wire::FrameStatus::frame:
        took_frame = true;
        if (!handle_frame(body)) return;
        continue;
      case wire::FrameStatus::need_more:
        // A frame held in part began with these bytes unless it was already
        // under way before them (and no whole frame came in between).
        if (reader_.buffered_bytes() == 0) {
          frame_begun_at_.reset();
        } else if (took_frame || !frame_begun_at_) {
          frame_begun_at_ = Clock::now();
        }
        read_more();
        return;
      case wire::FrameStatus::too_large:
        fail(tumble::v1::FRAME_TOO_LARGE, "frame of " + std::to_string(reader_.declared_bytes()) +
                                              " bytes exceeds the limit of " +
                                              std::to_string(reader_.max_frame_bytes()) + " bytes");
        return;
      case wire::FrameStatus::bad_length:
        fail(tumble::v1::MALFORMED_FRAME, "the frame's length prefix is not a valid varint");
        return;
    }
  }
}

bool Session::handle_frame(std::string_view body) {
  ClientMessage message;
  if (!message.ParseFromArray(body.data(), static_cast<int>(body.size()))) {
    fail(tumble::v1::MALFORMED_FRAME,
         "a frame of " + std::to_string(body.size()) + " bytes is not a valid tumble.v1.ClientMessage");
    return false;
  }
  if (!greeted_) {
    handle_hello(message);
    return greeted_;
  }
  handle_request(std::move(message));
  return !closed_ && !reading_stopped_;
}

void Session::handle_hello(const ClientMessage& message) {
  if (message.kind_case() != ClientMessage::kHello) {
    fail(tumble::v1::HANDSHAKE_REQUIRED, "the first message must be Hello", message.request_id());
    return;
  }
  const auto& hello = message.hello();
  if (hello.protocol_version() != tumble::v1::PROTOCOL_VERSION_CURRENT) {
    fail(tumble::v1::UNSUPPORTED_VERSION,
         "protocol version " + std::to_string(hello.protocol_version()) + " is not supported; this server speaks " +
             std::to_string(static_cast<int>(tumble::v1::PROTOCOL_VERSION_CURRENT)),
         message.request_id());
    return;
  }
  if (auto problem = sim::check_hello(hello)) {
    fail(problem->code, problem->message, message.request_id());
    return;
  }
  const std::optional<tumble::v1::Role> role = authenticate(context_.access, hello.token());
  if (!role) {
    fail(tumble::v1::UNAUTHENTICATED,
         hello.token().empty() ? "this server requires an access token in Hello"
                               : "the access token in Hello is not accepted by this server",
         message.request_id());
    return;
  }
  role_ = *role;
  greeted_ = true;
  client_name_ = hello.client_name();
  ServerMessage reply;
  auto& welcome = *reply.mutable_welcome();
  welcome.set_protocol_version(tumble::v1::PROTOCOL_VERSION_CURRENT);
  welcome.set_server_version(context_.server_version);
  welcome.set_tick_rate_hz(context_.sim.tick_rate_hz());
  welcome.set_tick(context_.sim.tick());
  welcome.set_sim_time(context_.sim.sim_time());
  welcome.set_body_count(context_.sim.body_count());
  welcome.set_role(role_);
  send(reply);
  net_log().info("session {}: {} '{}' joined as {} over {}", id_, peer_, sim::log_text(client_name_),
                 role_ == tumble::v1::ROLE_OBSERVER ? "an observer" : "a controller", transport_->kind());
}

bool Session::admit(const ClientMessage& message) {
  // The rate comes first, so that even refusals cannot be had faster than it.
  if (!command_budget_.try_take(Clock::now())) {
    if (!rate_limited_) {
      net_log().info("session {}: {} is over {:g} requests per second; refusing the excess", id_, peer_,
                     context_.limits.commands_per_second);
    }
    rate_limited_ = true;
    send_error(message.request_id(), tumble::v1::RATE_LIMITED,
               fmt::format("over the limit of {:g} requests per second; this request was not applied",
                           context_.limits.commands_per_second));
    return false;
  }
  rate_limited_ = false;
  if (!role_may(role_, message.kind_case())) {
    send_error(message.request_id(), tumble::v1::PERMISSION_DENIED, observer_denial(message.kind_case()));
    return false;
  }
  return true;
}

void Session::handle_request(ClientMessage message) {
  if (!admit(message)) return;
  if (auto problem = sim::check_request(message)) {
    send_error(message.request_id(), problem->code, problem->message);
    return;
  }
  switch (message.kind_case()) {
    case ClientMessage::kHello:
      send_error(message.request_id(), tumble::v1::INVALID_ARGUMENT, "Hello was already received");
      return;
    case ClientMessage::kSubscribe:
      handle_subscribe(message);
      return;
    case ClientMessage::kUnsubscribe:
      handle_unsubscribe(message);
      return;
    case ClientMessage::kKeyFrameRequest:
      handle_key_frame_request(message);
      return;
    default:
      break;
  }
  // Everything else is the world's business: the sim applies it at the next
  // tick and its reply comes back to this thread.
  sim::Command command;
  command.message = std::move(message);
  command.reply = [weak = weak_from_this(), &io = context_.io](ServerMessage reply) {
    asio::post(io, [weak, reply = std::move(reply)]() mutable {
      if (auto self = weak.lock()) self->send_reply(std::move(reply));
    });
  };
  context_.sim.submit(std::move(command));
}

void Session::send_reply(ServerMessage reply) {
  if (reply.has_error() && !charge_error()) return;
  if (reply.has_stats()) context_.counters.fill(*reply.mutable_stats());
  send(reply);
}

void Session::handle_subscribe(const ClientMessage& message) {
  auto result = context_.publisher.subscribe(shared_from_this(), message.subscribe());
  if (auto* problem = std::get_if<sim::RequestError>(&result)) {
    send_error(message.request_id(), problem->code, problem->message);
    return;
  }
  const Subscription& subscription = std::get<Subscription>(result);
  ServerMessage reply;
  auto& subscribed = *reply.mutable_subscribed();
  subscribed.set_request_id(message.request_id());
  subscribed.set_subscription_id(subscription.stream_id);
  subscribed.set_period_ticks(subscription.period_ticks);
  subscribed.set_rate_hz(subscription.rate_hz);
  subscribed.set_encoding(subscription.encoding);
  if (subscription.encoding != tumble::v1::POSE_ENCODING_FULL) subscribed.set_position_step(wire::kPositionStep);
  // A repeated Subscribe starts the client's picture of a DELTA stream afresh.
  if (subscription.encoding == tumble::v1::POSE_ENCODING_DELTA) outbound_.restart_delta(subscription.stream_id);
  send(reply);
}

void Session::handle_key_frame_request(const ClientMessage& message) {
  const std::uint32_t stream = message.key_frame_request().subscription_id();
  if (!context_.publisher.request_key_frame(shared_from_this(), stream)) {
    send_error(message.request_id(), tumble::v1::UNKNOWN_SUBSCRIPTION,
               "this connection has no subscription " + std::to_string(stream));
    return;
  }
  outbound_.restart_delta(stream);
  ServerMessage reply;
  reply.mutable_ack()->set_request_id(message.request_id());
  reply.mutable_ack()->set_applied_tick(context_.sim.tick());
  send(reply);
}

void Session::handle_unsubscribe(const ClientMessage& message) {
  const std::uint32_t stream = message.unsubscribe().subscription_id();
  if (!context_.publisher.unsubscribe(*this, stream)) {
    send_error(message.request_id(), tumble::v1::UNKNOWN_SUBSCRIPTION,
               "this connection has no subscription " + std::to_string(stream));
    return;
  }
  outbound_.drop_stream(stream);
  ServerMessage reply;
  reply.mutable_ack()->set_request_id(message.request_id());
  reply.mutable_ack()->set_applied_tick(context_.sim.tick());
  send(reply);
}

void Session::send_error(std::uint64_t request_id, tumble::v1::ErrorCode code, const std::string& text) {
  if (charge_error()) queue_error(request_id, code, text);
}

bool Session::charge_error() {
  // Once closed for its errors a client gets no more of them; a session
  // closing for another reason answers what it took before, which is
  // bounded by what it read before it stopped.
  if (closed_for_errors_) return false;
  if (reading_stopped_ || closed_) return true;
  if (error_budget_.try_take(Clock::now())) return true;
  closed_for_errors_ = true;
  ++context_.counters.clients_closed_for_errors;
  fail(tumble::v1::RESOURCE_EXHAUSTED, fmt::format("over the limit of {:g} errors per second; the connection is closed",
                                                   context_.limits.errors_per_second));
  return false;
}

void Session::queue_error(std::uint64_t request_id, tumble::v1::ErrorCode code, const std::string& text) {
  ServerMessage reply;
  auto& error = *reply.mutable_error();
  error.set_request_id(request_id);
  error.set_code(code);
  error.set_message(text);
  send(reply);
}

void Session::fail(tumble::v1::ErrorCode code, const std::string& text, std::uint64_t request_id) {
  net_log().warn("session {}: {}: {} ({}); closing", id_, peer_, sim::log_text(text, sim::kLogMessageBytes),
                 tumble::v1::ErrorCode_Name(code));
  stop_with_error(code, text, request_id);
}

void Session::stop_with_error(tumble::v1::ErrorCode code, const std::string& text, std::uint64_t request_id) {
  queue_error(request_id, code, text);
  reading_stopped_ = true;
  close_when_flushed_ = true;
  close_reason_ = text;
  close_code_ = code;
  if (!writing_) write_more();
}

void Session::refuse(tumble::v1::ErrorCode code, const std::string& text) {
  net_log().debug("session {}: {}: refused: {}", id_, peer_, text);
  stop_with_error(code, text, 0);
}

void Session::enforce_deadlines(Clock::time_point now) {
  if (closed_) return;
  if (!greeted_ && !reading_stopped_ && now - connected_at_ > context_.limits.handshake_timeout) {
    fail(tumble::v1::HANDSHAKE_REQUIRED,
         "no Hello within " + seconds_text(context_.limits.handshake_timeout) + " of connecting");
    return;
  }
  // Before Hello the handshake timeout bounds a partial frame.
  if (greeted_ && !reading_stopped_ && frame_begun_at_ && now - *frame_begun_at_ > context_.limits.frame_timeout) {
    fail(tumble::v1::MALFORMED_FRAME, "a frame begun " + seconds_text(now - *frame_begun_at_) + " ago has " +
                                          std::to_string(reader_.buffered_bytes()) +
                                          " bytes and is still incomplete, over the limit of " +
                                          seconds_text(context_.limits.frame_timeout));
    return;
  }
  // Anything queued is written as soon as the write before it is done, so
  // the oldest undelivered bytes are those of the write under way.
  if (writing_ && now - in_flight_since_ > context_.limits.max_undelivered) {
    close("a message queued " + seconds_text(now - in_flight_since_) +
          " ago is still undelivered (the client is not reading), over the limit of " +
          seconds_text(context_.limits.max_undelivered));
  }
}

void Session::send(const ServerMessage& message) {
  if (closed_) return;
  if (outbound_.empty()) queued_since_ = Clock::now();
  outbound_.push_message(wire::encode_frame(message));
  if (outbound_.pending_message_bytes() > context_.limits.max_pending_bytes) {
    close("client left " + std::to_string(outbound_.pending_message_bytes()) +
          " bytes of replies unread, over the limit of " + std::to_string(context_.limits.max_pending_bytes));
    return;
  }
  if (!writing_) write_more();
}

void Session::send_frame(std::uint32_t stream, std::shared_ptr<const std::string> bytes) {
  if (closed_ || close_when_flushed_) return;
  if (outbound_.empty()) queued_since_ = Clock::now();
  outbound_.offer_frame(stream, std::move(bytes));
  if (!writing_) write_more();
}

void Session::send_delta_frame(std::uint32_t stream, std::shared_ptr<const QuantizedFrame> frame) {
  if (closed_ || close_when_flushed_) return;
  if (outbound_.empty()) queued_since_ = Clock::now();
  outbound_.offer_delta_frame(stream, std::move(frame));
  if (!writing_) write_more();
}

void Session::write_more() {
  if (closed_ || shut_down_) return;
  if (outbound_.empty()) {
    if (close_when_flushed_) linger();
    return;
  }
  outbound_.take_batch(in_flight_);
  in_flight_since_ = queued_since_;
  write_buffers_.clear();
  for (std::string_view piece : in_flight_.pieces) write_buffers_.emplace_back(piece.data(), piece.size());
  writing_ = true;
  transport_->async_write(
      write_buffers_, [self = shared_from_this()](const boost::system::error_code& error) { self->on_written(error); });
}

void Session::on_written(const boost::system::error_code& error) {
  writing_ = false;
  if (!error) context_.counters.bytes_sent += transport_->wire_size(in_flight_.bytes);
  if (closed_) return;
  if (error) {
    close("write failed: " + error.message());
    return;
  }
  write_more();
}

void Session::linger() {
  shut_down_ = true;
  // The handler only keeps the session alive while the transport shuts down.
  const auto cause = close_code_ == tumble::v1::FRAME_TOO_LARGE ? ShutdownCause::too_large : ShutdownCause::refused;
  transport_->async_shutdown(cause, close_reason_, [self = shared_from_this()](const boost::system::error_code&) {});
  linger_timer_.expires_after(std::chrono::seconds(2));
  linger_timer_.async_wait([self = shared_from_this()](const boost::system::error_code& error) {
    if (!error) self->close(self->close_reason_);
  });
  if (!read_in_flight_) linger_read();
}

void Session::linger_read() {
  // Discard whatever the client still sends until it closes its side.
  if (closed_) return;
  read_in_flight_ = true;
  transport_->async_read_some(asio::buffer(read_buffer_),
                              [self = shared_from_this()](const boost::system::error_code& error, std::size_t) {
                                self->read_in_flight_ = false;
                                if (error) {
                                  self->close(self->close_reason_);
                                } else {
                                  self->linger_read();
                                }
                              });
}

void Session::close(const std::string& reason) {
  if (closed_) return;
  closed_ = true;
  --context_.counters.clients;
  net_log().info("session {}: {} disconnected: {}", id_, peer_, sim::log_text(reason, sim::kLogMessageBytes));
  transport_->close();
  linger_timer_.cancel();
  context_.publisher.remove_session(*this);
  if (on_closed_) on_closed_(id_);
}

}  // namespace tumble::net
