// Requests as the protocol tests send them: one ClientMessage each, with
// its request_id, naming bodies by name.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <string>

#include "tumble/v1/protocol.pb.h"

namespace tumble::test {

inline tumble::v1::ClientMessage list_bodies(std::uint64_t id) {
  tumble::v1::ClientMessage m;
  m.set_request_id(id);
  m.mutable_list_bodies();
  return m;
}

inline tumble::v1::ClientMessage get_stats(std::uint64_t id) {
  tumble::v1::ClientMessage m;
  m.set_request_id(id);
  m.mutable_get_stats();
  return m;
}

// A stream of `bodies` (every body when empty) at `rate_hz` (0: every tick),
// with the server's default fields and encoding.
inline tumble::v1::ClientMessage subscribe(std::uint64_t id, double rate_hz,
                                           std::initializer_list<const char*> bodies = {}) {
  tumble::v1::ClientMessage m;
  m.set_request_id(id);
  m.mutable_subscribe()->set_rate_hz(rate_hz);
  for (const char* name : bodies) m.mutable_subscribe()->add_bodies()->set_name(name);
  return m;
}

// Spawns a 1 kg sphere called `name` of `radius` m at (0, 10, 0).
inline tumble::v1::ClientMessage spawn_sphere(std::uint64_t id, const std::string& name, double radius = 0.5) {
  tumble::v1::ClientMessage m;
  m.set_request_id(id);
  auto* body = m.mutable_spawn_body()->mutable_body();
  body->set_name(name);
  body->mutable_shape()->mutable_sphere()->set_radius(radius);
  body->set_mass(1);
  body->mutable_position()->set_y(10);
  return m;
}

// fx N along x on `body`, for one tick.
inline tumble::v1::ClientMessage force(std::uint64_t id, const std::string& body, double fx) {
  tumble::v1::ClientMessage m;
  m.set_request_id(id);
  m.mutable_apply_force()->mutable_body()->set_name(body);
  m.mutable_apply_force()->mutable_force()->set_x(fx);
  return m;
}

// jx N s along x on `body`.
inline tumble::v1::ClientMessage impulse(std::uint64_t id, const std::string& body, double jx) {
  tumble::v1::ClientMessage m;
  m.set_request_id(id);
  m.mutable_apply_impulse()->mutable_body()->set_name(body);
  m.mutable_apply_impulse()->mutable_impulse()->set_x(jx);
  return m;
}

}  // namespace tumble::test
