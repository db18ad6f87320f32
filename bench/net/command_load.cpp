#include "command_load.h"

#include <cstdio>
#include <thread>

namespace tumble::bench {
namespace {

using Clock = std::chrono::steady_clock;

// A fixed pseudo-random sequence (64-bit LCG, Knuth's MMIX constants).
struct Sequence {
  std::uint64_t state = 1;
  std::uint64_t next() {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return state >> 33;
  }
  double unit() { return static_cast<double>(next() % 2001) / 1000 - 1; }  // -1 .. 1
};

void set_direction(tumble::v1::Vec3* out, Sequence& random, double length) {
  out->set_x(length * random.unit());
  out->set_y(length * random.unit());
  out->set_z(length * random.unit());
}

client::Result<tumble::v1::Ack> send(client::Connection& connection, std::uint64_t n, std::uint32_t body,
                                     Sequence& random) {
  const auto timeout = std::chrono::seconds(10);
  switch (n % 3) {
    case 0: {
      tumble::v1::ApplyForce force;
      force.mutable_body()->set_id(body);
      set_direction(force.mutable_force(), random, 0.2);
      force.set_ticks(10);
      return connection.apply_force(force, timeout);
    }
    case 1: {
      tumble::v1::ApplyImpulse impulse;
      impulse.mutable_body()->set_id(body);
      set_direction(impulse.mutable_impulse(), random, 0.05);
      return connection.apply_impulse(impulse, timeout);
    }
    default: {
      tumble::v1::SetBodyState set;
      set.mutable_body()->set_id(body);
      set.mutable_linear_velocity();  // present and zero: stop
      set.mutable_angular_velocity()->set_y(1);
      return connection.set_body_state(set, timeout);
    }
  }
}

}  // namespace

CommandTally run_commands(const LoadTarget& target, const std::vector<std::uint32_t>& bodies, double per_second,
                          Clock::time_point end) {
  CommandTally tally;
  if (bodies.empty() || per_second <= 0) return tally;
  client::Connection connection = connect_or_exit(target, "net_load-commands");
  const auto interval = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1 / per_second));
  Sequence random;
  const Clock::time_point start = Clock::now();
  for (std::uint64_t n = 0;; ++n) {
    const Clock::time_point due = start + static_cast<std::int64_t>(n) * interval;
    if (due >= end) break;
    std::this_thread::sleep_until(due);
    const std::uint32_t body = bodies[random.next() % bodies.size()];
    auto ack = send(connection, n, body, random);
    ++tally.sent;
    if (!ack) {
      ++tally.errors;
      std::fprintf(stderr, "net_load: command %llu on body %u: %s\n", static_cast<unsigned long long>(n), body,
                   ack.failure().message.c_str());
    }
  }
  return tally;
}

}  // namespace tumble::bench
