#include "sim/state_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "sim/crc32c.h"
#include "sim/world_state.h"

namespace tumble::sim {
namespace {

constexpr std::string_view kStateMagicV1 = "tumble-state-v1\n";
constexpr std::string_view kStateMagicV2 = "tumble-state-v2\n";
constexpr std::size_t kMagicBytes = 16;
constexpr std::size_t kLengthBytes = 8;
constexpr std::size_t kCrcBytes = 4;
// A version 2 file without its payload: magic, length and checksum.
constexpr std::size_t kFramingBytes = kMagicBytes + kLengthBytes + kCrcBytes;
// Far above any real world (a million bodies take about 300 MB) and below
// protobuf's 2 GiB message limit.
constexpr std::uint64_t kMaxPayloadBytes = std::uint64_t{1} << 30;

static_assert(kStateMagicV1.size() == kMagicBytes && kStateMagicV2.size() == kMagicBytes);

std::string errno_text() { return std::strerror(errno); }

std::string hex(std::uint32_t value) {
  char text[16];
  std::snprintf(text, sizeof text, "0x%08x", value);
  return text;
}

void append_le(std::uint64_t value, std::size_t bytes, std::string* out) {
  for (std::size_t i = 0; i < bytes; ++i) out->push_back(static_cast<char>((value >> (8 * i)) & 0xffu));
}

std::uint64_t read_le(std::string_view bytes) {
  std::uint64_t value = 0;
  for (std::size_t i = bytes.size(); i-- > 0;) value = (value << 8) | static_cast<unsigned char>(bytes[i]);
  return value;
}

// Whether `bytes` after a magic are a whole version 2 frame: the length
// field matches the size and the checksum matches the payload.
bool is_v2_frame(std::string_view rest) {
  if (rest.size() < kLengthBytes + kCrcBytes) return false;
  const std::uint64_t length = read_le(rest.substr(0, kLengthBytes));
  if (length != rest.size() - kLengthBytes - kCrcBytes) return false;
  const std::string_view payload = rest.substr(kLengthBytes, length);
  return crc32c::unmask(static_cast<std::uint32_t>(read_le(rest.substr(kLengthBytes + length)))) ==
         crc32c::value(payload);
}

// Parses a checked payload and makes sure it is a world state this build reads.
Status parse_payload(std::string_view payload, tumble::v1::WorldState* state) {
  if (!state->ParseFromArray(payload.data(), static_cast<int>(payload.size()))) {
    return Status::error("the payload does not parse as a WorldState");
  }
  if (state->format_version() == 0) return Status::error("the payload holds no world state (it has no format_version)");
  if (state->format_version() != kWorldStateFormat) {
    return Status::error("the payload is a world state of format " + std::to_string(state->format_version()) +
                         "; this tumbled reads format " + std::to_string(kWorldStateFormat));
  }
  return {};
}

// Writes all of `bytes` to `fd`, retrying short writes.
bool write_all(int fd, const std::string& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

std::string directory_of(const std::string& path) {
  const std::size_t slash = path.rfind('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

}  // namespace

bool encode_state_file(const tumble::v1::WorldState& state, std::string* bytes) {
  std::string payload;
  if (!state.SerializeToString(&payload) || payload.size() > kMaxPayloadBytes) return false;
  bytes->assign(kStateMagicV2);
  append_le(payload.size(), kLengthBytes, bytes);
  bytes->append(payload);
  append_le(crc32c::mask(crc32c::value(payload)), kCrcBytes, bytes);
  return true;
}

Status parse_state_file(std::string_view bytes, tumble::v1::WorldState* state, StateFileFormat* format) {
  if (bytes.empty()) return Status::error("the file is empty");
  if (bytes.size() < kMagicBytes &&
      (kStateMagicV2.substr(0, bytes.size()) == bytes || kStateMagicV1.substr(0, bytes.size()) == bytes)) {
    return Status::error("cut short inside its magic (" + std::to_string(bytes.size()) + " bytes)");
  }
  const std::string_view magic = bytes.substr(0, kMagicBytes);
  const std::string_view rest = bytes.substr(std::min(bytes.size(), kMagicBytes));

  if (magic == kStateMagicV1) {
    *format = StateFileFormat::v1;
    if (rest.empty()) return Status::error("nothing after its magic: the file holds no world");
    // One flipped byte turns "v2" into "v1"; such a file would otherwise be
    // parsed without its checksum.
    if (is_v2_frame(rest)) {
      return Status::error("its magic says version 1 but the rest is a version 2 file: the magic is damaged");
    }
    return parse_payload(rest, state);
  }
  if (magic != kStateMagicV2) {
    return Status::error("not a tumble state file (it does not start with 'tumble-state-v2' or 'tumble-state-v1')");
  }
  *format = StateFileFormat::v2;
  if (rest.size() < kLengthBytes) {
    return Status::error("cut short: " + std::to_string(bytes.size()) + " bytes end before its " +
                         std::to_string(kLengthBytes) + "-byte payload length");
  }
  const std::uint64_t length = read_le(rest.substr(0, kLengthBytes));
  if (length > kMaxPayloadBytes) {
    return Status::error("bad length: its length field says " + std::to_string(length) +
                         " bytes, more than the 1 GiB a state file may hold");
  }
  const std::uint64_t expected = kFramingBytes + length;
  if (bytes.size() < expected) {
    return Status::error("cut short: " + std::to_string(bytes.size()) + " bytes, where its length field makes " +
                         std::to_string(expected));
  }
  if (bytes.size() > expected) {
    return Status::error("too long: " + std::to_string(bytes.size()) + " bytes, where its length field makes " +
                         std::to_string(expected));
  }
  const std::string_view payload = rest.substr(kLengthBytes, length);
  const std::uint32_t stored = crc32c::unmask(static_cast<std::uint32_t>(read_le(rest.substr(kLengthBytes + length))));
  const std::uint32_t actual = crc32c::value(payload);
  if (stored != actual) {
    return Status::error("bad checksum: the payload's CRC32C is " + hex(actual) + ", the file says " + hex(stored) +
                         " (the file is damaged)");
  }
  return parse_payload(payload, state);
}

Status write_state_file(const std::string& path, const tumble::v1::WorldState& state) {
  std::string bytes;
  if (!encode_state_file(state, &bytes)) return Status::error(path + ": cannot encode the world state");

  const std::string temporary = path + ".tmp";
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return Status::error(temporary + ": cannot create: " + errno_text());
  // The data must be on disk before the rename makes it the state file.
  const bool written = write_all(fd, bytes) && ::fsync(fd) == 0;
  const std::string write_error = errno_text();
  if (::close(fd) != 0 || !written) {
    ::unlink(temporary.c_str());
    return Status::error(temporary + ": cannot write: " + write_error);
  }
  // The file being replaced becomes <path>.prev. A crash between the two
  // renames leaves no <path> and a whole <path>.prev, which a start takes.
  const std::string previous = path + std::string(kPreviousSuffix);
  if (::rename(path.c_str(), previous.c_str()) != 0 && errno != ENOENT) {
    const std::string rename_error = errno_text();
    ::unlink(temporary.c_str());
    return Status::error(previous + ": cannot keep the previous state file: " + rename_error);
  }
  if (::rename(temporary.c_str(), path.c_str()) != 0) {
    const std::string rename_error = errno_text();
    ::unlink(temporary.c_str());
    ::rename(previous.c_str(), path.c_str());  // put the old file back where it was
    return Status::error(path + ": cannot replace: " + rename_error);
  }
  // And the renames themselves must survive a power cut: sync the directory.
  const int dir = ::open(directory_of(path).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir >= 0) {
    ::fsync(dir);
    ::close(dir);
  }
  return {};
}

Status read_state_file(const std::string& path, tumble::v1::WorldState* state, bool* exists, StateFileFormat* format) {
  *exists = false;
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    if (errno == ENOENT) return {};
    return Status::error(path + ": cannot open: " + errno_text());
  }
  *exists = true;
  if (static_cast<std::uint64_t>(info.st_size) > kFramingBytes + kMaxPayloadBytes) {
    return Status::error(path + ": " + std::to_string(info.st_size) + " bytes is too large for a state file");
  }
  std::ifstream file(path, std::ios::binary);
  if (!file) return Status::error(path + ": cannot open: " + errno_text());
  std::ostringstream contents;
  contents << file.rdbuf();
  StateFileFormat read_format = StateFileFormat::v2;
  if (Status status = parse_state_file(contents.str(), state, &read_format); !status.ok()) {
    return Status::error(path + ": " + status.message());
  }
  if (format != nullptr) *format = read_format;
  return {};
}

}  // namespace tumble::sim
