#include "pair_set.h"

#include <algorithm>
#include <cassert>
#include <utility>

namespace tumble::physics {

std::uint64_t PairSet::key_of(std::uint32_t a, std::uint32_t b) {
  assert(a != b);
  if (a > b) std::swap(a, b);
  return (std::uint64_t{a} << 32) | b;
}

std::size_t PairSet::home(std::uint64_t key) const {
  // The 64-bit finalizer of MurmurHash3 (fmix64): every bit of the key moves
  // the low bits, which pick the entry.
  key ^= key >> 33;
  key *= 0xff51afd7ed558ccdULL;
  key ^= key >> 33;
  key *= 0xc4ceb9fe1a85ec53ULL;
  key ^= key >> 33;
  return static_cast<std::size_t>(key) & (entries_.size() - 1);
}

void PairSet::reserve(std::size_t pairs) {
  std::size_t capacity = 16;
  while (capacity < 2 * pairs) capacity *= 2;
  if (capacity > entries_.size()) grow(capacity);
}

void PairSet::grow(std::size_t capacity) {
  std::vector<Entry> old(capacity);
  old.swap(entries_);
  const std::size_t mask = entries_.size() - 1;
  for (const Entry& entry : old) {
    if (entry.key == 0) continue;
    std::size_t i = home(entry.key);
    while (entries_[i].key != 0) i = (i + 1) & mask;
    entries_[i] = entry;
  }
}

void PairSet::insert(std::uint32_t a, std::uint32_t b, std::uint32_t value) {
  if (2 * (count_ + 1) > entries_.size()) grow(std::max<std::size_t>(16, 2 * entries_.size()));
  const std::uint64_t key = key_of(a, b);
  const std::size_t mask = entries_.size() - 1;
  std::size_t i = home(key);
  while (entries_[i].key != 0) {
    assert(entries_[i].key != key);
    i = (i + 1) & mask;
  }
  entries_[i] = {key, value};
  ++count_;
}

std::uint32_t PairSet::find(std::uint32_t a, std::uint32_t b) const {
  if (entries_.empty()) return kNotFound;
  const std::uint64_t key = key_of(a, b);
  const std::size_t mask = entries_.size() - 1;
  for (std::size_t i = home(key); entries_[i].key != 0; i = (i + 1) & mask) {
    if (entries_[i].key == key) return entries_[i].value;
  }
  return kNotFound;
}

void PairSet::erase(std::uint32_t a, std::uint32_t b) {
  const std::uint64_t key = key_of(a, b);
  const std::size_t mask = entries_.size() - 1;
  std::size_t hole = home(key);
  while (entries_[hole].key != key) {
    assert(entries_[hole].key != 0);
    hole = (hole + 1) & mask;
  }
  // Backward shift: each entry after the hole in its run moves into the
  // hole if the hole lies on its way from its home, so every entry stays
  // reachable from its home without crossing an empty entry.
  for (std::size_t next = (hole + 1) & mask; entries_[next].key != 0; next = (next + 1) & mask) {
    const std::size_t want = home(entries_[next].key);
    // Cyclic: the entry may fill the hole unless its home lies in (hole, next].
    const bool home_after_hole = hole <= next ? (hole < want && want <= next) : (hole < want || want <= next);
    if (home_after_hole) continue;
    entries_[hole] = entries_[next];
    hole = next;
  }
  entries_[hole] = Entry{};
  --count_;
}

}  // namespace tumble::physics
