#include "net/transport.h"

namespace tumble::net {

namespace {

// error_category's destructor is protected and not virtual: categories are
// static objects, never deleted through a base pointer.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wnon-virtual-dtor"
class TransportCategory final : public boost::system::error_category {
 public:
  const char* name() const noexcept override { return "tumble.transport"; }
  std::string message(int value) const override {
    switch (static_cast<TransportError>(value)) {
      case TransportError::text_message:
        return "a text WebSocket message: tumble reads ClientMessage frames from binary messages only";
      case TransportError::illegal_frame_length:
        return "a WebSocket frame's 64-bit payload length has its most significant bit set, which RFC 6455 "
               "section 5.2 forbids";
    }
    return "unknown transport error";
  }
};
#pragma GCC diagnostic pop

}  // namespace

const boost::system::error_category& transport_category() {
  static const TransportCategory category;
  return category;
}

boost::system::error_code make_error_code(TransportError error) {
  return {static_cast<int>(error), transport_category()};
}

}  // namespace tumble::net
