#include "constraint_graph.h"

#include <algorithm>

namespace tumble::physics {

void ConstraintGraph::reserve(std::size_t constraints) {
  colour_of_.reserve(constraints);
  order_.reserve(constraints);
}

void ConstraintGraph::colour(std::span<const ContactConstraint> constraints, std::span<const double> inverse_mass,
                             std::span<const std::uint32_t> slot_of_body, std::uint32_t dynamic_body_count) {
  // First fit: a colour holds a dynamic body at most once (bit slot of
  // row c).
  const std::size_t words = (dynamic_body_count + 1 + 63) / 64;
  bits_.assign(kColours * words, 0);
  const std::size_t count = constraints.size();
  if (colour_of_.size() < count) colour_of_.resize(count);
  std::uint32_t members[kOverflow + 1] = {};
  for (std::size_t k = 0; k < count; ++k) {
    const ContactConstraint& c = constraints[k];
    const bool moves_a = inverse_mass[c.body_a] != 0, moves_b = inverse_mass[c.body_b] != 0;
    const std::uint32_t slot_a = moves_a ? slot_of_body[c.body_a] : 0;
    const std::uint32_t slot_b = moves_b ? slot_of_body[c.body_b] : 0;
    const std::uint64_t bit_a = std::uint64_t{1} << (slot_a % 64), bit_b = std::uint64_t{1} << (slot_b % 64);
    std::uint32_t colour = 0;
    for (; colour < kColours; ++colour) {
      std::uint64_t* row = bits_.data() + colour * words;
      if (moves_a && (row[slot_a / 64] & bit_a) != 0) continue;
      if (moves_b && (row[slot_b / 64] & bit_b) != 0) continue;
      if (moves_a) row[slot_a / 64] |= bit_a;
      if (moves_b) row[slot_b / 64] |= bit_b;
      break;
    }
    colour_of_[k] = colour;  // kOverflow when none was free
    ++members[colour];
  }

  // The constraints colour by colour (a counting sort, stable).
  for (std::uint32_t colour = 0, offset = 0; colour <= kOverflow; ++colour) {
    start_[colour] = offset;
    offset += members[colour];
  }
  start_[kOverflow + 1] = static_cast<std::uint32_t>(count);
  if (order_.size() < count) order_.resize(count);
  std::uint32_t next[kOverflow + 1];
  std::copy(start_, start_ + kOverflow + 1, next);
  for (std::uint32_t k = 0; k < count; ++k) order_[next[colour_of_[k]]++] = k;
}

}  // namespace tumble::physics
