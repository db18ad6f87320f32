#include "sim/joint_directory.h"

#include "sim/log_text.h"

namespace tumble::sim {

void JointDirectory::add(physics::JointId id, JointEntry entry) {
  if (!entry.name.empty()) ids_by_name_[entry.name] = id;
  entries_[id] = std::move(entry);
}

void JointDirectory::remove(physics::JointId id) {
  const auto it = entries_.find(id);
  if (it == entries_.end()) return;
  if (!it->second.name.empty()) ids_by_name_.erase(it->second.name);
  entries_.erase(it);
}

const JointEntry* JointDirectory::find(physics::JointId id) const {
  const auto it = entries_.find(id);
  return it == entries_.end() ? nullptr : &it->second;
}

physics::JointId JointDirectory::id_of(const std::string& name) const {
  const auto it = ids_by_name_.find(name);
  return it == ids_by_name_.end() ? physics::kInvalidJointId : it->second;
}

physics::JointId JointDirectory::resolve(const tumble::v1::JointRef& ref) const {
  switch (ref.ref_case()) {
    case tumble::v1::JointRef::kId:
      return entries_.count(ref.id()) ? ref.id() : physics::kInvalidJointId;
    case tumble::v1::JointRef::kName:
      return id_of(ref.name());
    case tumble::v1::JointRef::REF_NOT_SET:
      break;
  }
  return physics::kInvalidJointId;
}

std::string JointDirectory::describe(const tumble::v1::JointRef& ref) {
  if (ref.ref_case() == tumble::v1::JointRef::kName) return "joint '" + log_text(ref.name()) + "'";
  return "joint " + std::to_string(ref.id());
}

}  // namespace tumble::sim
