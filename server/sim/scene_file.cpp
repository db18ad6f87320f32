#include "sim/scene_file.h"

#include <cmath>
#include <fstream>
#include <initializer_list>
#include <sstream>

#include <nlohmann/json.hpp>

#include "sim/joint_spec.h"
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

// A JSON number that must be there, as a joint's fields need.
double read_required_number(const json& object, const char* field, const std::string& path) {
  if (!object.contains(field)) fail(path, std::string("missing field '") + field + "'");
  return read_number(object[field], path + "." + field);
}

void read_joint_motor(const json& value, const std::string& path, tumble::v1::JointMotorSpec* motor) {
  require_object(value, path, {"speed", "position", "hertz", "damping_ratio", "max_torque", "max_force"});
  if (value.contains("speed") == value.contains("position")) fail(path, "expected exactly one of speed, position");
  if (value.contains("speed")) motor->set_speed(read_number(value["speed"], path + ".speed"));
  if (value.contains("position")) motor->set_position(read_number(value["position"], path + ".position"));
  if (value.contains("hertz")) motor->set_hertz(read_number(value["hertz"], path + ".hertz"));
  if (value.contains("damping_ratio")) {
    motor->set_damping_ratio(read_number(value["damping_ratio"], path + ".damping_ratio"));
  }
  if (value.contains("max_torque")) motor->set_max_torque(read_number(value["max_torque"], path + ".max_torque"));
  if (value.contains("max_force")) motor->set_max_force(read_number(value["max_force"], path + ".max_force"));
}

// The joint's structure: fields of the right JSON types, the anchors its
// type names. What the numbers mean for the type is judged by
// check_joint_spec and joint_desc_from_spec (sim/joint_spec.h).
void read_joint(const json& value, const std::string& path, tumble::v1::JointSpec* joint) {
  require_object(
      value, path,
      {"name", "type", "body_a", "body_b", "anchor", "anchor_a", "anchor_b", "axis", "limits", "cone_limit", "length",
       "min_length", "max_length", "spring", "motor", "break_force", "break_torque", "collide_connected", "friction"});
  if (value.contains("name")) joint->set_name(read_string(value["name"], path + ".name"));
  if (!value.contains("type")) fail(path, "missing field 'type'");
  const std::string type = read_string(value["type"], path + ".type");
  joint->set_type(joint_type_named(type));
  if (joint->type() == tumble::v1::JOINT_TYPE_UNSPECIFIED) {
    fail(path + ".type",
         "unknown joint type '" + log_text(type) + "'; expected ball, hinge, slider, fixed or distance");
  }
  if (!value.contains("body_a")) fail(path, "missing field 'body_a'");
  if (!value.contains("body_b")) fail(path, "missing field 'body_b'");
  joint->set_body_a(read_string(value["body_a"], path + ".body_a"));
  joint->set_body_b(read_string(value["body_b"], path + ".body_b"));
  if (joint->type() == tumble::v1::JOINT_TYPE_DISTANCE) {
    if (value.contains("anchor")) fail(path + ".anchor", "a distance joint takes anchor_a and anchor_b");
    if (!value.contains("anchor_a")) fail(path, "missing field 'anchor_a'");
    if (!value.contains("anchor_b")) fail(path, "missing field 'anchor_b'");
    read_vec3(value["anchor_a"], path + ".anchor_a", joint->mutable_anchor());
    read_vec3(value["anchor_b"], path + ".anchor_b", joint->mutable_anchor_b());
  } else {
    for (const char* field : {"anchor_a", "anchor_b"}) {
      if (value.contains(field))
        fail(path + "." + field, "only a distance joint has two anchors; this one takes anchor");
    }
    if (value.contains("anchor")) read_vec3(value["anchor"], path + ".anchor", joint->mutable_anchor());
  }
  if (value.contains("axis")) read_vec3(value["axis"], path + ".axis", joint->mutable_axis());
  if (value.contains("limits")) {
    const json& limits = value["limits"];
    const std::string where = path + ".limits";
    if (!limits.is_array() || limits.size() != 2) fail(where, "expected an array of 2 numbers [lower, upper]");
    joint->mutable_limits()->set_lower(read_number(limits[0], where + "[0]"));
    joint->mutable_limits()->set_upper(read_number(limits[1], where + "[1]"));
  }
  if (value.contains("cone_limit")) joint->set_cone_limit(read_number(value["cone_limit"], path + ".cone_limit"));
  if (value.contains("length")) joint->set_length(read_number(value["length"], path + ".length"));
  if (value.contains("min_length")) joint->set_min_length(read_number(value["min_length"], path + ".min_length"));
  if (value.contains("max_length")) joint->set_max_length(read_number(value["max_length"], path + ".max_length"));
  if (value.contains("spring")) {
    const json& spring = value["spring"];
    const std::string where = path + ".spring";
    require_object(spring, where, {"hertz", "damping_ratio"});
    joint->mutable_spring()->set_hertz(read_required_number(spring, "hertz", where));
    if (spring.contains("damping_ratio")) {
      joint->mutable_spring()->set_damping_ratio(read_number(spring["damping_ratio"], where + ".damping_ratio"));
    }
  }
  if (value.contains("motor")) read_joint_motor(value["motor"], path + ".motor", joint->mutable_motor());
  if (value.contains("break_force")) joint->set_break_force(read_number(value["break_force"], path + ".break_force"));
  if (value.contains("break_torque")) {
    joint->set_break_torque(read_number(value["break_torque"], path + ".break_torque"));
  }
  if (value.contains("friction")) joint->set_friction(read_number(value["friction"], path + ".friction"));
  if (value.contains("collide_connected")) {
    joint->set_collide_connected(read_bool(value["collide_connected"], path + ".collide_connected"));
  }
}

void read_scene(const json& value, tumble::v1::Scene* scene) {
  require_object(value, "scene", {"gravity", "bodies", "joints"});
  if (value.contains("gravity")) {
    read_vec3(value["gravity"], "gravity", scene->mutable_gravity());
  } else {
    scene->mutable_gravity()->set_y(-9.81);
  }
  if (value.contains("bodies")) {
    const json& bodies = value["bodies"];
    if (!bodies.is_array()) fail("bodies", "expected an array of bodies");
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      read_body(bodies[i], "bodies[" + std::to_string(i) + "]", scene->add_bodies());
    }
  }
  if (value.contains("joints")) {
    const json& joints = value["joints"];
    if (!joints.is_array()) fail("joints", "expected an array of joints");
    for (std::size_t i = 0; i < joints.size(); ++i) {
      read_joint(joints[i], "joints[" + std::to_string(i) + "]", scene->add_joints());
    }
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
