// ConstraintGraph: the colouring of one group's constraints (Box2D v3's
// constraint graph, Catto, "Solver2D", 2024), so that no two constraints of
// one colour move the same dynamic body and a colour's constraints can be
// solved four at a time in the lanes of a wide constraint
// (wide_constraint.h). Colours are taken first fit, in the constraints'
// order; a constraint for which none of the kColours colours is free goes
// to the overflow colour, whose constraints are solved one at a time.
// Static and kinematic bodies (inverse mass 0) are moved by no constraint,
// so they take no colour: any number of a colour's constraints may read
// one.
//
// Thread: one thread at a time. Arrays are reused; colour() does not
// allocate once they have grown to the groups.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "contact_islands.h"

namespace tumble::physics {

class ConstraintGraph {
 public:
  static constexpr std::uint32_t kColours = 16;
  // The colour of the constraints that found none free.
  static constexpr std::uint32_t kOverflow = kColours;

  // Colours constraints (one group's). A dynamic body b is told apart by
  // its slot slot_of_body[b] in 1..dynamic_body_count; inverse_mass (by
  // dense body) tells dynamic bodies (> 0) from the rest.
  void colour(std::span<const ContactConstraint> constraints, std::span<const double> inverse_mass,
              std::span<const std::uint32_t> slot_of_body, std::uint32_t dynamic_body_count);
  // The constraints of a colour in 0..kOverflow, as indices into the
  // constraints given to colour(), in their order there.
  std::span<const std::uint32_t> members(std::uint32_t colour) const {
    return {order_.data() + start_[colour], start_[colour + 1] - start_[colour]};
  }
  // Room for a group of this many constraints, reserved ahead of need.
  void reserve(std::size_t constraints);

 private:
  // Row c holds a bit per body slot: set when colour c moves that body.
  std::vector<std::uint64_t> bits_;
  std::vector<std::uint32_t> colour_of_;     // by constraint
  std::vector<std::uint32_t> order_;         // constraints colour by colour
  std::uint32_t start_[kOverflow + 2] = {};  // colour c's members are order_[start_[c], start_[c + 1])
};

}  // namespace tumble::physics
