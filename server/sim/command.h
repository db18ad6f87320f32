// A client request on its way to the sim thread, and the queue that takes it
// there.
#pragma once

#include <functional>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "tumble/physics/body.h"
#include "tumble/v1/protocol.pb.h"

namespace tumble::sim {

// Receives the reply to one command. Called once, on the sim thread, or on
// the thread that submitted the command when Simulation::submit refuses it
// at once; never if the simulation stops first (a Step under way). It must
// not block (the network layer posts the reply to its own thread).
using ReplyFn = std::function<void(tumble::v1::ServerMessage)>;

// A checked request (see check_request) and where its reply goes.
struct Command {
  tumble::v1::ClientMessage message;
  ReplyFn reply;
  // SpawnBody: the body, converted from its spec by Simulation::submit on
  // the submitting thread, so a large convex hull is not built on the sim
  // thread. Empty for other requests.
  std::shared_ptr<const physics::BodyDesc> body_desc = nullptr;
};

// Many producers (I/O threads), one consumer (the sim thread). The sim takes
// everything queued at the start of a tick, so commands take effect in the
// order they were pushed.
class CommandQueue {
 public:
  void push(Command command) {
    std::lock_guard lock(mutex_);
    pending_.push_back(std::move(command));
  }

  // Swaps the queued commands into `out` (cleared first), keeping both
  // vectors' capacity so a steady stream of commands does not allocate.
  void drain(std::vector<Command>& out) {
    out.clear();
    std::lock_guard lock(mutex_);
    pending_.swap(out);
  }

 private:
  std::mutex mutex_;
  std::vector<Command> pending_;
};

}  // namespace tumble::sim
