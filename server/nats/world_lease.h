// WorldLease: which tumbled leads a world kept in a JetStream bucket
// (--nats-state), so that one world is stepped and published by one server
// at a time. The lease is the bucket's key "<world>.lease", holding a
// tumble.v1.WorldLease; every write of it is a compare-and-set on the key's
// revision, so of two writers racing for one revision only one succeeds.
//
//  - The leader rewrites the lease every `renew`, naming the revision it
//    last wrote. It holds the lease until `timeout - renew` after it sent
//    its last renewal that was taken; past that (it cannot reach the
//    cluster), or when a renewal is refused (the key moved on: another
//    server took it), it has lost the lease.
//  - A standby reads the key every `renew`. A revision it has seen
//    unchanged for `timeout`, a released lease or no key at all is a lease
//    to take, by the same compare-and-set; the revision it writes is its
//    epoch. A standby started with `defer` also waits `timeout` before it
//    takes a lease nobody held.
// A standby takes over no sooner than `timeout` after it saw the last
// renewal; the leader stops `timeout - renew` after it sent it: the two
// never both hold the lease, by `renew` of margin for their clocks.
//
// Thread: acquire(), start_renewing() and release() from tumbled's main
// thread; the renewals run on the lease's own thread; held(), epoch() and
// the observations from any thread.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include <nats/nats.h>
#include <spdlog/logger.h>

#include "nats/nats_link.h"
#include "sim/status.h"

namespace tumble::nats {

// A server's id: 16 random hexadecimal digits, new at every start.
std::string make_server_id();

struct WorldLeaseConfig {
  std::string bucket;  // the --nats-state bucket, already made
  std::string world;   // the lease is the key "<world>.lease"
  std::string id;      // this server's id (make_server_id())
  std::chrono::milliseconds renew{500};
  std::chrono::milliseconds timeout{2000};  // > renew
  bool defer = false;                       // --standby: do not take a lease nobody held before `timeout`
};

class WorldLease {
 public:
  WorldLease(NatsLink& link, WorldLeaseConfig config, spdlog::logger& log);
  ~WorldLease();  // stops renewing; does not release
  WorldLease(const WorldLease&) = delete;
  WorldLease& operator=(const WorldLease&) = delete;

  // Waits as a standby until this server takes the lease. Fails only when
  // JetStream cannot be used at all.
  sim::Status acquire();

  // Renews the lease on its own thread until release() or until it is lost;
  // then `lost` runs once, on that thread, with the reason.
  void start_renewing(std::function<void(const std::string& reason)> lost);

  // Stops renewing (the lease stays held until it runs out): a shutdown
  // under way is not turned into a restart as a standby.
  void stop_renewing();
  // Stops renewing and, when the lease is still this server's, releases it
  // so that a standby takes over at once instead of after the timeout.
  void release();

  // Whether this server leads the world now: checked before each frame,
  // event and reply is published.
  bool held() const;
  // The epoch of this server's leadership; 0 before acquire().
  std::uint64_t epoch() const { return epoch_.load(std::memory_order_relaxed); }
  // As a standby: the leader the lease names and its epoch, as last read.
  std::string observed_leader() const;
  std::uint64_t observed_epoch() const { return observed_epoch_.load(std::memory_order_relaxed); }
  const std::string& id() const { return config_.id; }

 private:
  enum class Write { taken, refused, unreachable };
  // One compare-and-set of the lease to `value` over `last` (0: create).
  Write write(const std::string& value, std::uint64_t last, std::uint64_t* revision);
  void renew_loop(const std::function<void(const std::string&)>& lost);
  void extend_from(std::chrono::steady_clock::time_point sent);

  NatsLink& link_;
  WorldLeaseConfig config_;
  spdlog::logger& log_;
  std::string key_;
  jsCtx* jetstream_ = nullptr;  // waits at most `renew` for an answer
  kvStore* bucket_ = nullptr;
  std::uint64_t revision_ = 0;  // the lease's revision this server last wrote (renewal thread)
  std::atomic<std::uint64_t> epoch_{0};
  std::atomic<std::int64_t> held_until_ns_{0};  // steady clock; 0: not held
  mutable std::mutex observed_mutex_;
  std::string observed_leader_;
  std::atomic<std::uint64_t> observed_epoch_{0};
  std::mutex stop_mutex_;
  std::condition_variable stop_wakeup_;
  bool stopping_ = false;
  std::thread renewer_;
};

}  // namespace tumble::nats
