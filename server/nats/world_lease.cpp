#include "nats/world_lease.h"

#include <algorithm>
#include <random>

#include "tumble/v1/world_info.pb.h"

namespace tumble::nats {
namespace {

using Clock = std::chrono::steady_clock;

std::int64_t to_ns(Clock::time_point t) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
}

std::string lease_value(const std::string& leader_id, std::uint64_t epoch) {
  tumble::v1::WorldLease lease;
  lease.set_leader_id(leader_id);
  lease.set_epoch(epoch);
  return lease.SerializeAsString();
}

// JetStream's refusal of a compare-and-set ("wrong last sequence", error
// 10071) in nats.c's last error of this thread.
bool refused_as_stale() {
  const char* text = nats_GetLastError(nullptr);
  return text != nullptr && std::string(text).find("wrong last sequence") != std::string::npos;
}

}  // namespace

std::string make_server_id() {
  std::random_device device;
  std::mt19937_64 generator((std::uint64_t{device()} << 32) ^ device());
  static constexpr char kHex[] = "0123456789abcdef";
  std::string id(16, '0');
  std::uint64_t bits = generator();
  for (char& c : id) {
    c = kHex[bits & 15];
    bits >>= 4;
  }
  return id;
}

WorldLease::WorldLease(NatsLink& link, WorldLeaseConfig config, spdlog::logger& log)
    : link_(link), config_(std::move(config)), log_(log), key_(config_.world + ".lease") {}

WorldLease::~WorldLease() {
  stop_renewing();
  kvStore_Destroy(bucket_);
  jsCtx_Destroy(jetstream_);
}

bool WorldLease::held() const { return to_ns(Clock::now()) < held_until_ns_.load(std::memory_order_acquire); }

std::string WorldLease::observed_leader() const {
  std::lock_guard lock(observed_mutex_);
  return observed_leader_;
}

void WorldLease::extend_from(Clock::time_point sent) {
  held_until_ns_.store(to_ns(sent + config_.timeout - config_.renew), std::memory_order_release);
}

WorldLease::Write WorldLease::write(const std::string& value, std::uint64_t last, std::uint64_t* revision) {
  const natsStatus status =
      last == 0 ? kvStore_Create(revision, bucket_, key_.c_str(), value.data(), static_cast<int>(value.size()))
                : kvStore_Update(revision, bucket_, key_.c_str(), value.data(), static_cast<int>(value.size()), last);
  if (status == NATS_OK) return Write::taken;
  return status == NATS_ERR && refused_as_stale() ? Write::refused : Write::unreachable;
}

sim::Status WorldLease::acquire() {
  // A context of its own, whose requests wait at most one renewal period:
  // a lease that waits longer than that for the cluster is as good as lost.
  while (bucket_ == nullptr) {
    if (link_.connected()) {
      jsOptions options;
      jsOptions_Init(&options);
      options.Wait = std::max<std::int64_t>(1, config_.renew.count());
      if (jetstream_ == nullptr && natsConnection_JetStream(&jetstream_, link_.connection(), &options) != NATS_OK) {
        return sim::Status::error("--nats-state: cannot make a JetStream context for the lease");
      }
      if (js_KeyValue(&bucket_, jetstream_, config_.bucket.c_str()) == NATS_OK) break;
      bucket_ = nullptr;
    }
    std::this_thread::sleep_for(config_.renew);
  }

  const Clock::time_point started = Clock::now();
  std::uint64_t seen_revision = 0;
  Clock::time_point seen_at = started;
  std::string said_leader = "-";
  for (;;) {
    kvEntry* entry = nullptr;
    const natsStatus status = kvStore_Get(&entry, bucket_, key_.c_str());
    const Clock::time_point now = Clock::now();
    std::uint64_t take_over = 0;  // the revision to write over; 0: create
    bool free = false;
    if (status == NATS_NOT_FOUND) {
      // Nobody ever held it (or it was purged): free, unless deferring.
      free = !config_.defer || now - started >= config_.timeout;
    } else if (status == NATS_OK) {
      const std::uint64_t revision = kvEntry_Revision(entry);
      tumble::v1::WorldLease lease;
      const bool parsed = lease.ParseFromArray(kvEntry_Value(entry), kvEntry_ValueLen(entry));
      if (revision != seen_revision) {
        seen_revision = revision;
        seen_at = now;
      }
      const std::string leader = parsed ? lease.leader_id() : std::string();
      {
        std::lock_guard lock(observed_mutex_);
        observed_leader_ = leader;
      }
      observed_epoch_.store(parsed && lease.epoch() != 0 ? lease.epoch() : revision, std::memory_order_relaxed);
      if (leader != said_leader) {
        if (!leader.empty())
          log_.info("standby for world {}: {} leads it (epoch {})", config_.world, leader, observed_epoch());
        said_leader = leader;
      }
      take_over = revision;
      free = leader.empty() || now - seen_at >= config_.timeout;
    }
    kvEntry_Destroy(entry);
    if (free) {
      const Clock::time_point sent = Clock::now();
      std::uint64_t revision = 0;
      if (write(lease_value(config_.id, 0), take_over, &revision) == Write::taken) {
        revision_ = revision;
        epoch_.store(revision, std::memory_order_relaxed);
        extend_from(sent);
        log_.info("took the lease of world {} (epoch {})", config_.world, revision);
        return {};
      }
    }
    std::this_thread::sleep_for(config_.renew);
  }
}

void WorldLease::start_renewing(std::function<void(const std::string& reason)> lost) {
  renewer_ = std::thread([this, lost = std::move(lost)] { renew_loop(lost); });
}

void WorldLease::renew_loop(const std::function<void(const std::string&)>& lost) {
  const std::string value = lease_value(config_.id, epoch());
  Clock::time_point next = Clock::now() + config_.renew;
  std::unique_lock lock(stop_mutex_);
  for (;;) {
    if (stop_wakeup_.wait_until(lock, next, [this] { return stopping_; })) return;
    lock.unlock();
    const Clock::time_point sent = Clock::now();
    next = sent + config_.renew;
    std::uint64_t revision = 0;
    const Write result = write(value, revision_, &revision);
    if (result == Write::taken) {
      revision_ = revision;
      extend_from(sent);
    } else if (result == Write::refused) {
      held_until_ns_.store(0, std::memory_order_release);
      lost("another server took the lease of world " + config_.world);
      return;
    } else if (!held()) {
      lost("no renewal of the lease of world " + config_.world + " was taken for " +
           std::to_string((config_.timeout - config_.renew).count()) + " ms");
      return;
    }
    lock.lock();
  }
}

void WorldLease::stop_renewing() {
  {
    std::lock_guard lock(stop_mutex_);
    stopping_ = true;
  }
  stop_wakeup_.notify_all();
  if (renewer_.joinable()) renewer_.join();
}

void WorldLease::release() {
  stop_renewing();
  if (!held()) return;
  held_until_ns_.store(0, std::memory_order_release);
  std::uint64_t revision = 0;
  if (write(lease_value("", epoch()), revision_, &revision) == Write::taken) {
    log_.info("released the lease of world {}", config_.world);
  }
}

}  // namespace tumble::nats
