#include "engine.h"

#include <stdexcept>

namespace tumble::bench {

const std::vector<std::string>& engine_names() {
  static const std::vector<std::string> names = {"tumble", "bullet", "ode"};
  return names;
}

std::unique_ptr<Engine> make_engine(std::string_view name, const Scene& scene, const EngineOptions& options) {
  if (name == "tumble") return make_tumble_engine(scene, options);
  if (name == "bullet") return make_bullet_engine(scene, options);
  if (name == "ode") return make_ode_engine(scene, options);
  throw std::invalid_argument("unknown engine: " + std::string(name));
}

}  // namespace tumble::bench
