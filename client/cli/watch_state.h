// What `tumble watch` knows of each body besides its pose: its name and
// whether it sleeps. Filled from a BodyList, then kept current by the
// WorldEvents of the watch's subscription (spawned, removed, asleep, awake),
// applied in the order they arrive.
#pragma once

#include <cstdint>
#include <string>
#include <unordered_map>

#include "tumble/v1/protocol.pb.h"

namespace tumble::cli {

class WatchState {
 public:
  // Takes every body of `list`, replacing what was known.
  void load(const tumble::v1::BodyList& list);

  // Takes in one event; kinds that do not concern a body are ignored.
  void apply(const tumble::v1::WorldEvent& event);

  // The body's name; "" when unnamed or unknown.
  const std::string& name(std::uint32_t id) const;

  // Whether the body was asleep at the last news of it; false when unknown.
  bool asleep(std::uint32_t id) const;

 private:
  struct Body {
    std::string name;
    bool asleep = false;
  };
  std::unordered_map<std::uint32_t, Body> bodies_;
};

}  // namespace tumble::cli
