#include "sim/journal.h"

#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/io/zero_copy_stream_impl.h>

#include <string_view>

namespace tumble::sim {
namespace {

constexpr std::string_view kMagic = "tumble-journal-v1\n";
// No single record comes near this: a command is at most a client frame
// (1 MiB by default), a header at most a state file.
constexpr std::uint32_t kMaxRecordBytes = 1u << 30;

// Reads one varint32-delimited record. Returns false at a clean end of file
// (nothing read); sets *torn when a record starts but does not finish or
// does not parse.
bool read_record(std::istream& in, google::protobuf::MessageLite* message, bool* torn) {
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
  file_.write(kMagic.data(), static_cast<std::streamsize>(kMagic.size()));
  write(header);
  flush();
  return status_;
}

void JournalWriter::write(const google::protobuf::MessageLite& message) {
  if (!status_.ok()) return;
  std::string bytes;
  {
    google::protobuf::io::StringOutputStream stream(&bytes);
    google::protobuf::io::CodedOutputStream coded(&stream);
    coded.WriteVarint32(static_cast<std::uint32_t>(message.ByteSizeLong()));
    message.SerializeWithCachedSizes(&coded);
  }
  file_.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
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

Status JournalReader::open(const std::string& path) {
  file_.open(path, std::ios::binary);
  if (!file_) return Status::error(path + ": cannot open the journal");
  std::string magic(kMagic.size(), '\0');
  file_.read(magic.data(), static_cast<std::streamsize>(magic.size()));
  if (magic != kMagic) return Status::error(path + ": not a tumble journal (no 'tumble-journal-v1' at its start)");
  bool torn = false;
  if (!read_record(file_, &header_, &torn)) return Status::error(path + ": the journal has no readable header");
  if (header_.format_version() != kJournalFormat) {
    return Status::error(path + ": journal format " + std::to_string(header_.format_version()) +
                         " is not the supported " + std::to_string(kJournalFormat));
  }
  return {};
}

bool JournalReader::next(tumble::v1::JournalEntry* entry) {
  if (done_) return false;
  if (!read_record(file_, entry, &torn_)) {
    done_ = true;
    return false;
  }
  done_ = entry->end();
  return true;
}

}  // namespace tumble::sim
