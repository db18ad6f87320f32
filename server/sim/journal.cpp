#include "sim/journal.h"

#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/io/zero_copy_stream_impl.h>

#include <string_view>

#include "sim/crc32c.h"

namespace tumble::sim {
namespace {

constexpr std::string_view kJournalMagicV1 = "tumble-journal-v1\n";
constexpr std::string_view kJournalMagicV2 = "tumble-journal-v2\n";
static_assert(kJournalMagicV1.size() == kJournalMagicV2.size());
// A record's head: length, payload CRC, head CRC.
constexpr std::size_t kHeadBytes = 12;
// No single record comes near this: a command is at most a client frame
// (1 MiB by default), a header at most a state file.
constexpr std::uint32_t kMaxRecordBytes = 1u << 30;

void append_u32(std::uint32_t value, std::string* out) {
  for (int i = 0; i < 4; ++i) out->push_back(static_cast<char>((value >> (8 * i)) & 0xffu));
}

std::uint32_t read_u32(const char* bytes) {
  std::uint32_t value = 0;
  for (int i = 3; i >= 0; --i) value = (value << 8) | static_cast<unsigned char>(bytes[i]);
  return value;
}

// Reads one varint32-delimited record of a version 1 journal. Returns false
// at a clean end of file (nothing read); sets *torn when a record starts but
// does not finish or does not parse.
bool read_v1_record(std::istream& in, google::protobuf::MessageLite* message, bool* torn) {
  std::uint32_t length = 0;
  int shift = 0;
  for (;;) {
    const int c = in.get();
    if (c == std::char_traits<char>::eof()) {
      *torn = shift != 0;
      return false;
    }
    length |= static_cast<std::uint32_t>(c & 0x7f) << shift;
    if ((c & 0x80) == 0) break;
    shift += 7;
    if (shift > 28) {
      *torn = true;
      return false;
    }
  }
  if (length > kMaxRecordBytes) {
    *torn = true;
    return false;
  }
  std::string bytes(length, '\0');
  in.read(bytes.data(), length);
  if (static_cast<std::uint32_t>(in.gcount()) != length || !message->ParseFromString(bytes)) {
    *torn = true;
    return false;
  }
  return true;
}

}  // namespace

Status JournalWriter::open(const std::string& path, const tumble::v1::JournalHeader& header) {
  path_ = path;
  file_.open(path, std::ios::binary | std::ios::trunc);
  if (!file_) return status_ = Status::error(path + ": cannot create the journal");
  file_.write(kJournalMagicV2.data(), static_cast<std::streamsize>(kJournalMagicV2.size()));
  write(header);
  flush();
  return status_;
}

void JournalWriter::write(const google::protobuf::MessageLite& message) {
  if (!status_.ok()) return;
  std::string payload;
  if (!message.SerializeToString(&payload) || payload.size() > kMaxRecordBytes) {
    status_ = Status::error(path_ + ": a record is too large for the journal");
    return;
  }
  std::string head;
  append_u32(static_cast<std::uint32_t>(payload.size()), &head);
  append_u32(crc32c::mask(crc32c::value(payload)), &head);
  append_u32(crc32c::mask(crc32c::value(head)), &head);
  file_.write(head.data(), static_cast<std::streamsize>(head.size()));
  file_.write(payload.data(), static_cast<std::streamsize>(payload.size()));
  if (!file_) status_ = Status::error(path_ + ": cannot write the journal");
}

void JournalWriter::record(std::uint64_t tick, const tumble::v1::ClientMessage& command) {
  tumble::v1::JournalEntry entry;
  entry.set_tick(tick);
  *entry.mutable_command() = command;
  write(entry);
}

void JournalWriter::finish(std::uint64_t tick) {
  if (!file_.is_open()) return;
  tumble::v1::JournalEntry entry;
  entry.set_tick(tick);
  entry.set_end(true);
  write(entry);
  flush();
  file_.close();
}

void JournalWriter::flush() {
  if (!file_.is_open() || !status_.ok()) return;
  file_.flush();
  if (!file_) status_ = Status::error(path_ + ": cannot write the journal");
}

bool JournalReader::read(google::protobuf::MessageLite* message) {
  if (!checksummed_) offset_ = static_cast<std::uint64_t>(file_.tellg());
  const std::string where = "record " + std::to_string(record_) + " at byte " + std::to_string(offset_);
  if (!checksummed_) {
    if (read_v1_record(file_, message, &torn_)) {
      ++record_;
      return true;
    }
    if (torn_) torn_record_ = where + " is cut short or garbled (a version 1 journal has no checksums)";
    return false;
  }

  char head[kHeadBytes];
  file_.read(head, kHeadBytes);
  const auto got = static_cast<std::size_t>(file_.gcount());
  if (got == 0) return false;  // the clean end of the file
  if (got < kHeadBytes) {
    torn_ = true;
    torn_record_ =
        where + " is cut short: " + std::to_string(got) + " bytes of its " + std::to_string(kHeadBytes) + "-byte head";
    return false;
  }
  const std::uint32_t length = read_u32(head);
  const std::uint32_t payload_crc = crc32c::unmask(read_u32(head + 4));
  if (crc32c::unmask(read_u32(head + 8)) != crc32c::value(std::string_view(head, 8))) {
    status_ = Status::error(where + ": its head is damaged (its length and checksum fail their own checksum)");
    return false;
  }
  if (length > kMaxRecordBytes) {
    status_ =
        Status::error(where + ": a length of " + std::to_string(length) + " bytes is more than a record may have");
    return false;
  }
  std::string payload(length, '\0');
  file_.read(payload.data(), length);
  const auto got_payload = static_cast<std::uint32_t>(file_.gcount());
  if (got_payload < length) {
    torn_ = true;
    torn_record_ = where + " is cut short: " + std::to_string(kHeadBytes + got_payload) + " of its " +
                   std::to_string(kHeadBytes + length) + " bytes";
    return false;
  }
  if (crc32c::value(payload) != payload_crc) {
    status_ = Status::error(where + ": its payload is damaged (the checksum does not match)");
    return false;
  }
  if (!message->ParseFromString(payload)) {
    status_ = Status::error(where + ": its payload does not parse, though its checksum matches");
    return false;
  }
  ++record_;
  offset_ += kHeadBytes + length;
  return true;
}

Status JournalReader::open(const std::string& path) {
  file_.open(path, std::ios::binary);
  if (!file_) return Status::error(path + ": cannot open the journal");
  std::string magic(kJournalMagicV2.size(), '\0');
  file_.read(magic.data(), static_cast<std::streamsize>(magic.size()));
  if (magic == kJournalMagicV1) {
    checksummed_ = false;
  } else if (magic != kJournalMagicV2) {
    return Status::error(path + ": not a tumble journal (no 'tumble-journal-v2' or 'tumble-journal-v1' at its start)");
  }
  offset_ = magic.size();
  if (!read(&header_)) {
    if (!status_.ok()) return Status::error(path + ": the journal's header is damaged: " + status_.message());
    return Status::error(path + ": the journal has no readable header" +
                         (torn_record_.empty() ? std::string() : " (" + torn_record_ + ")"));
  }
  if (header_.format_version() != kJournalFormat) {
    return Status::error(path + ": journal format " + std::to_string(header_.format_version()) +
                         " is not the supported " + std::to_string(kJournalFormat));
  }
  return {};
}

bool JournalReader::next(tumble::v1::JournalEntry* entry) {
  if (done_) return false;
  if (!read(entry)) {
    done_ = true;
    return false;
  }
  done_ = entry->end();
  return true;
}

}  // namespace tumble::sim
