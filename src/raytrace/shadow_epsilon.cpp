// The shadow epsilon's names, from its table (shadow_ray_tracer.hpp).
#include "nearcap/raytrace/shadow_ray_tracer.hpp"

namespace nearcap::raytrace {

std::string_view to_string(ShadowEpsilon e) { return name_of(e); }

std::optional<ShadowEpsilon> shadow_epsilon_from_string(std::string_view name) {
  return value_named<ShadowEpsilon>(name);
}

}  // namespace nearcap::raytrace
