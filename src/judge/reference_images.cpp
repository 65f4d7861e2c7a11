// The per-pixel reference as PGM counts and a shaded PNG.
#include "nearcap/judge/reference_images.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "nearcap/io/image_io.hpp"

namespace nearcap {
namespace {

std::vector<std::uint16_t> flip_to_top_first(const PixelReference& ref, const std::vector<std::uint32_t>& plane) {
  std::vector<std::uint16_t> out(plane.size());
  for (int j = 0; j < ref.height; ++j)
    for (int i = 0; i < ref.width; ++i) {
      const std::uint32_t v = plane[ref.index(i, j)];
      const std::size_t row = static_cast<std::size_t>(ref.height - 1 - j);
      out[row * ref.width + i] = v == PixelReference::kNothingSeen
                                     ? kPgmNothingSeen
                                     : static_cast<std::uint16_t>(std::min<std::uint32_t>(v, kPgmSaturated));
    }
  return out;
}

Vec3d normalized(const Vec3d& v) {
  const double n = std::sqrt(dot(v, v));
  return n > 0 ? Vec3d{v.x / n, v.y / n, v.z / n} : Vec3d{0, 0, 0};
}

}  // namespace

std::string cap_pgm(const PixelReference& ref) {
  return encode_pgm16(ref.width, ref.height, flip_to_top_first(ref, ref.cap));
}
std::string stencil_pgm(const PixelReference& ref) {
  return encode_pgm16(ref.width, ref.height, flip_to_top_first(ref, ref.stencil));
}

std::vector<std::uint8_t> shadow_rgb(const CameraSpaceScene& cs, const PixelReference& ref) {
  static constexpr std::array<std::array<double, 3>, 6> kPalette{{{0.85, 0.80, 0.70},
                                                                  {0.80, 0.45, 0.30},
                                                                  {0.35, 0.60, 0.80},
                                                                  {0.55, 0.75, 0.40},
                                                                  {0.75, 0.55, 0.80},
                                                                  {0.90, 0.75, 0.35}}};
  const BoundedVec3& lb = cs.light(ref.light);
  const Vec3d l{lb.x.v, lb.y.v, lb.z.v};
  const Frustum& fr = cs.frustum();
  std::vector<std::uint8_t> rgb(3 * static_cast<std::size_t>(ref.width) * ref.height);
  for (int j = 0; j < ref.height; ++j)
    for (int i = 0; i < ref.width; ++i) {
      const std::size_t k = ref.index(i, j);
      std::array<double, 3> c{0.10, 0.12, 0.18};  // background
      if (ref.stencil[k] != PixelReference::kNothingSeen) {
        const auto o = static_cast<std::size_t>(ref.object[k]);
        const auto& t = cs.mesh(o).triangles[ref.face[k]];
        const Vec3d a = cs.vertex_estimate(o, t[0]), b = cs.vertex_estimate(o, t[1]), cc = cs.vertex_estimate(o, t[2]);
        Vec3d n = normalized(cross(b - a, cc - a));
        // The visible point, for the light direction (estimate: shading only).
        const Vec3d p{fr.left + (i + 0.5) / ref.width * (fr.right - fr.left),
                      fr.bottom + (j + 0.5) / ref.height * (fr.top - fr.bottom), -fr.near};
        const double np = dot(n, p);
        const double tq = np != 0 ? dot(n, a) / np : 1.0;
        const Vec3d q{tq * p.x, tq * p.y, tq * p.z};
        if (dot(n, q) > 0) n = Vec3d{-n.x, -n.y, -n.z};  // face the viewer
        const double lambert = std::max(0.0, dot(n, normalized(l - q)));
        const bool shadowed = ref.stencil[k] > 0;
        const double light = 0.25 + (shadowed ? 0.0 : 0.75 * lambert);
        const auto& base = kPalette[o % kPalette.size()];
        for (int ch = 0; ch < 3; ++ch) c[ch] = base[ch] * light;
      }
      const std::size_t row = static_cast<std::size_t>(ref.height - 1 - j);
      for (int ch = 0; ch < 3; ++ch)
        rgb[3 * (row * ref.width + i) + ch] =
            static_cast<std::uint8_t>(std::lround(std::clamp(c[ch], 0.0, 1.0) * 255.0));
    }
  return rgb;
}

std::string shadow_png(const CameraSpaceScene& cs, const PixelReference& ref) {
  return encode_png_rgb(ref.width, ref.height, shadow_rgb(cs, ref));
}

}  // namespace nearcap
