// Connections refused for a limit, counted and logged as one line a second:
// "refused 40 connections over the limit of 1024 in the last second". A flood
// of connections then costs the log one line a second, however fast it comes.
// Each refusal also counts in NetCounters::connections_refused.
//
// Thread: the I/O thread only.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "net/asio.h"
#include "net/net_counters.h"

namespace tumble::net {

class RefusalTally {
 public:
  // `what` names the connections in the log ("connections", "HTTP
  // connections"); `limit` is the limit they were refused for. `counters`
  // must outlive the tally.
  RefusalTally(boost::asio::io_context& io, std::string what, std::size_t limit, NetCounters& counters);

  // Counts one refusal: `answered` when the client is told why, else it is
  // closed without a word. The count is logged within a second.
  void note(bool answered);

  // Drops the line not yet logged (the server is stopping).
  void cancel();

 private:
  void report(const boost::system::error_code& error);

  boost::asio::steady_timer timer_;
  std::string what_;
  std::size_t limit_;
  NetCounters& counters_;
  std::uint64_t answered_ = 0;    // refusals since the last line, told why
  std::uint64_t unanswered_ = 0;  // refusals since the last line, closed without a word
  bool due_ = false;              // a line is due when timer_ fires
};

}  // namespace tumble::net
