#include "net/checked_tcp_stream.h"

#include <algorithm>

namespace tumble::net {

std::size_t FrameHeaderScanner::scan(const unsigned char* data, std::size_t size) {
  if (illegal_) return 0;
  std::size_t at = 0;
  std::size_t header_start = 0;  // where the header being read began in these bytes (0: before them)
  while (at < size) {
    if (payload_left_ > 0) {
      const std::size_t skip = static_cast<std::size_t>(std::min<std::uint64_t>(payload_left_, size - at));
      at += skip;
      payload_left_ -= skip;
      continue;
    }
    if (header_bytes_ == 0) header_start = at;
    header_[header_bytes_++] = data[at++];
    if (header_bytes_ == 2) {
      // The second byte tells the header's size: 7 bits of length, 126 for
      // 16 more bits, 127 for 64 more; then the mask key when the mask bit is set.
      const unsigned length7 = header_[1] & 0x7Fu;
      header_size_ = std::size_t{2} +
                     (length7 == 126   ? 2u
                      : length7 == 127 ? 8u
                                       : 0u) +
                     ((header_[1] & 0x80u) != 0 ? 4u : 0u);
    }
    if (header_bytes_ < header_size_) continue;
    const unsigned length7 = header_[1] & 0x7Fu;
    std::uint64_t length = length7;
    if (length7 == 126) {
      length = (std::uint64_t{header_[2]} << 8) | header_[3];
    } else if (length7 == 127) {
      if ((header_[2] & 0x80u) != 0) {
        illegal_ = true;
        return header_start;
      }
      length = 0;
      for (std::size_t i = 2; i < 10; ++i) length = (length << 8) | header_[i];
    }
    payload_left_ = length;
    header_bytes_ = 0;
    header_size_ = 2;
  }
  return size;
}

}  // namespace tumble::net
