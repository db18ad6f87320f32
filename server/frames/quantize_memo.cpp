#include "frames/quantize_memo.h"

#include <algorithm>
#include <cstring>

namespace tumble::frames {

namespace {

// Whether n doubles are the same to the bit (inlined with n constant, the
// compare is a few vector instructions).
inline bool same_bits(const double* a, const double* b, std::size_t n) {
  return std::memcmp(a, b, n * sizeof(double)) == 0;
}

}  // namespace

std::vector<wire::QuantizedBody> QuantizeMemo::quantize(const sim::Snapshot& snapshot, bool all_bodies,
                                                        const std::vector<physics::BodyId>& filter, bool velocities) {
  const std::size_t per_body = values_per_body(velocities);
  next_ids_.clear();
  next_values_.clear();
  next_records_.clear();
  quantized_last_ = 0;
  std::size_t last = 0;    // the next record of the last call to match
  std::size_t wanted = 0;  // the first id of `filter` not below the ids read so far
  for (std::size_t i = 0; i < snapshot.body_count(); ++i) {
    const physics::BodyId id = snapshot.ids[i];
    if (!all_bodies) {
      // Snapshots mostly list ids in ascending order: walk the filter
      // alongside, and search it only where the order turns back.
      if (wanted > 0 && filter[wanted - 1] >= id) {
        wanted = static_cast<std::size_t>(std::lower_bound(filter.begin(), filter.end(), id) - filter.begin());
      }
      while (wanted < filter.size() && filter[wanted] < id) ++wanted;
      if (wanted == filter.size() || filter[wanted] != id) continue;
      ++wanted;
    }
    const double* position = &snapshot.positions[3 * i];
    const double* orientation = &snapshot.orientations[4 * i];
    const double* linear = velocities ? &snapshot.linear_velocities[3 * i] : nullptr;
    const double* angular = velocities ? &snapshot.angular_velocities[3 * i] : nullptr;
    // One body of the last call missing here (it left): step over it.
    if (last + 1 < ids_.size() && ids_[last] != id && ids_[last + 1] == id) ++last;
    const bool matched = last < ids_.size() && ids_[last] == id;
    const double* kept = matched ? &values_[per_body * last] : nullptr;
    if (matched && same_bits(position, kept, 3) && same_bits(orientation, kept + 3, 4) &&
        (!velocities || (same_bits(linear, kept + 7, 3) && same_bits(angular, kept + 10, 3)))) {
      next_records_.push_back(records_[last]);
    } else {
      next_records_.push_back(wire::quantize_body(id, position, orientation, linear, angular));
      ++quantized_last_;
    }
    if (matched) ++last;
    next_ids_.push_back(id);
    next_values_.insert(next_values_.end(), position, position + 3);
    next_values_.insert(next_values_.end(), orientation, orientation + 4);
    if (velocities) {
      next_values_.insert(next_values_.end(), linear, linear + 3);
      next_values_.insert(next_values_.end(), angular, angular + 3);
    }
  }
  ids_.swap(next_ids_);
  values_.swap(next_values_);
  records_.swap(next_records_);

  std::vector<wire::QuantizedBody> sorted = records_;
  const auto by_id = [](const wire::QuantizedBody& a, const wire::QuantizedBody& b) { return a.id < b.id; };
  if (!std::is_sorted(sorted.begin(), sorted.end(), by_id)) std::sort(sorted.begin(), sorted.end(), by_id);
  return sorted;
}

}  // namespace tumble::frames
