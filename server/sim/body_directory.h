// The names and descriptions of a world's bodies, by id. The simulation
// owns one and keeps it in step with its world; other threads reach it only
// through Simulation::resolve. Not thread-safe by itself.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <unordered_map>

#include "tumble/physics/body.h"
#include "tumble/v1/protocol.pb.h"

namespace tumble::sim {

// What a client is told about a body besides its state.
struct BodyEntry {
  std::string name;         // may be empty
  tumble::v1::Shape shape;  // as it was specified
  double mass = 0;          // kg
};

class BodyDirectory {
 public:
  void add(physics::BodyId id, BodyEntry entry);
  void remove(physics::BodyId id);

  // nullptr when the id is unknown.
  const BodyEntry* find(physics::BodyId id) const;

  // kInvalidBodyId when no body has that name.
  physics::BodyId id_of(const std::string& name) const;

  // Resolves a reference by id or by name; kInvalidBodyId when unknown.
  physics::BodyId resolve(const tumble::v1::BodyRef& ref) const;

  // The entries by ascending id, for a reader that pages through them.
  const std::map<physics::BodyId, BodyEntry>& entries() const { return entries_; }

  // "body 'crate'" or "body 7", for messages (the name escaped and bounded
  // by log_text).
  static std::string describe(const tumble::v1::BodyRef& ref);

  // The name of `id`, or "" for unnamed or unknown bodies.
  const std::string& name_of(physics::BodyId id) const;

 private:
  std::map<physics::BodyId, BodyEntry> entries_;  // ordered, so that ListBodies pages by id
  std::unordered_map<std::string, physics::BodyId> ids_by_name_;
};

}  // namespace tumble::sim
