// PairSet: the pairs of bodies that have a contact, each with its contact's
// slot, so "have a and b a contact?" is one probe instead of a walk along a
// body's contact list (Box2D v3 keeps its pairs in a hash set the same
// way). A pair is unordered: (a, b) and (b, a) are one key.
//
// Open addressing with linear probing, at most half full; an erase shifts
// the entries after it back into place, so there are no tombstones and a
// probe ends at the first empty entry. Bodies are dense indices below
// 2^32 - 1. Not thread-safe. insert() allocates only when the set grows
// past the capacity reserved.
#pragma once

#include <cstdint>
#include <vector>

namespace tumble::physics {

class PairSet {
 public:
  static constexpr std::uint32_t kNotFound = 0xffffffff;

  // Room for `pairs` pairs without growing.
  void reserve(std::size_t pairs);
  // Adds the pair with its value; the pair must not be in the set.
  void insert(std::uint32_t a, std::uint32_t b, std::uint32_t value);
  // Removes the pair; it must be in the set.
  void erase(std::uint32_t a, std::uint32_t b);
  // The pair's value, or kNotFound.
  std::uint32_t find(std::uint32_t a, std::uint32_t b) const;
  std::size_t size() const { return count_; }

 private:
  // key 0 marks an empty entry: a pair's key has its smaller body in the
  // high half and the larger in the low, and the two differ.
  struct Entry {
    std::uint64_t key = 0;
    std::uint32_t value = 0;
  };

  static std::uint64_t key_of(std::uint32_t a, std::uint32_t b);
  std::size_t home(std::uint64_t key) const;
  void grow(std::size_t capacity);

  std::vector<Entry> entries_;  // a power of two in size, or empty
  std::size_t count_ = 0;
};

}  // namespace tumble::physics
