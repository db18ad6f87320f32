#include "sim/scene_file.h"

#include <cmath>
#include <fstream>
#include <initializer_list>
#include <sstream>

#include <nlohmann/json.hpp>

#include "sim/log_text.h"

namespace tumble::sim {
namespace {

using nlohmann::json;

// Thrown inside this file only, to unwind a failed parse; the public
// functions turn it into a Status.
struct SceneError {
  std::string message;
};

[[noreturn]] void fail(const std::string& path, const std::string& what) { throw SceneError{path + ": " + what}; }

void require_object(const json& value, const std::string& path, std::initializer_list<std::string_view> known_fields) {
  if (!value.is_object()) fail(path, "expected an object");
  for (const auto& item : value.items()) {
    bool known = false;
    for (std::string_view field : known_fields) known = known || item.key() == field;
    if (!known) fail(path, "unknown field '" + log_text(item.key()) + "'");
  }
}

double read_number(const json& value, const std::string& path) {
  if (!value.is_number()) fail(path, "expected a number");
  const double number = value.get<double>();
  if (!std::isfinite(number)) fail(path, "expected a finite number");
  return number;
}

bool read_bool(const json& value, const std::string& path) {
  if (!value.is_boolean()) fail(path, "expected true or false");
  return value.get<bool>();
}

std::string read_string(const json& value, const std::string& path) {
  if (!value.is_string()) fail(path, "expected a string");
  return value.get<std::string>();
}

void read_vec3(const json& value, const std::string& path, tumble::v1::Vec3* out) {
  if (!value.is_array() || value.size() != 3) fail(path, "expected an array of 3 numbers [x, y, z]");
  out->set_x(read_number(value[0], path + "[0]"));
  out->set_y(read_number(value[1], path + "[1]"));
  out->set_z(read_number(value[2], path + "[2]"));
}

void read_quat(const json& value, const std::string& path, tumble::v1::Quat* out) {
  if (!value.is_array() || value.size() != 4) fail(path, "expected an array of 4 numbers [w, x, y, z]");
  out->set_w(read_number(value[0], path + "[0]"));
  out->set_x(read_number(value[1], path + "[1]"));
  out->set_y(read_number(value[2], path + "[2]"));
  out->set_z(read_number(value[3], path + "[3]"));
}

void read_shape(const json& value, const std::string& path, tumble::v1::Shape* shape) {
  require_object(value, path, {"box", "sphere", "capsule", "points", "plane", "convex"});
  if (value.size() != 1) fail(path, "expected exactly one of box, sphere, capsule, points, plane, convex");
  // The object's only member. Not `*value.items().begin()`: that is a
  // reference to a temporary iterator, dead before its key is read.
  const auto member = value.begin();
  const std::string& kind = member.key();
  const json& body = member.value();
  const std::string where = path + "." + kind;
  if (kind == "box") {
    require_object(body, where, {"half_extents"});
    if (!body.contains("half_extents")) fail(where, "missing field 'half_extents'");
    read_vec3(body["half_extents"], where + ".half_extents", shape->mutable_box()->mutable_half_extents());
  } else if (kind == "sphere") {
    require_object(body, where, {"radius"});
    if (!body.contains("radius")) fail(where, "missing field 'radius'");
    shape->mutable_sphere()->set_radius(read_number(body["radius"], where + ".radius"));
  } else if (kind == "capsule") {
    require_object(body, where, {"radius", "half_height"});
    if (!body.contains("radius")) fail(where, "missing field 'radius'");
    if (!body.contains("half_height")) fail(where, "missing field 'half_height'");
    auto* capsule = shape->mutable_capsule();
    capsule->set_radius(read_number(body["radius"], where + ".radius"));
    capsule->set_half_height(read_number(body["half_height"], where + ".half_height"));
  } else if (kind == "plane") {
    require_object(body, where, {"normal", "offset"});
    auto* plane = shape->mutable_plane();
    if (body.contains("normal")) {
      read_vec3(body["normal"], where + ".normal", plane->mutable_normal());
    }
    if (body.contains("offset")) plane->set_offset(read_number(body["offset"], where + ".offset"));
  } else if (kind == "convex") {
    require_object(body, where, {"points"});
    if (!body.contains("points")) fail(where, "missing field 'points'");
    const json& points = body["points"];
    if (!points.is_array()) fail(where + ".points", "expected an array of [x, y, z] arrays");
    auto* convex = shape->mutable_convex();
    for (std::size_t i = 0; i < points.size(); ++i) {
      read_vec3(points[i], where + ".points[" + std::to_string(i) + "]", convex->add_points());
    }
  } else {
    require_object(body, where, {"masses", "positions"});
    const json& masses = body.contains("masses") ? body["masses"] : json();
    const json& positions = body.contains("positions") ? body["positions"] : json();
    if (!masses.is_array()) fail(where + ".masses", "expected an array of numbers");
    if (!positions.is_array()) fail(where + ".positions", "expected an array of [x, y, z] arrays");
    if (masses.size() != positions.size()) {
      fail(where, "masses has " + std::to_string(masses.size()) + " entries but positions has " +
                      std::to_string(positions.size()));
    }
    auto* points = shape->mutable_points();
    for (std::size_t i = 0; i < masses.size(); ++i) {
      const std::string index = "[" + std::to_string(i) + "]";
      points->add_masses(read_number(masses[i], where + ".masses" + index));
      read_vec3(positions[i], where + ".positions" + index, points->add_positions());
    }
  }
}

void read_body(const json& value, const std::string& path, tumble::v1::BodySpec* body) {
  require_object(value, path,
                 {"name", "shape", "mass", "position", "orientation", "linear_velocity", "angular_velocity", "static",
                  "kinematic", "friction", "restitution"});
  if (value.contains("name")) body->set_name(read_string(value["name"], path + ".name"));
  const bool is_static = value.contains("static") && read_bool(value["static"], path + ".static");
  const bool is_kinematic = value.contains("kinematic") && read_bool(value["kinematic"], path + ".kinematic");
  if (is_static && is_kinematic) fail(path, "a body cannot be both static and kinematic");
  if (is_static) body->set_motion(tumble::v1::MOTION_STATIC);
  if (is_kinematic) body->set_motion(tumble::v1::MOTION_KINEMATIC);
  if (value.contains("friction")) body->set_friction(read_number(value["friction"], path + ".friction"));
  if (value.contains("restitution")) body->set_restitution(read_number(value["restitution"], path + ".restitution"));
  if (!value.contains("shape")) fail(path, "missing field 'shape'");
  read_shape(value["shape"], path + ".shape", body->mutable_shape());
  if (value.contains("mass")) body->set_mass(read_number(value["mass"], path + ".mass"));
  if (value.contains("position")) read_vec3(value["position"], path + ".position", body->mutable_position());
  if (value.contains("orientation")) {
    read_quat(value["orientation"], path + ".orientation", body->mutable_orientation());
  }
  if (value.contains("linear_velocity")) {
    read_vec3(value["linear_velocity"], path + ".linear_velocity", body->mutable_linear_velocity());
  }
  if (value.contains("angular_velocity")) {
    read_vec3(value["angular_velocity"], path + ".angular_velocity", body->mutable_angular_velocity());
  }
}

void read_scene(const json& value, tumble::v1::Scene* scene) {
  require_object(value, "scene", {"gravity", "bodies"});
  if (value.contains("gravity")) {
    read_vec3(value["gravity"], "gravity", scene->mutable_gravity());
  } else {
    scene->mutable_gravity()->set_y(-9.81);
  }
  if (!value.contains("bodies")) return;
  const json& bodies = value["bodies"];
  if (!bodies.is_array()) fail("bodies", "expected an array of bodies");
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    read_body(bodies[i], "bodies[" + std::to_string(i) + "]", scene->add_bodies());
  }
}

}  // namespace

Status parse_scene_json(std::string_view text, tumble::v1::Scene* scene) {
  scene->Clear();
  try {
    const json document = json::parse(text, nullptr, /*allow_exceptions=*/true, /*ignore_comments=*/true);
    read_scene(document, scene);
  } catch (const json::exception& error) {
    // what() reads "[json.exception.parse_error.101] parse error at line L, column C: ...", or for a
    // number beyond a double, "[json.exception.out_of_range.406] number overflow parsing '1e400'".
    const std::string what = error.what();
    const std::size_t start = what.find("] ");
    return Status::error("not valid JSON: " + (start == std::string::npos ? what : what.substr(start + 2)));
  } catch (const SceneError& error) {
    return Status::error(error.message);
  }
  return {};
}

Status load_scene_file(const std::string& path, tumble::v1::Scene* scene) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return Status::error(path + ": cannot open the file");
  std::ostringstream text;
  text << file.rdbuf();
  Status status = parse_scene_json(text.str(), scene);
  if (!status.ok()) return Status::error(path + ": " + status.message());
  return {};
}

}  // namespace tumble::sim
