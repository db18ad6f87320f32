// NatsStateStore: a world's checkpoints in a JetStream key-value bucket
// (tumbled --nats-state). One value per world, under the world's name; the
// value is the bytes of a state file (sim/state_file.h: magic, length,
// WorldState, CRC32C), so that a damaged or foreign value is refused as a
// damaged file is, never loaded as a different world.
//
// The bucket keeps one revision per key and is made, when missing, with the
// replicas asked for (0: three when the link knows of three servers or
// more, else one). A checkpoint larger than the NATS server's max payload
// cannot be one message and is refused with a reason: nats.c has no object
// store to put it in.
//
// Thread: open() and load() from tumbled's main thread before the world
// starts; put() from one thread at a time (the StateSaver's, then main's
// for the last checkpoint). The link outlives the store.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <string>

#include <nats/nats.h>
#include <spdlog/logger.h>

#include "nats/nats_link.h"
#include "sim/status.h"
#include "tumble/v1/state.pb.h"

namespace tumble::nats {

inline constexpr const char* kDefaultStateBucket = "tumble_worlds";

struct NatsStateStoreConfig {
  std::string bucket = kDefaultStateBucket;  // 1 to 64 of A-Z a-z 0-9 _ -
  std::string key;                           // the world's name
  int replicas = 0;                          // 1 to 5; 0: by the cluster's size
  // How long open() waits for the link and for JetStream to answer (a
  // cluster still electing its leaders) before it gives up.
  std::chrono::milliseconds wait = std::chrono::seconds(30);
};

// The world's checkpoint as load() found it.
struct StoredState {
  bool found = false;  // false: the bucket has no value for the world
  tumble::v1::WorldState state;
  std::uint64_t revision = 0;  // the value's revision in the bucket
};

class NatsStateStore {
 public:
  NatsStateStore(NatsLink& link, NatsStateStoreConfig config, spdlog::logger& log);
  ~NatsStateStore();
  NatsStateStore(const NatsStateStore&) = delete;
  NatsStateStore& operator=(const NatsStateStore&) = delete;

  // Binds the bucket, making it when missing; retries until config.wait has
  // passed. Fails naming the bucket, with nats.c's reason; at once when the
  // server has no JetStream.
  sim::Status open();

  // Reads the world's checkpoint. A value that is not a state file of a
  // WorldState fails with a sentence naming the bucket and the key.
  sim::Status load(StoredState* out);

  // Writes `state` as the world's checkpoint and waits for the bucket's
  // acknowledgement. Fails when the value is over the max payload or the
  // bucket did not take it.
  sim::Status put(const tumble::v1::WorldState& state);

  // "bucket tumble_worlds, key demo", for log lines.
  std::string where() const;
  std::uint64_t last_revision() const { return last_revision_.load(std::memory_order_relaxed); }
  int replicas() const { return replicas_; }

 private:
  // One attempt; `retry` is set false when trying again cannot help.
  sim::Status bind(bool* retry);

  NatsLink& link_;
  NatsStateStoreConfig config_;
  spdlog::logger& log_;
  jsCtx* jetstream_ = nullptr;
  kvStore* bucket_ = nullptr;
  int replicas_ = 1;
  std::atomic<std::uint64_t> last_revision_{0};
};

}  // namespace tumble::nats
