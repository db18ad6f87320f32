#include "sim/body_directory.h"

#include "sim/log_text.h"

namespace tumble::sim {

void BodyDirectory::add(physics::BodyId id, BodyEntry entry) {
  if (!entry.name.empty()) ids_by_name_[entry.name] = id;
  entries_[id] = std::move(entry);
}

void BodyDirectory::remove(physics::BodyId id) {
  const auto it = entries_.find(id);
  if (it == entries_.end()) return;
  if (!it->second.name.empty()) ids_by_name_.erase(it->second.name);
  entries_.erase(it);
}

const BodyEntry* BodyDirectory::find(physics::BodyId id) const {
  const auto it = entries_.find(id);
  return it == entries_.end() ? nullptr : &it->second;
}

physics::BodyId BodyDirectory::id_of(const std::string& name) const {
  const auto it = ids_by_name_.find(name);
  return it == ids_by_name_.end() ? physics::kInvalidBodyId : it->second;
}

physics::BodyId BodyDirectory::resolve(const tumble::v1::BodyRef& ref) const {
  switch (ref.ref_case()) {
    case tumble::v1::BodyRef::kId:
      return entries_.count(ref.id()) ? ref.id() : physics::kInvalidBodyId;
    case tumble::v1::BodyRef::kName:
      return id_of(ref.name());
    case tumble::v1::BodyRef::REF_NOT_SET:
      break;
  }
  return physics::kInvalidBodyId;
}

std::string BodyDirectory::describe(const tumble::v1::BodyRef& ref) {
  if (ref.ref_case() == tumble::v1::BodyRef::kName) return "body '" + log_text(ref.name()) + "'";
  return "body " + std::to_string(ref.id());
}

const std::string& BodyDirectory::name_of(physics::BodyId id) const {
  static const std::string kNoName;
  const BodyEntry* entry = find(id);
  return entry ? entry->name : kNoName;
}

}  // namespace tumble::sim
