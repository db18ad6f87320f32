#include "net/refusal_tally.h"

#include <chrono>
#include <utility>

#include "net/log.h"

namespace tumble::net {

RefusalTally::RefusalTally(boost::asio::io_context& io, std::string what, std::size_t limit, NetCounters& counters)
    : timer_(io), what_(std::move(what)), limit_(limit), counters_(counters) {}

void RefusalTally::note(bool answered) {
  ++counters_.connections_refused;
  ++(answered ? answered_ : unanswered_);
  if (due_) return;
  due_ = true;
  timer_.expires_after(std::chrono::seconds(1));
  timer_.async_wait([this](const boost::system::error_code& error) { report(error); });
}

void RefusalTally::cancel() {
  timer_.cancel();
  due_ = false;
}

void RefusalTally::report(const boost::system::error_code& error) {
  if (error) return;  // cancelled: `this` may be gone
  due_ = false;
  const std::uint64_t refused = answered_ + unanswered_;
  if (unanswered_ == 0) {
    net_log().warn("refused {} {} over the limit of {} in the last second", refused, what_, limit_);
  } else {
    net_log().warn("refused {} {} over the limit of {} in the last second ({} closed without an answer)", refused,
                   what_, limit_, unanswered_);
  }
  answered_ = 0;
  unanswered_ = 0;
}

}  // namespace tumble::net
