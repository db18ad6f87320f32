#include "nats/nats_state_store.h"

#include <thread>

#include "sim/state_file.h"

namespace tumble::nats {
namespace {

// How long one JetStream request waits for its answer.
constexpr std::int64_t kRequestWaitMs = 5000;

// Between attempts while the link or JetStream is not there yet.
constexpr auto kRetryPause = std::chrono::milliseconds(200);

// Three replicas on a cluster that can hold them, one on a lone server.
int replicas_for(std::size_t servers) { return servers >= 3 ? 3 : 1; }

}  // namespace

NatsStateStore::NatsStateStore(NatsLink& link, NatsStateStoreConfig config, spdlog::logger& log)
    : link_(link), config_(std::move(config)), log_(log) {}

NatsStateStore::~NatsStateStore() {
  kvStore_Destroy(bucket_);
  jsCtx_Destroy(jetstream_);
}

std::string NatsStateStore::where() const { return "bucket " + config_.bucket + ", key " + config_.key; }

sim::Status NatsStateStore::open() {
  const auto deadline = std::chrono::steady_clock::now() + config_.wait;
  sim::Status last = sim::Status::error("the NATS link did not come up");
  bool said_waiting = false;
  while (std::chrono::steady_clock::now() < deadline) {
    if (link_.connected()) {
      bool retry = true;
      last = bind(&retry);
      if (last.ok()) return last;
      if (!retry) return sim::Status::error("--nats-state: bucket " + config_.bucket + ": " + last.message());
    }
    if (!said_waiting) {
      log_.info("waiting for the JetStream bucket {} ({})", config_.bucket, last.message());
      said_waiting = true;
    }
    std::this_thread::sleep_for(kRetryPause);
  }
  return sim::Status::error("--nats-state: bucket " + config_.bucket + " not reachable within " +
                            std::to_string(config_.wait.count() / 1000) + " s: " + last.message());
}

sim::Status NatsStateStore::bind(bool* retry) {
  if (jetstream_ == nullptr) {
    jsOptions options;
    jsOptions_Init(&options);
    options.Wait = kRequestWaitMs;
    if (natsStatus status = natsConnection_JetStream(&jetstream_, link_.connection(), &options); status != NATS_OK) {
      return nats_failure("JetStream", status);
    }
  }
  natsStatus status = js_KeyValue(&bucket_, jetstream_, config_.bucket.c_str());
  if (status == NATS_OK) return {};
  if (status == NATS_NO_RESPONDERS) {
    // A server with JetStream answers its API even while electing leaders.
    *retry = false;
    return sim::Status::error("the NATS server has no JetStream (nats-server -js, or a jetstream block)");
  }
  if (status != NATS_NOT_FOUND) return nats_failure("binding the bucket", status);
  kvConfig config;
  kvConfig_Init(&config);
  config.Bucket = config_.bucket.c_str();
  config.Description = "tumble worlds' checkpoints, one per world";
  config.History = 1;
  config.StorageType = js_FileStorage;
  replicas_ = config_.replicas > 0 ? config_.replicas : replicas_for(link_.known_servers());
  config.Replicas = replicas_;
  status = js_CreateKeyValue(&bucket_, jetstream_, &config);
  if (status != NATS_OK)
    return nats_failure("making the bucket with " + std::to_string(replicas_) + " replica(s)", status);
  log_.info("made the JetStream bucket {} with {} replica(s)", config_.bucket, replicas_);
  return {};
}

sim::Status NatsStateStore::load(StoredState* out) {
  *out = StoredState{};
  kvEntry* entry = nullptr;
  const natsStatus status = kvStore_Get(&entry, bucket_, config_.key.c_str());
  if (status == NATS_NOT_FOUND) return {};
  if (status != NATS_OK) return nats_failure("--nats-state: reading " + where(), status);
  const std::string_view bytes(static_cast<const char*>(kvEntry_Value(entry)),
                               static_cast<std::size_t>(kvEntry_ValueLen(entry)));
  out->revision = kvEntry_Revision(entry);
  sim::StateFileFormat format{};
  const sim::Status parsed = sim::parse_state_file(bytes, &out->state, &format);
  kvEntry_Destroy(entry);
  if (!parsed.ok()) {
    return sim::Status::error("--nats-state: the value of " + where() + " (revision " + std::to_string(out->revision) +
                              ", " + std::to_string(bytes.size()) +
                              " bytes) is not a world's state: " + parsed.message());
  }
  out->found = true;
  return {};
}

sim::Status NatsStateStore::put(const tumble::v1::WorldState& state) {
  std::string bytes;
  if (!sim::encode_state_file(state, &bytes)) return sim::Status::error("the state cannot be encoded");
  const std::int64_t limit = link_.max_payload();
  if (static_cast<std::int64_t>(bytes.size()) > limit) {
    return sim::Status::error("the checkpoint is " + std::to_string(bytes.size()) +
                              " bytes, over the NATS server's max payload of " + std::to_string(limit) +
                              " bytes: not written to " + where());
  }
  std::uint64_t revision = 0;
  const natsStatus status =
      kvStore_Put(&revision, bucket_, config_.key.c_str(), bytes.data(), static_cast<int>(bytes.size()));
  if (status != NATS_OK) return nats_failure("writing " + where(), status);
  last_revision_.store(revision, std::memory_order_relaxed);
  return {};
}

}  // namespace tumble::nats
