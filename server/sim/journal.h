// The command journal of tumbled --record and --replay: where a run started
// (a scene or a saved state) and every command the sim thread executed, with
// the tick it executed at, in order. Replaying it on the same binary gives
// the same world bit for bit: the step is deterministic and commands are the
// only input.
//
// Layout of version 2: the 18-byte magic "tumble-journal-v2\n", then
// records, each a 12-byte head and a payload (integers little-endian):
//    4 bytes  L, the payload's length (at most 1 GiB)
//    4 bytes  the payload's CRC32C, masked (sim/crc32c.h)
//    4 bytes  the CRC32C of the 8 bytes before, masked: a damaged length is
//             told from a record cut short
//    L bytes  the payload, in protobuf's binary encoding
// Record 0 is a JournalHeader, the others JournalEntry; the last record of
// a run that stopped cleanly has end = true. Version 1 (magic
// "tumble-journal-v1\n", each message after a varint32 length, no
// checksums) is still read.
//
// Two ways a journal can end early, told apart as LevelDB's log reader
// does. A torn last record (the file ends inside it: the run was killed
// mid-write) is the end of the journal, reported by torn(): everything
// before it is what the run did. A record whose bytes are all there but
// fail a checksum or do not parse is damage: reading stops with status()
// naming the record and its offset, and a replay refuses to go on, since
// skipping a command would give another world.
//
// Thread: a writer or reader belongs to one thread (the sim thread).
#pragma once

#include <cstdint>
#include <fstream>
#include <string>

#include "sim/status.h"
#include "tumble/v1/state.pb.h"

namespace tumble::sim {

// The JournalHeader's format_version: what the messages mean. The framing
// has a version of its own, in the magic.
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
  // Opens `path` and reads its header (record 0); a damaged or torn header
  // is an error naming the file.
  Status open(const std::string& path);
  const tumble::v1::JournalHeader& header() const { return header_; }
  // False for a version 1 journal, whose records carry no checksums.
  bool checksummed() const { return checksummed_; }

  // The next entry, the end record included (entry->end()), or false after
  // it, at the end of the file, at a torn last record (torn()) or at a
  // damaged one (status()).
  bool next(tumble::v1::JournalEntry* entry);
  // The journal ended in a partial record: the run that wrote it was killed.
  bool torn() const { return torn_; }
  // Which record was torn and where, e.g. "record 7 at byte 300 is cut
  // short: 5 of its 32 bytes"; empty unless torn().
  const std::string& torn_record() const { return torn_record_; }
  // Not ok once a damaged record was met: "record 7 at byte 300: ...".
  const Status& status() const { return status_; }

 private:
  // Reads the record at the current offset into `message`; false at the
  // end, a torn record or a damaged one.
  bool read(google::protobuf::MessageLite* message);

  std::ifstream file_;
  tumble::v1::JournalHeader header_;
  bool checksummed_ = true;
  std::uint64_t record_ = 0;  // index of the next record (0: the header)
  std::uint64_t offset_ = 0;  // its byte offset in the file
  bool done_ = false;
  bool torn_ = false;
  std::string torn_record_;
  Status status_;
};

}  // namespace tumble::sim
