// The names of a world's joints and the bodies each joins, by id: what the
// simulation needs of a joint after the world has let it go (a broken
// joint's event) and to resolve a JointRef. Kept in step with the world by
// the simulation, on the sim thread only. Not thread-safe by itself.
#pragma once

#include <map>
#include <string>
#include <unordered_map>

#include "tumble/physics/joint.h"
#include "tumble/v1/protocol.pb.h"

namespace tumble::sim {

struct JointEntry {
  std::string name;  // may be empty
  physics::BodyId body_a = physics::kWorldBodyId;
  physics::BodyId body_b = physics::kInvalidBodyId;
};

class JointDirectory {
 public:
  void add(physics::JointId id, JointEntry entry);
  void remove(physics::JointId id);

  // nullptr when the id is unknown.
  const JointEntry* find(physics::JointId id) const;

  // kInvalidJointId when no joint has that name.
  physics::JointId id_of(const std::string& name) const;

  // Resolves a reference by id or by name; kInvalidJointId when unknown.
  physics::JointId resolve(const tumble::v1::JointRef& ref) const;

  // The entries by ascending id, for a reader that pages through them.
  const std::map<physics::JointId, JointEntry>& entries() const { return entries_; }

  // "joint 'hinge'" or "joint 7", for messages (the name escaped and
  // bounded by log_text).
  static std::string describe(const tumble::v1::JointRef& ref);

 private:
  std::map<physics::JointId, JointEntry> entries_;  // ordered, so that ListJoints pages by id
  std::unordered_map<std::string, physics::JointId> ids_by_name_;
};

}  // namespace tumble::sim
