// Scene files: JSON documents with the fields of tumble.v1.Scene, vectors
// written as arrays ([x, y, z], quaternions [w, x, y, z]). Parsing is strict:
// an unknown field, a wrong type or a missing required value is an error
// that names the field by its path, e.g. "bodies[2].shape.box.half_extents".
//
// Defaults for missing fields: gravity [0, -9.81, 0], orientation identity,
// velocities zero. Physical validity (positive mass, sizes) is checked by
// body_desc_from_spec, not here.
#pragma once

#include <string>
#include <string_view>

#include "sim/status.h"
#include "tumble/v1/scene.pb.h"

namespace tumble::sim {

// Parses JSON `text` into `scene`.
Status parse_scene_json(std::string_view text, tumble::v1::Scene* scene);

// Reads and parses the file at `path`; errors start with the path.
Status load_scene_file(const std::string& path, tumble::v1::Scene* scene);

}  // namespace tumble::sim
