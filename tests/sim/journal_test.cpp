// Journal records carry checksums: a journal cut anywhere reads back the
// records before the cut and reports the torn one; a change to any byte of
// a whole record is damage, reported with the record's index and offset;
// version 1 journals still read.
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "sim/journal.h"
#include "temp_dir.h"

namespace tumble::sim {
namespace {

constexpr std::size_t kMagicBytes = 18;
constexpr std::size_t kHeadBytes = 12;

tumble::v1::JournalHeader test_header() {
  tumble::v1::JournalHeader header;
  header.set_format_version(kJournalFormat);
  header.set_tick_rate_hz(240);
  header.mutable_scene()->mutable_gravity()->set_y(-9.81);
  return header;
}

tumble::v1::ClientMessage push(std::uint64_t request_id) {
  tumble::v1::ClientMessage message;
  message.set_request_id(request_id);
  message.mutable_apply_force()->mutable_body()->set_name("crate");
  message.mutable_apply_force()->mutable_force()->set_x(10);
  return message;
}

// A journal of three commands at ticks 3, 3 and 9 and its end at 20; sets
// *starts to the byte offset of each record (the header's first).
std::string recorded_journal(const TempDir& dir, std::vector<std::size_t>* starts) {
  const std::string path = dir.file("run.journal");
  JournalWriter writer;
  EXPECT_TRUE(writer.open(path, test_header()).ok());
  writer.record(3, push(1));
  writer.record(3, push(2));
  writer.record(9, push(3));
  writer.finish(20);
  EXPECT_TRUE(writer.status().ok());
  std::ifstream file(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  starts->clear();
  for (std::size_t at = kMagicBytes; at < bytes.size();) {
    starts->push_back(at);
    // The record's length, little-endian; each byte widened before its shift.
    std::uint32_t length = 0;
    for (std::size_t i = 0; i < 4; ++i) length |= std::uint32_t{static_cast<unsigned char>(bytes[at + i])} << (8 * i);
    at += kHeadBytes + length;
  }
  return bytes;
}

// What a reader makes of `bytes`.
struct Reading {
  Status open;
  std::vector<std::uint64_t> ticks;  // of the entries read
  bool torn = false;
  std::string torn_record;
  Status status;
};

Reading read_journal(const TempDir& dir, const std::string& bytes) {
  const std::string path = dir.file("read.journal");
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  Reading reading;
  JournalReader reader;
  reading.open = reader.open(path);
  if (!reading.open.ok()) return reading;
  tumble::v1::JournalEntry entry;
  while (reader.next(&entry)) reading.ticks.push_back(entry.tick());
  reading.torn = reader.torn();
  reading.torn_record = reader.torn_record();
  reading.status = reader.status();
  return reading;
}

TEST(JournalChecksums, ACutAnywhereAfterTheHeaderReadsTheWholeRecordsBeforeIt) {
  TempDir dir;
  std::vector<std::size_t> starts;
  const std::string bytes = recorded_journal(dir, &starts);
  ASSERT_EQ(starts.size(), 5u);  // the header, three commands, the end
  const std::vector<std::uint64_t> all = {3, 3, 9, 20};
  for (std::size_t size = starts[1]; size <= bytes.size(); ++size) {
    const Reading reading = read_journal(dir, bytes.substr(0, size));
    ASSERT_TRUE(reading.open.ok()) << reading.open.message();
    EXPECT_TRUE(reading.status.ok()) << "cut at " << size << ": " << reading.status.message();
    // The records wholly before the cut, and a torn one when the cut is inside it.
    std::size_t whole = 0;
    while (whole + 2 < starts.size() && starts[whole + 2] <= size) ++whole;
    if (size == bytes.size()) whole = 4;
    EXPECT_EQ(reading.ticks, std::vector<std::uint64_t>(all.begin(), all.begin() + static_cast<long>(whole)))
        << "cut at " << size;
    const bool inside = size != bytes.size() && size != starts[whole + 1];
    EXPECT_EQ(reading.torn, inside) << "cut at " << size;
    if (inside) {
      EXPECT_EQ(reading.torn_record.rfind("record " + std::to_string(whole + 1) + " at byte " +
                                              std::to_string(starts[whole + 1]) + " is cut short: ",
                                          0),
                0u)
          << reading.torn_record;
    }
  }
}

TEST(JournalChecksums, AChangeToAnyByteOfAWholeRecordIsDamageAtThatRecord) {
  TempDir dir;
  std::vector<std::size_t> starts;
  const std::string bytes = recorded_journal(dir, &starts);
  for (std::size_t at = starts[1]; at < bytes.size(); ++at) {
    std::size_t record = 1;
    while (record + 1 < starts.size() && starts[record + 1] <= at) ++record;
    for (const char flip : {'\x01', '\x80', '\xff'}) {
      std::string damaged = bytes;
      damaged[at] ^= flip;
      const Reading reading = read_journal(dir, damaged);
      ASSERT_TRUE(reading.open.ok());
      const std::string where =
          "record " + std::to_string(record) + " at byte " + std::to_string(starts[record]) + ": ";
      EXPECT_EQ(reading.status.message().rfind(where, 0), 0u) << "byte " << at << ": " << reading.status.message();
      EXPECT_EQ(reading.ticks.size(), record - 1) << "byte " << at;
      EXPECT_FALSE(reading.torn) << "byte " << at;
    }
  }
}

TEST(JournalChecksums, DamageIsNamedByKind) {
  TempDir dir;
  std::vector<std::size_t> starts;
  const std::string bytes = recorded_journal(dir, &starts);
  std::string damaged = bytes;
  damaged[starts[2] + 1] ^= 0x10;  // the length of record 2
  EXPECT_EQ(read_journal(dir, damaged).status.message(),
            "record 2 at byte " + std::to_string(starts[2]) +
                ": its head is damaged (its length and checksum fail their own checksum)");
  damaged = bytes;
  damaged[starts[2] + kHeadBytes + 2] ^= 0x10;
  EXPECT_EQ(read_journal(dir, damaged).status.message(),
            "record 2 at byte " + std::to_string(starts[2]) + ": its payload is damaged (the checksum does not match)");
  damaged = bytes;
  damaged[kMagicBytes + kHeadBytes + 3] ^= 0x10;
  const Reading header = read_journal(dir, damaged);
  EXPECT_EQ(header.open.message(), dir.file("read.journal") +
                                       ": the journal's header is damaged: record 0 at byte 18: its payload is "
                                       "damaged (the checksum does not match)");
}

// protobuf's delimited encoding, as version 1 wrote it.
void append_delimited(const google::protobuf::MessageLite& message, std::string* out) {
  std::string payload = message.SerializeAsString();
  std::size_t length = payload.size();
  do {
    out->push_back(static_cast<char>((length & 0x7f) | (length > 0x7f ? 0x80 : 0)));
    length >>= 7;
  } while (length != 0);
  out->append(payload);
}

TEST(JournalChecksums, AVersion1JournalStillReads) {
  TempDir dir;
  std::string bytes = "tumble-journal-v1\n";
  append_delimited(test_header(), &bytes);
  tumble::v1::JournalEntry entry;
  entry.set_tick(4);
  *entry.mutable_command() = push(1);
  append_delimited(entry, &bytes);
  const std::string path = dir.file("old.journal");
  std::ofstream(path, std::ios::binary) << bytes;
  JournalReader reader;
  ASSERT_TRUE(reader.open(path).ok());
  EXPECT_FALSE(reader.checksummed());
  ASSERT_TRUE(reader.next(&entry));
  EXPECT_EQ(entry.tick(), 4u);
  EXPECT_FALSE(reader.next(&entry));
  EXPECT_FALSE(reader.torn());
  EXPECT_TRUE(reader.status().ok());
}

}  // namespace
}  // namespace tumble::sim
