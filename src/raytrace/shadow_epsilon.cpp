// The shadow epsilon's names (shadow_ray_tracer.hpp).
#include "nearcap/raytrace/shadow_ray_tracer.hpp"

namespace nearcap::raytrace {

std::string_view to_string(ShadowEpsilon e) {
  switch (e) {
    case ShadowEpsilon::Fixed:
      return "fixed";
    case ShadowEpsilon::Relative:
      return "relative";
    case ShadowEpsilon::PrimitiveId:
      return "primitive-id";
  }
  return "?";
}

std::optional<ShadowEpsilon> shadow_epsilon_from_string(std::string_view name) {
  for (ShadowEpsilon e : {ShadowEpsilon::Fixed, ShadowEpsilon::Relative, ShadowEpsilon::PrimitiveId})
    if (to_string(e) == name) return e;
  return std::nullopt;
}

}  // namespace nearcap::raytrace
