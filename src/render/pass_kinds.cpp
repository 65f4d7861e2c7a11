// A lit frame's draws by pass kind, and each draw's work (see pass_kinds.hpp).
#include "nearcap/render/pass_kinds.hpp"

#include "nearcap/error.hpp"

namespace nearcap::render {

gl::PassKind draw_kind(const gl::DrawCall& d) {
  switch (d.pass) {
    case gl::DrawPass::Depth:
      return gl::PassKind::Depth;
    case gl::DrawPass::NearCap:
      return gl::PassKind::NearCap;
    case gl::DrawPass::Volume:
      break;
  }
  // A volume draw the CPU built is ZF+'s far-plane cap: it closes the
  // volume at the far end, as the dark cap does.
  if (!d.vertex_stage) return gl::PassKind::DarkCap;
  switch (d.vertex_stage->part) {
    case gl::GeometryPart::LightCap:
      return gl::PassKind::LightCap;
    case gl::GeometryPart::DarkCap:
      return gl::PassKind::DarkCap;
    case gl::GeometryPart::Sides:
    case gl::GeometryPart::Corrective:
    case gl::GeometryPart::Mesh:
      break;
  }
  return gl::PassKind::Sides;
}

std::vector<gl::DrawCounters> draw_counters(const gl::ShadowFrame& frame, const gl::RasterSettings& raster,
                                            gl::DepthFormat depth) {
  if (frame.draws.empty()) throw Error(ErrorKind::Usage, "counting a frame's draws needs its recorded draws");
  gl::Framebuffer fb(frame.width, frame.height, depth);
  // As the emulation's depth pre-pass clears (shadow_methods.cpp).
  for (const gl::DrawCall& d : frame.draws)
    if (d.pass == gl::DrawPass::Depth) {
      if (d.state.depth_mapping == gl::DepthMapping::Reversed) fb.clear_depth(0.0f);
      break;
    }
  std::vector<gl::DrawCounters> out;
  out.reserve(frame.draws.size());
  for (const gl::DrawCall& d : frame.draws) out.push_back(fb.draw(d.clip_vertices, d.state, raster));
  return out;
}

}  // namespace nearcap::render
