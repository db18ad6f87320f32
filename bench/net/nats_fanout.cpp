#include "nats_fanout.h"

#include <nats/nats.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>

#include "tumble/v1/protocol.pb.h"
#include "tumble_client/pose_stream.h"
#include "tumble_client/sequence_gate.h"

namespace tumble::bench {
namespace {

std::size_t digits(std::uint64_t n) {
  std::size_t count = 1;
  for (; n >= 10; n /= 10) ++count;
  return count;
}

// The counters nats.c's callbacks bump, every connection together.
struct EventCounters {
  std::atomic<std::uint64_t> slow_consumer{0};
  std::atomic<std::uint64_t> disconnects{0};
  std::atomic<std::uint64_t> reconnects{0};
};

// Subscriptions whose callbacks have ended for good, waited for by close().
struct Completions {
  std::mutex mutex;
  std::condition_variable changed;
  std::size_t done = 0;
};

// One subscription's reader: what it holds of the stream and what it
// counted. Its callbacks run one at a time, on one delivery thread.
struct Reader {
  const MeasuredTicks* ticks = nullptr;
  const MeasuredWindow* wall = nullptr;
  std::atomic<unsigned>* ready = nullptr;
  Completions* completions = nullptr;
  natsSubscription* subscription = nullptr;
  std::size_t wire_overhead = 0;  // "MSG <subject> <sid> " and the two CRLFs, without the size's digits
  tumble::v1::ServerMessage message;
  client::SequenceGate gate;
  client::PoseStream stream;
  std::uint64_t last_sequence = 0;
  bool shown_whole = false;
  StreamTally tally;
};

// A frame for one subscription.
void on_message(natsConnection*, natsSubscription*, natsMsg* msg, void* closure) {
  Reader& reader = *static_cast<Reader*>(closure);
  const int length = natsMsg_GetDataLength(msg);
  const bool parsed = reader.message.ParseFromArray(natsMsg_GetData(msg), length) && reader.message.has_pose_frame();
  natsMsg_Destroy(msg);
  StreamTally& tally = reader.tally;
  if (!parsed) {
    ++tally.errors;
    return;
  }
  const tumble::v1::PoseFrame& frame = reader.message.pose_frame();
  const std::uint64_t sequence = frame.sequence();
  const bool counted = reader.ticks->contains(frame.tick());
  if (reader.wall->contains(std::chrono::steady_clock::now())) ++tally.handled_in_window;
  if (counted) {
    ++tally.frames;
    tally.bytes += static_cast<std::uint64_t>(length);
    tally.wire_bytes +=
        static_cast<std::uint64_t>(length) + reader.wire_overhead + digits(static_cast<std::uint64_t>(length));
    if (reader.last_sequence != 0 && sequence != reader.last_sequence + 1) {
      ++tally.gaps;
      if (sequence > reader.last_sequence) tally.missed += sequence - reader.last_sequence - 1;
    }
  }
  reader.last_sequence = sequence;
  if (!reader.gate.published(frame).show) return;
  auto applied = reader.stream.apply(frame);
  if (!applied) {
    ++tally.errors;
    return;
  }
  if (!reader.shown_whole) {
    reader.shown_whole = true;
    ++*reader.ready;
  }
  if (counted) {
    ++tally.shown;
    tally.body_slots += *applied;
  }
}

void on_complete(void* closure) {
  Completions& completions = *static_cast<Reader*>(closure)->completions;
  {
    const std::lock_guard lock(completions.mutex);
    ++completions.done;
  }
  completions.changed.notify_all();
}

void on_error(natsConnection*, natsSubscription*, natsStatus status, void* closure) {
  if (status == NATS_SLOW_CONSUMER) ++static_cast<EventCounters*>(closure)->slow_consumer;
}

void on_disconnected(natsConnection*, void* closure) { ++static_cast<EventCounters*>(closure)->disconnects; }
void on_reconnected(natsConnection*, void* closure) { ++static_cast<EventCounters*>(closure)->reconnects; }

std::string nats_error(const std::string& what, natsStatus status) {
  const char* text = nats_GetLastError(nullptr);
  return what + ": " + (text != nullptr && *text != '\0' ? text : natsStatus_GetText(status));
}

}  // namespace

struct NatsFanout::State {
  std::string error;
  std::atomic<unsigned> ready{0};
  EventCounters events;
  Completions completions;
  std::vector<natsConnection*> connections;
  std::vector<std::unique_ptr<Reader>> readers;
  NatsClientEvents final_events;  // as they stood when close() began: closing disconnects every connection
  bool closed = false;
};

NatsFanout::NatsFanout(const NatsFanoutOptions& options, const MeasuredTicks& ticks, const MeasuredWindow& wall)
    : state_(std::make_unique<State>()) {
  State& state = *state_;
  const unsigned connections = std::max(1u, std::min(options.connections, options.subscriptions));
  for (unsigned j = 0; j < connections && state.error.empty(); ++j) {
    natsOptions* nats_options = nullptr;
    natsStatus status = natsOptions_Create(&nats_options);
    if (status != NATS_OK) {
      state.error = nats_error("natsOptions_Create", status);
      break;
    }
    // The pool's threads start with the first subscriptions, on this thread.
    if (j == 0) nats_SetMessageDeliveryPoolSize(static_cast<int>(std::max(1u, options.delivery_threads)));
    const std::string& url = options.node_urls[j % options.node_urls.size()];
    const std::string name = "nats_load-" + std::to_string(j);
    natsOptions_SetURL(nats_options, url.c_str());
    natsOptions_SetName(nats_options, name.c_str());
    natsOptions_UseGlobalMessageDelivery(nats_options, true);
    natsOptions_SetErrorHandler(nats_options, on_error, &state.events);
    natsOptions_SetDisconnectedCB(nats_options, on_disconnected, &state.events);
    natsOptions_SetReconnectedCB(nats_options, on_reconnected, &state.events);
    natsOptions_SetMaxReconnect(nats_options, -1);  // keep reading for the whole run
    natsConnection* connection = nullptr;
    status = natsConnection_Connect(&connection, nats_options);
    natsOptions_Destroy(nats_options);
    if (status != NATS_OK) {
      state.error = nats_error("connect to " + url, status);
      break;
    }
    state.connections.push_back(connection);
  }
  for (unsigned i = 0; i < options.subscriptions && state.error.empty(); ++i) {
    auto reader = std::make_unique<Reader>();
    reader->ticks = &ticks;
    reader->wall = &wall;
    reader->ready = &state.ready;
    reader->completions = &state.completions;
    natsConnection* connection = state.connections[i % state.connections.size()];
    natsStatus status =
        natsConnection_Subscribe(&reader->subscription, connection, options.subject.c_str(), on_message, reader.get());
    if (status == NATS_OK) status = natsSubscription_SetOnCompleteCB(reader->subscription, on_complete, reader.get());
    if (status == NATS_OK) {
      status = natsSubscription_SetPendingLimits(reader->subscription, options.pending_messages, options.pending_bytes);
    }
    if (status != NATS_OK) {
      state.error = nats_error("subscribe to " + options.subject, status);
      if (reader->subscription != nullptr) state.readers.push_back(std::move(reader));
      break;
    }
    const std::uint64_t sid = static_cast<std::uint64_t>(natsSubscription_GetID(reader->subscription));
    reader->wire_overhead = 4 + options.subject.size() + 1 + digits(sid) + 1 + 2 + 2;
    state.readers.push_back(std::move(reader));
  }
  // The subscriptions reach the servers (and through their routes the
  // node tumbled publishes to) before the caller counts on them.
  for (natsConnection* connection : state.connections) {
    if (state.error.empty()) {
      if (const natsStatus status = natsConnection_FlushTimeout(connection, 10000); status != NATS_OK) {
        state.error = nats_error("flush", status);
      }
    }
  }
}

NatsFanout::~NatsFanout() { close(); }

const std::string& NatsFanout::error() const { return state_->error; }

unsigned NatsFanout::ready() const { return state_->ready.load(); }

void NatsFanout::close() {
  State& state = *state_;
  if (state.closed) return;
  state.closed = true;
  state.final_events = NatsClientEvents{state.events.slow_consumer.load(), 0, state.events.disconnects.load(),
                                        state.events.reconnects.load()};
  for (const auto& reader : state.readers) {
    int64_t dropped = 0;
    if (natsSubscription_GetDropped(reader->subscription, &dropped) == NATS_OK && dropped > 0) {
      state.final_events.dropped += static_cast<std::uint64_t>(dropped);
    }
    natsSubscription_Unsubscribe(reader->subscription);
  }
  {
    // Each subscription's callback has returned for the last time (or 10 s passed).
    std::unique_lock lock(state.completions.mutex);
    state.completions.changed.wait_for(lock, std::chrono::seconds(10),
                                       [&] { return state.completions.done >= state.readers.size(); });
  }
  for (const auto& reader : state.readers) natsSubscription_Destroy(reader->subscription);
  for (natsConnection* connection : state.connections) {
    natsConnection_Close(connection);
    natsConnection_Destroy(connection);
  }
  state.connections.clear();
}

std::vector<StreamTally> NatsFanout::tallies() const {
  std::vector<StreamTally> out;
  out.reserve(state_->readers.size());
  for (const auto& reader : state_->readers) out.push_back(reader->tally);
  return out;
}

NatsClientEvents NatsFanout::events() const { return state_->final_events; }

}  // namespace tumble::bench
