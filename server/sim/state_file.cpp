#include "sim/state_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string_view>

namespace tumble::sim {
namespace {

constexpr std::string_view kMagic = "tumble-state-v1\n";
// Far above any real world (a million bodies take about 300 MB) and below
// protobuf's 2 GiB message limit.
constexpr off_t kMaxStateBytes = off_t{1} << 30;

std::string errno_text() { return std::strerror(errno); }

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

Status write_state_file(const std::string& path, const tumble::v1::WorldState& state) {
  std::string bytes(kMagic);
  if (!state.AppendToString(&bytes)) return Status::error(path + ": cannot encode the world state");

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
  if (::rename(temporary.c_str(), path.c_str()) != 0) {
    const std::string rename_error = errno_text();
    ::unlink(temporary.c_str());
    return Status::error(path + ": cannot replace: " + rename_error);
  }
  // And the rename itself must survive a power cut: sync the directory.
  const int dir = ::open(directory_of(path).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir >= 0) {
    ::fsync(dir);
    ::close(dir);
  }
  return {};
}

Status read_state_file(const std::string& path, tumble::v1::WorldState* state, bool* exists) {
  *exists = false;
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    if (errno == ENOENT) return {};
    return Status::error(path + ": cannot open: " + errno_text());
  }
  *exists = true;
  if (info.st_size > kMaxStateBytes) {
    return Status::error(path + ": " + std::to_string(info.st_size) + " bytes is too large for a state file");
  }
  std::ifstream file(path, std::ios::binary);
  if (!file) return Status::error(path + ": cannot open: " + errno_text());
  std::ostringstream contents;
  contents << file.rdbuf();
  const std::string bytes = contents.str();
  if (bytes.compare(0, kMagic.size(), kMagic) != 0) {
    return Status::error(path + ": not a tumble state file (it does not start with 'tumble-state-v1')");
  }
  if (!state->ParseFromArray(bytes.data() + kMagic.size(), static_cast<int>(bytes.size() - kMagic.size()))) {
    return Status::error(path + ": the state file is damaged (not a valid WorldState)");
  }
  return {};
}

}  // namespace tumble::sim
