// The replies the sim gives to a request: an Ack with the tick it took
// effect at, or an Error with a code and a sentence. Both echo the
// request's id.
#pragma once

#include <cstdint>
#include <string>
#include <utility>

#include "tumble/v1/protocol.pb.h"

namespace tumble::sim {

inline tumble::v1::ServerMessage ack_reply(const tumble::v1::ClientMessage& request, std::uint64_t applied_tick) {
  tumble::v1::ServerMessage reply;
  reply.mutable_ack()->set_request_id(request.request_id());
  reply.mutable_ack()->set_applied_tick(applied_tick);
  return reply;
}

inline tumble::v1::ServerMessage error_reply(const tumble::v1::ClientMessage& request, tumble::v1::ErrorCode code,
                                             std::string text) {
  tumble::v1::ServerMessage reply;
  auto* error = reply.mutable_error();
  error->set_request_id(request.request_id());
  error->set_code(code);
  error->set_message(std::move(text));
  return reply;
}

}  // namespace tumble::sim
