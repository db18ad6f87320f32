// The command journal of tumbled --record and --replay: where a run started
// (a scene or a saved state) and every command the sim thread executed, with
// the tick it executed at, in order. Replaying it on the same binary gives
// the same world bit for bit: the step is deterministic and commands are the
// only input.
//
// Layout: the 18-byte magic "tumble-journal-v1\n", then protobuf's delimited
// encoding (a varint32 length before each message): one JournalHeader, then
// JournalEntry records. The last record of a run that stopped cleanly has
// end = true. A run killed mid-write leaves a torn last record, which the
// reader reports as the end.
//
// Thread: a writer or reader belongs to one thread (the sim thread).
#pragma once

#include <cstdint>
#include <fstream>
#include <string>

#include "sim/status.h"
#include "tumble/v1/state.pb.h"

namespace tumble::sim {

inline constexpr std::uint32_t kJournalFormat = 1;

// Appends to a new journal file. Writes are buffered; flush() hands them to
// the operating system (the sim calls it once per tick that recorded
// something), so a crash of tumbled loses nothing already flushed.
class JournalWriter {
 public:
  // Creates (or truncates) `path` and writes the header.
  Status open(const std::string& path, const tumble::v1::JournalHeader& header);
  bool is_open() const { return file_.is_open(); }

  // Records a command executed at `tick` (before the step that makes tick + 1).
  void record(std::uint64_t tick, const tumble::v1::ClientMessage& command);
  // Records the end of the run at `tick` and closes the file.
  void finish(std::uint64_t tick);
  void flush();

  // False once a write has failed (disk full, ...); the first error.
  const Status& status() const { return status_; }

 private:
  void write(const google::protobuf::MessageLite& message);

  std::string path_;
  std::ofstream file_;
  Status status_;
};

// Reads a journal from the start.
class JournalReader {
 public:
  // Opens `path` and reads its header.
  Status open(const std::string& path);
  const tumble::v1::JournalHeader& header() const { return header_; }

  // The next entry, the end record included (entry->end()), or false after
  // it, at the end of the file, or at a torn last record (see torn()).
  bool next(tumble::v1::JournalEntry* entry);
  // The journal ended in a partial record: the run that wrote it was killed.
  bool torn() const { return torn_; }

 private:
  std::ifstream file_;
  tumble::v1::JournalHeader header_;
  bool done_ = false;
  bool torn_ = false;
};

}  // namespace tumble::sim
