// NatsLink: tumbled's connection to NATS, through nats.c. It connects to
// the first reachable URL of its list (user and password, or a token, in
// the URL; a .creds file; TLS for tls:// URLs), and nats.c reconnects on
// its own, with backoff and without a limit on attempts, to any server of
// the list or of the cluster. A server that is not reachable at start is
// not an error: the link is down, is logged as such, and comes up when the
// server does. A server that answers and refuses the credentials is one. While it is down, what is published is not
// buffered beyond a bound (the reconnect buffer): the caller counts what it does not send.
//
// Counters (messages and bytes out, reconnects, requests answered, frames
// dropped) are atomics read by GetStats on the sim thread.
//
// Thread: start() and subscribe() on the thread that builds tumbled,
// before the sim starts; publish() and the counters from any thread
// (nats.c locks its connection). Handlers run on nats.c's threads.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include <nats/nats.h>
#include <spdlog/logger.h>

#include "sim/status.h"
#include "tumble/v1/protocol.pb.h"

namespace tumble::nats {

struct NatsLinkConfig {
  std::vector<std::string> urls;  // nats:// or tls://, tried in order at start
  std::string creds_file;         // a .creds file (JWT and NKey seed); empty: none
  std::string name = "tumbled";   // the connection's name, as the server lists it
  // Bytes nats.c keeps of what is published while reconnecting; beyond,
  // publish() reports the link down.
  int reconnect_buffer_bytes = 8 << 20;
};

// A message a subscription received.
struct NatsRequest {
  std::string subject;
  std::string reply;  // the requester's inbox; empty for a plain publish
  std::string data;
};

// Waits, as it goes out of scope, for nats.c's own threads to finish (up to
// 2 s), so that none of them still runs (in OpenSSL, say) while the process
// exits. One per process, made in main before the NatsLink so that it
// outlives it.
// `what`: nats.c's status, and its own detail of this thread's last error
// when it says more (e.g. which certificate check failed).
sim::Status nats_failure(const std::string& what, natsStatus status);

class NatsLibraryScope {
 public:
  NatsLibraryScope() = default;
  ~NatsLibraryScope();
  NatsLibraryScope(const NatsLibraryScope&) = delete;
  NatsLibraryScope& operator=(const NatsLibraryScope&) = delete;
};

class NatsLink {
 public:
  NatsLink(NatsLinkConfig config, spdlog::logger& log);
  ~NatsLink();  // close()
  NatsLink(const NatsLink&) = delete;
  NatsLink& operator=(const NatsLink&) = delete;

  // Starts connecting. Fails when the options cannot be used (a creds file
  // nats.c refuses, a URL it cannot parse) or the first server reached
  // refuses the credentials; an unreachable server is retried in the
  // background.
  sim::Status start();

  // Subscribes `subject` (in `queue_group` when not empty); `handler` runs
  // on a nats.c thread for each message. Made before the connection is up,
  // it takes effect when it is.
  sim::Status subscribe(const std::string& subject, const std::string& queue_group,
                        std::function<void(NatsRequest)> handler);

  // Closes the connection and waits (at most 5 s) until nats.c has said
  // its last word about it and every handler has returned: after it no
  // handler runs, so what the handlers reach may go. Publishing after it
  // reports the link down. Idempotent; from the owner's thread.
  void close();

  enum class Sent { ok, down, too_large, failed };
  // Publishes `data` on `subject`; counted in messages_out and bytes_out when sent.
  Sent publish(const std::string& subject, std::string_view data);

  bool connected() const;
  // The servers the link knows: those given, and those the cluster told
  // it of once connected.
  std::size_t known_servers() const;
  // The connection, for a JetStream context on it (nats/nats_state_store.h);
  // null before start(). Owned by the link.
  natsConnection* connection() const { return connection_; }
  // The server's max payload (bytes) once connected; else the NATS default, 1 MiB.
  std::int64_t max_payload() const;

  void count_request() { requests_in_.fetch_add(1, std::memory_order_relaxed); }
  void count_dropped_frame() { frames_dropped_.fetch_add(1, std::memory_order_relaxed); }

  // The link's figures for Stats.nats; `world` is this tumbled's world.
  void fill(const std::string& world, tumble::v1::NatsLink* out) const;

  // The URL of the server connected to, without credentials; "" when down.
  std::string server_url() const;

 private:
  static void on_connected(natsConnection* connection, void* closure);
  static void on_disconnected(natsConnection* connection, void* closure);
  static void on_reconnected(natsConnection* connection, void* closure);
  static void on_closed(natsConnection* connection, void* closure);
  static void on_error(natsConnection* connection, natsSubscription* subscription, natsStatus status, void* closure);
  static void on_message(natsConnection* connection, natsSubscription* subscription, natsMsg* message, void* closure);
  static void on_subscription_complete(void* closure);
  // nats.c's last error on the connection, for a log line.
  std::string last_error() const;

  struct Subscription {
    NatsLink* link = nullptr;
    std::function<void(NatsRequest)> handler;
    natsSubscription* handle = nullptr;
  };

  NatsLinkConfig config_;
  spdlog::logger& log_;
  natsOptions* options_ = nullptr;
  natsConnection* connection_ = nullptr;
  std::vector<std::unique_ptr<Subscription>> subscriptions_;
  std::atomic<bool> up_{false};
  std::atomic<bool> closing_{false};  // close() has begun closing the connection
  // Set by on_closed, nats.c's last call about the connection, and by
  // on_subscription_complete, its last call about a subscription (no
  // handler runs after it).
  std::mutex closed_mutex_;
  std::condition_variable closed_wakeup_;
  bool closed_ = false;
  std::size_t subscriptions_completed_ = 0;
  std::atomic<std::uint64_t> messages_out_{0};
  std::atomic<std::uint64_t> bytes_out_{0};
  std::atomic<std::uint64_t> reconnects_{0};
  std::atomic<std::uint64_t> requests_in_{0};
  std::atomic<std::uint64_t> frames_dropped_{0};
};

// `url` without a user, password or token ("nats://user:pw@h:4222" -> "nats://h:4222").
std::string without_credentials(std::string_view url);

}  // namespace tumble::nats
