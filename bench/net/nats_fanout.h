// NatsFanout: many readers of one NATS pose stream, as clients on other
// machines would read it, counting what each receives.
//
// S subscriptions to the stream's subject share C nats.c connections
// (C <= S; 1,000 connections would be 1,000 reader threads and sockets on
// the server's own machine), connection j to node j % N of the cluster, so
// subscription i reads through node (i % C) % N. NATS delivers every
// message once per subscription, also to subscriptions on one connection:
// the bytes and the decoding are those of S readers. The subscriptions'
// callbacks run on a shared pool of T threads (nats.c's global message
// delivery); each subscription's messages are handled in order by one of
// them.
//
// Each subscription parses every message as a ServerMessage, counts the
// frames of the measured ticks (MeasuredTicks) whenever they arrive, checks that
// the frames' sequence numbers follow each other (counting the gaps and the
// frames they skipped), passes them through a SequenceGate and applies
// those it lets through to a PoseStream without converting the values to
// floats (the load generator shares the machine with the server). It does
// not ask for key frames after a gap: it waits for the stream's next one,
// so the server's work is the same whatever the readers lose.
//
// Thread: construct it on a thread of the priority its readers should
// have: the nats.c threads (a reader per connection, the delivery pool) are
// created by the constructing thread and inherit its nice value and
// scheduling policy (thread_priority.h). After that, use it from one thread
// at a time.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "measured_window.h"

namespace tumble::bench {

struct NatsFanoutOptions {
  std::vector<std::string> node_urls;  // nats://HOST:PORT of each node
  std::string subject;                 // the pose stream's subject
  unsigned subscriptions = 1;          // S
  unsigned connections = 1;            // C, at most S
  unsigned delivery_threads = 4;       // T
  // nats.c's limit on the messages one subscription has waiting; past it
  // nats.c drops the ones that come (a slow consumer on the client's side).
  // 64 frames: about a second of a 60 Hz stream, so that a reader that
  // cannot keep up loses frames rather than reading ever older ones.
  int pending_messages = 64;
  int pending_bytes = 8 << 20;
};

// What one subscription counted of the frames of the measured ticks.
struct StreamTally {
  std::uint64_t frames = 0;      // received
  std::uint64_t bytes = 0;       // their payloads (ServerMessage bytes)
  std::uint64_t wire_bytes = 0;  // the same with NATS's MSG line and CRLFs, as they crossed the socket
  std::uint64_t shown = 0;       // let through by the SequenceGate and applied
  std::uint64_t body_slots = 0;  // bodies the applied frames stood for
  std::uint64_t gaps = 0;        // frames whose sequence did not follow the previous one's
  std::uint64_t missed = 0;      // sequence numbers those gaps skipped
  std::uint64_t errors = 0;      // a message that did not parse, or a frame that did not apply
  // Frames of any tick handled inside the wall-clock window: what the
  // reader got through in that time, late ones included.
  std::uint64_t handled_in_window = 0;
};

// What nats.c reported over the run, every connection together.
struct NatsClientEvents {
  std::uint64_t slow_consumer = 0;  // nats.c errors: a subscription's pending limit was reached
  std::uint64_t dropped = 0;        // messages nats.c dropped for those limits
  std::uint64_t disconnects = 0;    // connections lost (e.g. closed by a server as a slow consumer)
  std::uint64_t reconnects = 0;
};

class NatsFanout {
 public:
  // Connects and subscribes. Check error(): empty when every connection and
  // subscription is up.
  // `ticks` says which frames count, `wall` when a handled frame counts
  // as handled_in_window; both outlive it.
  NatsFanout(const NatsFanoutOptions& options, const MeasuredTicks& ticks, const MeasuredWindow& wall);
  // Closes whatever close() has not.
  ~NatsFanout();
  NatsFanout(const NatsFanout&) = delete;
  NatsFanout& operator=(const NatsFanout&) = delete;

  const std::string& error() const;

  // Subscriptions that have applied a whole frame (a key frame) by now.
  unsigned ready() const;

  // Unsubscribes and closes every connection, and waits until no callback
  // runs any more; then the tallies and events are final.
  void close();

  // One per subscription, in order; after close().
  std::vector<StreamTally> tallies() const;
  // Up to close() (which disconnects every connection itself); after close().
  NatsClientEvents events() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace tumble::bench
