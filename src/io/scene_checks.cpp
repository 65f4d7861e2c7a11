// Checks shared by the scene reader and SceneBuilder (see scene_checks.hpp).
#include "scene_checks.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include "nearcap/error.hpp"
#include "nearcap/exact/light_validation.hpp"
#include "nearcap/numeric/rational.hpp"

namespace nearcap::scene_checks {

void fail(const std::string& source, ErrorKind kind, const std::string& where, const std::string& what) {
  throw Error(kind, source + ": " + where + ": " + what);
}

bool invertible(const Affine3d& m) {
  Rational a[3][3];
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) a[i][k] = m.rows[i][k];
  const Rational det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                       a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                       a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
  return sgn(det) != 0;
}

void check_frustum(const Frustum& f, const std::string& source, const std::string& where) {
  std::ostringstream s;
  s.precision(17);
  // Finite and within the float32 pipeline's range first: a frustum derived
  // from fovy and a huge near plane can overflow to infinity, and an
  // infinite one passes the ordering tests below.
  const std::pair<const char*, double> values[] = {{"left", f.left}, {"right", f.right}, {"bottom", f.bottom},
                                                   {"top", f.top},   {"near", f.near},   {"far", f.far}};
  for (const auto& [name, v] : values) {
    if (!std::isfinite(v)) {
      s << name << " is " << v << " (not finite)";
      fail(source, ErrorKind::NonFinite, where, s.str());
    }
    if (std::fabs(v) > kFloatPipelineCoordinateLimit) {
      s << name << " (" << v << ") is beyond the float32 pipeline's limit 2^40";
      fail(source, ErrorKind::Range, where, s.str());
    }
    if (v != 0 && std::fabs(v) < static_cast<double>(std::numeric_limits<float>::min())) {
      s << v << " is below float32's smallest normal number (2^-126): the float pipeline would round it to 0";
      fail(source, ErrorKind::Range, where + "." + name, s.str());
    }
  }
  if (!(f.left < f.right)) {
    s << "left (" << f.left << ") must be < right (" << f.right << "): zero-size or inverted frustum";
    fail(source, ErrorKind::Camera, where, s.str());
  }
  if (!(f.bottom < f.top)) {
    s << "bottom (" << f.bottom << ") must be < top (" << f.top << "): zero-size or inverted frustum";
    fail(source, ErrorKind::Camera, where, s.str());
  }
  if (!(f.near > 0)) {
    s << "near (" << f.near << ") must be > 0";
    fail(source, ErrorKind::Camera, where, s.str());
  }
  if (!(f.near < f.far)) {
    s << "near (" << f.near << ") must be < far (" << f.far << ")";
    fail(source, ErrorKind::Camera, where, s.str());
  }
  // Distinct in double but equal in float32: a frustum a GL cannot use.
  if (static_cast<float>(f.left) == static_cast<float>(f.right) ||
      static_cast<float>(f.bottom) == static_cast<float>(f.top) ||
      static_cast<float>(f.near) == static_cast<float>(f.far)) {
    s << "left/right, bottom/top or near/far round to the same float32 value (left " << f.left << ", right " << f.right
      << ", bottom " << f.bottom << ", top " << f.top << ", near " << f.near << ", far " << f.far
      << "): the frustum is degenerate for the float pipeline";
    fail(source, ErrorKind::Range, where, s.str());
  }
}

}  // namespace nearcap::scene_checks
