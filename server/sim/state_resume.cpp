#include "sim/state_resume.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "sim/state_file.h"

namespace tumble::sim {
namespace {

// One candidate file, read and offered to `accept`.
struct Attempt {
  Status status;  // ok: accepted, or the file does not exist
  bool exists = false;
  StateFileFormat format = StateFileFormat::v2;
  std::uint64_t tick = 0;
};

Attempt attempt(const std::string& path, const AcceptState& accept) {
  Attempt result;
  tumble::v1::WorldState state;
  result.status = read_state_file(path, &state, &result.exists, &result.format);
  if (!result.status.ok() || !result.exists) return result;
  if (Status status = accept(state); !status.ok()) {
    result.status = Status::error(path + ": " + status.message());
  }
  result.tick = state.tick();
  return result;
}

bool exists(const std::string& path) {
  struct stat info {};
  return ::lstat(path.c_str(), &info) == 0 || errno != ENOENT;
}

// Renames `path` to the first of <path>.damaged, .damaged.1, ... that does
// not exist yet; sets *kept_as to it.
Status keep_damaged(const std::string& path, std::string* kept_as) {
  const std::string base = path + ".damaged";
  for (int n = 0; n < 1000; ++n) {
    const std::string name = n == 0 ? base : base + "." + std::to_string(n);
    if (exists(name)) continue;
    if (std::rename(path.c_str(), name.c_str()) != 0) {
      return Status::error("cannot keep the damaged " + path + " as " + name + ": " + std::strerror(errno));
    }
    *kept_as = name;
    return {};
  }
  return Status::error("cannot keep the damaged " + path + ": " + base + " to " + base + ".999 all exist");
}

std::string v1_warning(const std::string& path) {
  return path +
         " is a version 1 state file, which carries no checksum: damage to it cannot be detected; "
         "the next save writes version 2";
}

}  // namespace

Status resume_state(const std::string& path, const AcceptState& accept, ResumedState* out) {
  *out = ResumedState{};
  const Attempt current = attempt(path, accept);
  if (current.status.ok() && current.exists) {
    out->resumed = true;
    out->from = path;
    out->tick = current.tick;
    if (current.format == StateFileFormat::v1) out->warnings.push_back(v1_warning(path));
    return {};
  }

  const std::string previous = path + std::string(kPreviousSuffix);
  const Attempt fallback = attempt(previous, accept);
  const bool fallback_good = fallback.status.ok() && fallback.exists;
  if (current.status.ok()) {
    // There is no <path>.
    if (!fallback.exists) return {};  // a first start
    if (!fallback_good) {
      return Status::error(path +
                           " does not exist, and the previous state file is unusable: " + fallback.status.message());
    }
    out->warnings.push_back(path + " does not exist (a save was interrupted between its two renames): resuming from " +
                            previous + ", saved at tick " + std::to_string(fallback.tick));
  } else {
    if (!fallback_good) {
      return Status::error(current.status.message() + "; and the previous state file is unusable too: " +
                           (fallback.exists ? fallback.status.message() : previous + " does not exist"));
    }
    std::string kept_as;
    if (Status status = keep_damaged(path, &kept_as); !status.ok()) return status;
    out->warnings.push_back("THE STATE FILE IS DAMAGED: " + current.status.message() + "; resuming from " + previous +
                            ", the last good state, saved at tick " + std::to_string(fallback.tick) +
                            " (what happened after it is lost); the damaged file is kept as " + kept_as);
  }
  out->resumed = true;
  out->from = previous;
  out->tick = fallback.tick;
  if (fallback.format == StateFileFormat::v1) out->warnings.push_back(v1_warning(previous));
  return {};
}

}  // namespace tumble::sim
