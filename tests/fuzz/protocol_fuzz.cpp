// Fuzz target: a sequence of requests from two clients, as the server's
// sessions would hand them to the simulation, run in process (no sockets)
// with passes of the sim loop between them. The input is read front to
// back as operations (layout below); each becomes a well-formed request
// (spawn, forces, torques, impulses, remove, set state, clear, the clock
// requests, list, stats) or a new set of pose streams. Numbers come from a
// table of ordinary and extreme values, so check_request's refusals are
// reached as well as the world.
//
// Checked after every pass, aborting on the first breach:
//   - every body of the world is finite (position, orientation, velocities),
//     and so is every published snapshot;
//   - a world that is paused for a pass steps only while a Step is open,
//     one tick a pass (run_tick());
//   - a Step's Ack adds up: the tick it started at plus the ticks asked is
//     the tick it reached plus the ticks it left;
//   - no request is answered twice, every reply names its request, and at
//     the end (after a last Pause ends any Step) every request has exactly
//     one reply.
//
// Masses are at least 1e-6 kg: smaller ones are the body ranges' to refuse,
// and would only stop the run at the first of them.
//
// Layout: each operation is a header byte, then its arguments. Header: bits
// 0-3 the request (Op), bit 4 the client, bits 5-7 the passes run after it.
// A missing byte reads as 0.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "quiet_logs.h"
#include "sim/request_check.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"

namespace {

using tumble::v1::ClientMessage;
using tumble::v1::ServerMessage;

// The world each input starts from: ground, a box on it, a free ball.
const char* kScene = R"({"gravity": [0, -9.81, 0], "bodies": [
    {"name": "ground", "static": true, "shape": {"plane": {"normal": [0, 1, 0], "offset": 0}}},
    {"name": "crate", "shape": {"box": {"half_extents": [0.5, 0.5, 0.5]}}, "mass": 2, "position": [0, 0.5, 0]},
    {"name": "ball", "shape": {"sphere": {"radius": 0.5}}, "mass": 1, "position": [3, 4, 0]}]})";

// Few enough that a run stays fast; SpawnBody beyond it is refused.
constexpr std::uint32_t kMaxBodies = 48;
constexpr int kMaxOperations = 200;
const char* const kNames[] = {"", "crate", "ball", "a", "b", "123"};

[[noreturn]] void breach(const std::string& what) {
  std::fprintf(stderr, "protocol_fuzz: %s\n", what.c_str());
  std::abort();
}

// The input, read front to back; zeros once it is used up.
class Input {
 public:
  Input(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  bool empty() const { return at_ >= size_; }
  std::uint8_t byte() { return at_ < size_ ? data_[at_++] : 0; }

  // A number: mostly small values in steps of 0.1 around 0, else one of
  // the values where limits and arithmetic break.
  double number() {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    static const double kEdges[] = {
        0,    1e-9,  1e-6,  1e-3,   1e3,    1e6,  1e9,   -1e9,
        1e10, -1e10, 1e300, -1e300, 5e-324, kInf, -kInf, std::numeric_limits<double>::quiet_NaN()};
    const std::uint8_t b = byte();
    if (b < 240) return (static_cast<int>(b) - 120) / 10.0;
    return kEdges[b - 240];
  }
  double positive(const double* table, std::size_t n) { return table[byte() % n]; }

  void vec3(tumble::v1::Vec3* v) {
    v->set_x(number());
    v->set_y(number());
    v->set_z(number());
  }

  // A body: by name from kNames, or by an id near those in use.
  void body_ref(tumble::v1::BodyRef* ref) {
    const std::uint8_t b = byte();
    if (b & 1) {
      ref->set_name(kNames[(b >> 1) % std::size(kNames)]);
    } else {
      ref->set_id(b >> 1);
    }
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t at_ = 0;
};

enum Op : std::uint8_t {
  kSpawn,
  kRemove,
  kForce,
  kTorque,
  kImpulse,
  kSetState,
  kClear,
  kPause,
  kResume,
  kStep,
  kReset,
  kTickRate,
  kList,
  kStats,
  kStreams,
  kNothing,
};

// One spawn: a sphere, box or capsule of a size from a table, dynamic,
// static or kinematic, with a mass of at least 1e-6 kg.
void fill_spawn(Input& in, tumble::v1::BodySpec* body) {
  static const double kSizes[] = {0.01, 0.1, 0.5, 1, 3, 50, 1e-4, 1e4};
  static const double kMasses[] = {1e-6, 1e-3, 0.1, 1, 2, 100, 1e4, 1e9};
  const std::uint8_t shape = in.byte();
  body->set_name(kNames[(shape >> 4) % std::size(kNames)]);
  switch (shape % 3) {
    case 0:
      body->mutable_shape()->mutable_sphere()->set_radius(in.positive(kSizes, std::size(kSizes)));
      break;
    case 1: {
      auto* h = body->mutable_shape()->mutable_box()->mutable_half_extents();
      h->set_x(in.positive(kSizes, std::size(kSizes)));
      h->set_y(in.positive(kSizes, std::size(kSizes)));
      h->set_z(in.positive(kSizes, std::size(kSizes)));
      break;
    }
    default:
      body->mutable_shape()->mutable_capsule()->set_radius(in.positive(kSizes, std::size(kSizes)));
      body->mutable_shape()->mutable_capsule()->set_half_height(in.positive(kSizes, std::size(kSizes)));
      break;
  }
  body->set_motion(static_cast<tumble::v1::Motion>((shape >> 2) % 3));
  body->set_mass(in.positive(kMasses, std::size(kMasses)));
  in.vec3(body->mutable_position());
  if (shape & 0x80) in.vec3(body->mutable_linear_velocity());
  if (shape & 0x40) in.vec3(body->mutable_angular_velocity());
}

// The request of operation `op`, read from the input.
ClientMessage make_request(Op op, Input& in) {
  ClientMessage m;
  switch (op) {
    case kSpawn:
      fill_spawn(in, m.mutable_spawn_body()->mutable_body());
      break;
    case kRemove:
      in.body_ref(m.mutable_remove_body()->mutable_body());
      break;
    case kForce: {
      auto* f = m.mutable_apply_force();
      in.body_ref(f->mutable_body());
      in.vec3(f->mutable_force());
      const std::uint8_t how = in.byte();
      if (how & 1) in.vec3(f->mutable_point());
      if (how & 2) f->set_point_frame(tumble::v1::FRAME_BODY);
      if (how & 4) f->set_persistent(true);
      if (how & 8) f->set_ticks(how >> 4);
      if (how & 16) f->set_seconds(in.number());
      break;
    }
    case kTorque: {
      auto* t = m.mutable_apply_torque();
      in.body_ref(t->mutable_body());
      in.vec3(t->mutable_torque());
      const std::uint8_t how = in.byte();
      if (how & 4) t->set_persistent(true);
      if (how & 8) t->set_ticks(how >> 4);
      break;
    }
    case kImpulse: {
      auto* j = m.mutable_apply_impulse();
      in.body_ref(j->mutable_body());
      in.vec3(j->mutable_impulse());
      if (in.byte() & 1) in.vec3(j->mutable_point());
      break;
    }
    case kSetState: {
      auto* s = m.mutable_set_body_state();
      in.body_ref(s->mutable_body());
      const std::uint8_t parts = in.byte();
      if (parts & 1) in.vec3(s->mutable_position());
      if (parts & 2) {
        auto* q = s->mutable_orientation();
        q->set_w(in.number());
        q->set_x(in.number());
        q->set_y(in.number());
        q->set_z(in.number());
      }
      if (parts & 4) in.vec3(s->mutable_linear_velocity());
      if (parts & 8) in.vec3(s->mutable_angular_velocity());
      break;
    }
    case kClear:
      if (in.byte() & 1) {
        in.body_ref(m.mutable_clear_forces()->mutable_body());
      } else {
        m.mutable_clear_forces();
      }
      break;
    case kPause:
      m.mutable_pause();
      break;
    case kResume:
      m.mutable_resume();
      break;
    case kStep: {
      // Mostly short Steps that finish; sometimes ones only a clock request ends.
      static const std::uint32_t kLong[] = {0, 300000, tumble::sim::kMaxStepTicks, tumble::sim::kMaxStepTicks + 1};
      const std::uint8_t b = in.byte();
      m.mutable_step()->set_ticks(b < 252 ? b % 32 + 1 : kLong[b - 252]);
      break;
    }
    case kReset:
      m.mutable_reset();
      break;
    case kTickRate: {
      static const double kRates[] = {1, 30, 60, 240, 1000, 10000, 0.5, 20000};
      m.mutable_set_tick_rate()->set_rate_hz(in.positive(kRates, std::size(kRates)));
      break;
    }
    case kList:
      m.mutable_list_bodies();
      break;
    default:
      m.mutable_get_stats();
      break;
  }
  return m;
}

bool finite(const tumble::physics::Vec3& v) { return v.allFinite(); }

// The simulation of one input, its two clients' requests and what checks them.
class Run {
 public:
  Run() {
    tumble::v1::Scene scene;
    if (!tumble::sim::parse_scene_json(kScene, &scene).ok()) breach("the scene does not parse");
    tumble::sim::SimConfig config;
    config.max_bodies = kMaxBodies;
    if (!tumble::sim::Simulation::create(scene, config, &sim_).ok()) breach("the scene does not build");
    sim_->add_snapshot_listener([this](std::shared_ptr<const tumble::sim::Snapshot> s) { check_snapshot(*s); });
    sim_->add_event_listener([this](std::shared_ptr<const tumble::sim::WorldEvents> events) {
      for (const auto& event : *events) {
        // An edit applied while running is dated the next tick; a Pause in
        // the same pass keeps the world at the current one, a tick short.
        if (event.tick > sim_->tick() + 1) breach("an event dated past the next tick");
      }
    });
  }

  // Submits `message` from `client` as a session does: checked, refused at
  // once or queued with a reply that is counted.
  void submit(ClientMessage message, int client) {
    const std::uint64_t id = ++last_id_;
    message.set_request_id(id);
    Request& request = requests_[id];
    request.client = client;
    if (message.has_step()) request.step_ticks = message.step().ticks();
    if (auto problem = tumble::sim::check_request(message)) {
      ServerMessage reply;
      reply.mutable_error()->set_request_id(id);
      reply.mutable_error()->set_code(problem->code);
      reply.mutable_error()->set_message(problem->message);
      answer(id, reply);
      return;
    }
    request.queued = true;
    sim_->submit(tumble::sim::Command{std::move(message), [this, id](ServerMessage reply) { answer(id, reply); }});
  }

  // New pose streams: up to three, every body or a few ids, at periods of 1 to 8 ticks.
  void set_streams(Input& in) {
    std::vector<tumble::sim::PublishInterest> interests;
    const std::uint8_t b = in.byte();
    for (int i = 0; i < b % 4; ++i) {
      tumble::sim::PublishInterest interest;
      const std::uint8_t s = in.byte();
      interest.period_ticks = s % 8 + 1;
      interest.all_bodies = (s & 8) != 0;
      if (!interest.all_bodies) {
        for (tumble::physics::BodyId id = 0; id < 8; ++id) {
          if (s & (16 << (id % 4))) interest.bodies.push_back(id + (s & 0x80 ? 4u : 0u));
        }
      }
      interests.push_back(std::move(interest));
    }
    sim_->set_publish_interest(std::move(interests), 4);
    sim_->set_sleep_events_wanted((b & 0x80) != 0);
    if (b & 0x40) sim_->request_snapshot();
  }

  // One pass of the sim loop, then the checks.
  void pass() {
    const std::uint64_t before = sim_->tick();
    // The Steps the pass takes up start at the tick it begins at.
    for (auto& [id, request] : requests_) {
      if (request.queued && request.step_ticks > 0 && !request.taken_up) {
        request.taken_up = true;
        request.step_start = before;
      }
    }
    const bool step_open = open_step();
    sim_->run_tick();
    if (sim_->paused() && sim_->tick() != before) {
      if (!step_open) breach("a paused world stepped with no Step open");
      if (sim_->tick() != before + 1) breach("a paused world stepped more than one tick in a pass");
    }
    check_world();
  }

  // Ends any Step with a Pause and checks that every request has its one reply.
  void finish() {
    submit(make_pause(), 0);
    pass();
    for (const auto& [id, request] : requests_) {
      if (request.replies != 1) {
        breach("client " + std::to_string(request.client) + "'s request " + std::to_string(id) + " has no reply");
      }
    }
  }

 private:
  struct Request {
    int client = 0;
    std::uint32_t step_ticks = 0;  // a Step's
    bool queued = false;           // passed check_request
    bool taken_up = false;         // a pass has begun since it was queued
    std::uint64_t step_start = 0;  // the tick of that pass
    int replies = 0;
  };

  static ClientMessage make_pause() {
    ClientMessage m;
    m.mutable_pause();
    return m;
  }

  bool open_step() const {
    for (const auto& [id, request] : requests_) {
      if (request.queued && request.step_ticks > 0 && request.replies == 0) return true;
    }
    return false;
  }

  void answer(std::uint64_t id, const ServerMessage& reply) {
    Request& request = requests_.at(id);
    if (++request.replies > 1) breach("request " + std::to_string(id) + " answered twice");
    std::uint64_t echoed = 0;
    if (reply.has_ack()) echoed = reply.ack().request_id();
    if (reply.has_error()) echoed = reply.error().request_id();
    if (reply.has_body_list()) echoed = reply.body_list().request_id();
    if (reply.has_stats()) echoed = reply.stats().request_id();
    if (echoed != id) breach("a reply names request " + std::to_string(echoed) + ", not " + std::to_string(id));
    if (request.step_ticks > 0 && reply.has_ack()) {
      const auto& ack = reply.ack();
      if (!ack.has_step_ticks_left() || ack.step_ended_by() == tumble::v1::STEP_END_UNSPECIFIED) {
        breach("a Step's Ack does not say how it ended");
      }
      if (ack.applied_tick() + ack.step_ticks_left() != request.step_start + request.step_ticks) {
        breach("a Step's ticks do not add up");
      }
      if ((ack.step_ticks_left() == 0) != (ack.step_ended_by() == tumble::v1::STEP_END_COMPLETED)) {
        breach("a Step completed with ticks left, or was cut short with none");
      }
    } else if (reply.has_ack() && (reply.ack().has_step_ticks_left() || reply.ack().step_ended_by() != 0)) {
      breach("an Ack that does not answer a Step carries a Step's end");
    }
  }

  void check_world() const {
    const tumble::physics::World& world = sim_->world();
    for (std::size_t i = 0; i < world.body_count(); ++i) {
      const tumble::physics::BodyId id = world.body_id_at(i);
      if (!finite(world.position(id)) || !world.orientation(id).coeffs().allFinite() ||
          !finite(world.linear_velocity(id)) || !finite(world.angular_velocity(id))) {
        breach("body " + std::to_string(id) + " is not finite at tick " + std::to_string(sim_->tick()));
      }
    }
  }

  void check_snapshot(const tumble::sim::Snapshot& s) const {
    if (s.tick != sim_->tick()) breach("a snapshot of another tick than the current one");
    auto all_finite = [](const std::vector<double>& values) {
      for (double v : values) {
        if (!std::isfinite(v)) return false;
      }
      return true;
    };
    if (!all_finite(s.positions) || !all_finite(s.orientations) || !all_finite(s.linear_velocities) ||
        !all_finite(s.angular_velocities)) {
      breach("a snapshot is not finite at tick " + std::to_string(s.tick));
    }
  }

  std::unique_ptr<tumble::sim::Simulation> sim_;
  std::map<std::uint64_t, Request> requests_;
  std::uint64_t last_id_ = 0;
};

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) { return tumble::fuzz::silence_logs(); }

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Input in(data, size);
  Run run;
  for (int n = 0; n < kMaxOperations && !in.empty(); ++n) {
    const std::uint8_t header = in.byte();
    const Op op = static_cast<Op>(header & 0x0f);
    const int client = (header >> 4) & 1;
    if (op == kStreams) {
      run.set_streams(in);
    } else if (op != kNothing) {
      run.submit(make_request(op, in), client);
    }
    for (int i = 0; i < (header >> 5); ++i) run.pass();
  }
  run.finish();
  return 0;
}
