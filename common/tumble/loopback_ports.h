// Free TCP ports of 127.0.0.1, for the programs that start servers of their
// own on loopback (the tests and the benchmarks): POSIX sockets only.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace tumble {

// `count` distinct ports free at the time of the call: each is bound to
// port 0 and read back, all are held until the last is, then released, so
// the kernel never hands out one twice. 0 for each that could not be had.
std::vector<std::uint16_t> free_loopback_ports(std::size_t count);

}  // namespace tumble
