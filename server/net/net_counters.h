// The network layer's figures in GetStats's Stats: the sim answers with its
// own counters and the session that relays the answer adds these.
//
// Thread: the I/O thread only, like every session that updates them.
#pragma once

#include <cstddef>
#include <cstdint>

#include "tumble/v1/protocol.pb.h"

namespace tumble::net {

struct NetCounters {
  std::size_t clients = 0;  // open connections, handshaking and refused ones included
  std::uint64_t bytes_sent =
      0;  // protocol messages written to clients since the server started, WebSocket framing included
  std::uint64_t connections_refused = 0;        // TCP, WebSocket and HTTP connections refused for a limit
  std::uint64_t clients_closed_for_errors = 0;  // sessions closed for drawing errors too fast

  // Writes the network's fields into a Stats.
  void fill(tumble::v1::Stats& stats) const {
    stats.set_clients(static_cast<std::uint32_t>(clients));
    stats.set_bytes_sent(bytes_sent);
    stats.set_connections_refused(connections_refused);
    stats.set_clients_closed_for_errors(clients_closed_for_errors);
  }
};

}  // namespace tumble::net
