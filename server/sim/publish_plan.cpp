#include "sim/publish_plan.h"

#include <algorithm>
#include <iterator>
#include <utility>

namespace tumble::sim {
namespace {

// Adds the sorted, unique `ids` to the sorted, unique `into`: a merge, not
// a sort, since the filters are sorted already (bench/README.md has what the
// sort cost on a fan-out tick). `scratch` keeps its capacity.
void merge_into(std::vector<physics::BodyId>& into, const std::vector<physics::BodyId>& ids,
                std::vector<physics::BodyId>& scratch) {
  if (into.empty()) {
    into.assign(ids.begin(), ids.end());
    return;
  }
  scratch.clear();
  std::set_union(into.begin(), into.end(), ids.begin(), ids.end(), std::back_inserter(scratch));
  into.swap(scratch);
}

}  // namespace

void PublishPlan::set_interests(std::vector<PublishInterest> interests, std::size_t early_bodies) {
  interests_ = std::move(interests);
  early_bodies_ = early_bodies;
}

PublishPlan::Due PublishPlan::plan(std::uint64_t tick, std::size_t world_bodies, bool snapshot_requested) {
  bool every_body = snapshot_requested;
  due_.clear();
  early_.clear();
  bool large = false;
  for (std::size_t i = 0; i < interests_.size(); ++i) {
    const PublishInterest& interest = interests_[i];
    if (interest.period_ticks == 0 || tick % interest.period_ticks != 0) continue;
    if (interest.all_bodies) {
      every_body = true;
      continue;
    }
    due_.push_back(i);
    if (goes_early(interest.all_bodies, interest.bodies.size(), early_bodies_)) {
      merge_into(early_, interest.bodies, merge_scratch_);
    } else {
      large = true;
      // The union holds at least these: most of the world on its own.
      if (copies_every_body(interest.bodies.size(), world_bodies)) every_body = true;
    }
  }
  if (!large && !every_body) early_.clear();  // nothing large to go before: early_ stays empty
  if (every_body) return Due::every_body;
  return due_.empty() ? Due::nothing : Due::wanted_bodies;
}

const std::vector<physics::BodyId>& PublishPlan::collect_wanted() {
  wanted_.clear();
  for (const std::size_t i : due_) merge_into(wanted_, interests_[i].bodies, merge_scratch_);
  return wanted_;
}

bool PublishPlan::copies_every_body(std::size_t wanted, std::size_t world_bodies) const {
  return wanted > early_bodies_ && 2 * wanted >= world_bodies;
}

}  // namespace tumble::sim
