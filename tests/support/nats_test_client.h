// A small NATS client for tests, on nats.c: publish, request (one reply or
// all replies until a quiet gap), and subscriptions that collect their
// messages for the test to wait on with a deadline. A subscription can be
// held (its handler blocks) to make a slow consumer that NATS drops
// messages for.
//
// Thread: the client and its subscriptions are used from the test's thread;
// messages arrive on nats.c's threads and are collected under a mutex.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <nats/nats.h>

namespace tumble::test {

struct NatsMessage {
  std::string subject;
  std::string data;
  std::string reply;  // the requester's inbox, for a request; else ""
};

// A subscription's messages, oldest first.
class NatsCollector {
 public:
  ~NatsCollector();
  NatsCollector(const NatsCollector&) = delete;
  NatsCollector& operator=(const NatsCollector&) = delete;

  // Waits until `done(messages)` holds or `timeout` passes; true when it held.
  bool wait(const std::function<bool(const std::vector<NatsMessage>&)>& done,
            std::chrono::milliseconds timeout = std::chrono::seconds(20));
  // Waits for at least `count` messages.
  bool wait_count(std::size_t count, std::chrono::milliseconds timeout = std::chrono::seconds(20));
  // A copy of what arrived so far.
  std::vector<NatsMessage> messages();
  // Takes what arrived so far, leaving none.
  std::vector<NatsMessage> take();

  // While held, the handler blocks on the first message it gets: nats.c
  // queues the rest up to the pending limits and drops the excess.
  void hold();
  void release();
  // Messages nats.c dropped for this subscription (slow consumer).
  std::int64_t dropped();

 private:
  friend class NatsTestClient;
  NatsCollector() = default;
  static void on_message(natsConnection* connection, natsSubscription* subscription, natsMsg* message, void* closure);
  static void on_complete(void* closure);

  natsSubscription* subscription_ = nullptr;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<NatsMessage> messages_;
  bool held_ = false;
  bool complete_ = false;  // nats.c will not call on_message again
};

class NatsTestClient {
 public:
  // Connects to `urls` (comma-separated; credentials may be in the URL),
  // trying for up to `timeout`. Check connected().
  explicit NatsTestClient(const std::string& urls, std::chrono::milliseconds timeout = std::chrono::seconds(10));
  ~NatsTestClient();
  NatsTestClient(const NatsTestClient&) = delete;
  NatsTestClient& operator=(const NatsTestClient&) = delete;

  bool connected() const { return connection_ != nullptr; }
  // Why the last call failed (nats.c's text), or "", and its status
  // (NATS_NO_RESPONDERS: nothing subscribes to a request's subject).
  const std::string& error() const { return error_; }
  natsStatus last_status() const { return last_status_; }

  natsStatus publish(const std::string& subject, const std::string& data);
  // Flushes and waits for the server's answer: what was published before has reached it.
  natsStatus flush(std::chrono::milliseconds timeout = std::chrono::seconds(5));

  // The first reply to a request, or nullopt (see error()).
  std::optional<std::string> request(const std::string& subject, const std::string& data,
                                     std::chrono::milliseconds timeout = std::chrono::seconds(5));
  // Every reply to one request, until none came for `quiet` or `timeout` passed.
  std::vector<std::string> request_many(const std::string& subject, const std::string& data,
                                        std::chrono::milliseconds quiet = std::chrono::milliseconds(250),
                                        std::chrono::milliseconds timeout = std::chrono::seconds(5));

  // Subscribes and collects; pending limits (messages, bytes) when given. Null on failure.
  std::unique_ptr<NatsCollector> subscribe(const std::string& subject, int pending_messages = 0, int pending_bytes = 0);

  // Publishes on `subject` until a message comes back on `collector`, which
  // was subscribed on another connection: interest has crossed the cluster.
  bool wait_for_interest(const std::string& subject, NatsCollector& collector,
                         std::chrono::milliseconds timeout = std::chrono::seconds(20));

  // A JetStream key-value bucket's value for `key` and its revision; nullopt
  // when the bucket or the key is missing (see error()).
  struct KvValue {
    std::string data;
    std::uint64_t revision = 0;
  };
  std::optional<KvValue> kv_get(const std::string& bucket, const std::string& key);
  // Puts `data` under `key`; false on failure (see error()).
  bool kv_put(const std::string& bucket, const std::string& key, const std::string& data);
  // The replicas of the bucket's stream (KV_<bucket>) the cluster reports
  // current, the leader included; 0 when it cannot be read.
  int kv_current_replicas(const std::string& bucket);

  natsConnection* connection() { return connection_; }

 private:
  void note(natsStatus status);

  natsConnection* connection_ = nullptr;
  std::string error_;
  natsStatus last_status_ = NATS_OK;
};

}  // namespace tumble::test
