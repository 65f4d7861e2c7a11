// nearcap/gl/pipeline.hpp — the fixed-function back end of a GL pipeline in
// software: clipping, perspective divide, viewport, rasterization, depth test
// and stencil, on a framebuffer of one depth buffer, one 8-bit stencil buffer
// and one object-id buffer (the "colour" of the depth pre-pass).
//
// Everything after the vertex stage follows the GL rules as far as they fix
// the result: homogeneous clipping (clipping.hpp), x_w = (x/w + 1) (W/2),
// y_w = (y/w + 1) (H/2), z_w = (z/w) / 2 + 1/2 (glDepthRange(0, 1); z/w with
// the reversed depth mapping's GL_ZERO_TO_ONE), each a
// float32 operation in that order; every fragment's depth is clamped to
// [0, 1] before the test (with depth clamp that is what keeps it in range);
// rasterization by rasterizer.hpp; the depth test compares the fragment's
// depth, converted to the depth buffer's format, with the stored value;
// stencil operations wrap (GL_INCR_WRAP / GL_DECR_WRAP) and are chosen per
// facing (glStencilOpSeparate).  The stencil test itself always passes (the
// shadow passes never mask by stencil).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "nearcap/gl/clipping.hpp"
#include "nearcap/gl/float_transforms.hpp"
#include "nearcap/gl/rasterizer.hpp"
#include "nearcap/gl/shadow_vertex_programs.hpp"
#include "nearcap/named_values.hpp"

namespace nearcap::gl {

enum class DepthFormat {
  Fixed24,  // GL_DEPTH24_STENCIL8: round(z_w * (2^24 - 1))
  Float32,  // GL_DEPTH32F_STENCIL8: z_w as stored float
};
inline constexpr NamedValue<DepthFormat> kDepthFormatTable[] = {
    {DepthFormat::Fixed24, "fixed24", ""},
    {DepthFormat::Float32, "float32", ""},
};
constexpr const auto& named_values(DepthFormat) { return kDepthFormatTable; }
static_assert(names_are_unique<DepthFormat>());
inline std::string_view to_string(DepthFormat f) { return name_of(f); }

enum class CullFace { None, Back, Front };
// Less: the standard depth mapping's test; Greater: the reversed mapping's.
enum class DepthFunc { Always, Less, Greater };
enum class StencilOp { Keep, IncrementWrap, DecrementWrap };

// glStencilOpSeparate(face, GL_KEEP, depth_fail, depth_pass).
struct StencilOps {
  StencilOp depth_fail = StencilOp::Keep;
  StencilOp depth_pass = StencilOp::Keep;
};

// Pixels [x0, x1) x [y0, y1) in GL window coordinates (row 0 at the bottom).
struct PixelRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool empty() const { return x0 >= x1 || y0 >= y1; }
  bool contains(int x, int y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
  bool operator==(const PixelRect& o) const { return x0 == o.x0 && y0 == o.y0 && x1 == o.x1 && y1 == o.y1; }
};

struct DrawState {
  CullFace cull = CullFace::None;
  DepthFunc depth_func = DepthFunc::Less;  // Always: the depth test is disabled
  bool depth_write = false;
  // glClipControl's depth mode, with the matching projection: which clip
  // planes are the near and far ones, and the window depth (float_transforms.hpp).
  DepthMapping depth_mapping = DepthMapping::Standard;
  // GL_DEPTH_CLAMP sets both: no near and no far clipping, depth clamped.
  // GL_AMD_depth_clamp_separate sets one of them (GL_DEPTH_CLAMP_FAR_AMD:
  // clipped at the near plane as usual, clamped at the far one); without
  // it, GL_DEPTH_CLAMP and the other plane as a gl_ClipDistance
  // (one_sided_depth_clamp, below).
  bool depth_clamp_near = false;
  bool depth_clamp_far = false;
  // With the near side clamped, the plane w >= clamp_w_min that keeps the
  // divide's w positive (ClipSettings::w_min).  Camera passes set it to the
  // near plane's w times 1e-5 (shadow_methods.cpp, camera_state: 1e-6 for a
  // near plane at 0.1), so that it cuts only what is nearer the eye than
  // 1/100,000 of the near distance, whatever the scene's unit: a scene
  // scaled by a power of two draws the same frames.  The llvmpipe model's
  // clipper takes 2^-24 of it (clipping.cpp, w_min_of).
  float clamp_w_min = 1e-6f;
  bool clip_far = true;  // false with an infinite far plane (w - z is 0 at infinity)
  // The clipped-sides near cap (near_plane_cap.hpp): its vertices are where
  // the clipper put the sides' near edges, so no near-side plane cuts them
  // again (ClipSettings::skip_near_side) and every one counts as the
  // clipper's own; the real GL draws it with GL_DEPTH_CLAMP.
  bool vertices_on_near_plane = false;
  // ZF+ (near_plane_cap.hpp): its volumes clipped at the far plane first
  // (ClipSettings::far_first), and its far-plane cap, whose vertices are
  // where that stage put the volumes' far edges, not cut at the far plane
  // again (the real GL clips in its own order, and draws the cap with
  // GL_DEPTH_CLAMP).
  bool far_first = false;
  bool vertices_on_far_plane = false;
  StencilOps front, back;
  // Volume culling (volume_bounds.hpp): glScissor's rectangle and
  // glDepthBoundsEXT's range (window depth, inclusive), where set.  A
  // fragment outside either is dropped before the stencil test; the depth
  // bounds test reads the depth stored at the pixel, not the fragment's.
  std::optional<PixelRect> scissor;
  std::optional<std::array<double, 2>> depth_bounds;
  std::int32_t object_id = -1;  // written to the object buffer with the depth, when depth_write
  // The value the frame's stencil buffer holds before its first stencil
  // draw (glClearStencil): 0, or AtomicZP's eye count (eye_count.hpp), set on
  // each of its volume draws so that a replay clears to it.
  std::uint8_t stencil_clear = 0;
};
// Depth clamped at one plane only (near or far), clipped at the other: what
// GL_AMD_depth_clamp_separate does, and what the renderer does without it
// with GL_DEPTH_CLAMP and the other plane as a gl_ClipDistance
// (render/draw_state.hpp; ClipSettings::depth_plane_as_clip_distance).
// Not for the caps whose vertices lie on a plane (drawn with GL_DEPTH_CLAMP).
inline bool one_sided_depth_clamp(const DrawState& s) {
  return s.depth_clamp_near != s.depth_clamp_far && !s.vertices_on_near_plane && !s.vertices_on_far_plane;
}

// One draw call as a GL receives it: the clip-space vertices its vertex
// program wrote (3 per triangle) and the state it was drawn with.  A frame's
// draw calls (ShadowFrame::draws, with EmulationSettings::record_draws) are
// what the real-GL renderer replays (render/gl_frame_replay.hpp).
// Where a vertex program made the clip-space vertices, `vertex_stage` says
// which program, its object-space inputs and uniforms: what a GPU runs to
// build the same vertices itself (render/glsl_shadow_programs.hpp).  Absent
// where the CPU built them (the clipped-sides near cap's fan).
enum class DrawPass { Depth, NearCap, Volume };
// Which part of the shadow volume (shadow_volume_geometry.hpp) a draw's
// inputs are: the mesh itself (depth pre-pass, near-cap pass), the sides
// (quads, 6 vertices each), the corrective quads, the light or dark cap.
enum class GeometryPart { Mesh, Sides, Corrective, LightCap, DarkCap };
struct VertexProgramRun {
  VertexProgram program = VertexProgram::Extrusion;
  GeometryPart part = GeometryPart::Mesh;
  std::vector<ShadowVertex> inputs;  // clip_vertices[k] = run_vertex_program(program, uniforms, inputs[k])
  ShadowUniforms uniforms;
};
struct DrawCall {
  DrawPass pass = DrawPass::Volume;
  std::vector<Vec4f> clip_vertices;
  DrawState state;
  std::optional<VertexProgramRun> vertex_stage;
};

// What a draw call did: primitives in, after clipping and culling, fragments.
struct DrawCounters {
  std::uint64_t triangles = 0;      // submitted
  std::uint64_t clipped = 0;        // entirely clipped away
  std::uint64_t culled = 0;         // culled by facing, or dropped for zero snapped area
  std::uint64_t rasterized = 0;     // triangles (after clipping's fan) that reached coverage
  std::uint64_t in_view = 0;        // of those, the ones whose bounds meet the viewport (the rest cover no pixel)
  std::uint64_t fragments = 0;      // that reached the stencil test
  std::uint64_t bounds_culled = 0;  // dropped by the scissor or depth bounds test
  std::uint64_t depth_passed = 0;   // fragments that passed the depth test (all of them when it is off)
  std::uint64_t depth_failed() const { return fragments - depth_passed; }
  DrawCounters& operator+=(const DrawCounters& o);
};

// A draw call's triangles after vertex post-processing and setup: clipped,
// divided, in window coordinates, the clipped polygons' fans, without the
// pieces of zero snapped area or culled by facing; in submission order.
// What the fragment stage reads, with that stage's counters (triangles,
// clipped, culled, rasterized; no fragments).
struct SetUpTriangles {
  std::vector<std::array<WindowVertex, 3>> triangles;
  DrawCounters counters;
};
// The fragments a set-up draw covers, as the rasterizer emits them, before
// any per-fragment test: per band of rows (Framebuffer's parallel bands), in
// the order each band's triangles emit them, so that each pixel sees its
// fragments in submission order.  Kept by Framebuffer::rasterize when asked;
// Framebuffer::replay applies them again with another state that has the
// same_setup, on a framebuffer of the same size and RasterSettings: the same
// fragments, tests and stencil operations as rasterizing the triangles again.
struct CoveredFragments {
  struct Covered {
    std::uint32_t pixel_and_facing;  // Framebuffer::index, front-facing in the top bit
    float depth;                     // window depth, interpolated as RasterSettings::depth says
  };
  static constexpr std::uint32_t kFront = std::uint32_t{1} << 31;
  std::vector<std::vector<Covered>> bands;
  std::uint64_t in_view = 0;  // DrawCounters::in_view of the draw
  std::size_t size() const;   // fragments, over all bands
};

// Do two states set up the same clip-space vertices alike (same clipping,
// depth mapping and face culling) on one framebuffer size and RasterSettings?
// The rest of a state (depth test and writes, stencil operations, scissor,
// depth bounds, object id) acts on fragments only.
bool same_setup(const DrawState& a, const DrawState& b);

class Framebuffer {
 public:
  Framebuffer(int width, int height, DepthFormat format);

  int width() const { return width_; }
  int height() const { return height_; }
  DepthFormat depth_format() const { return format_; }
  std::size_t index(int i, int j) const { return static_cast<std::size_t>(j) * width_ + i; }

  // glClear of each buffer (depth 1.0 or `value`: 0 for the reversed
  // mapping; stencil 0, object -1).
  void clear_depth(float value = 1.0f);
  void clear_stencil(std::uint8_t value = 0);  // glClearStencil(value), glClear(GL_STENCIL_BUFFER_BIT)
  void clear_objects();

  // The stored depth as a comparable integer: the 24-bit value, or the bits of
  // the non-negative float (whose order is the integers' order).
  std::uint32_t encode_depth(float z_window) const;
  // The same as llvmpipe converts it (RasterSettings::depth Llvmpipe): the
  // 24-bit value by a float32 product rounded to nearest even.
  std::uint32_t encode_depth_llvmpipe(float z_window) const;
  const std::vector<std::uint32_t>& depth() const { return depth_; }
  const std::vector<std::uint8_t>& stencil() const { return stencil_; }
  const std::vector<std::int32_t>& objects() const { return objects_; }
  // Was anything drawn with depth writes on this pixel?
  bool covered(int i, int j) const { return objects_[index(i, j)] >= 0; }

  // Draws triangles given as clip-space vertex triples (3 per triangle).
  // Fragments are processed in horizontal bands on all cores (TBB); each
  // pixel sees its fragments in submission order, as in GL.
  DrawCounters draw(const std::vector<Vec4f>& clip_vertices, const DrawState& state, const RasterSettings& raster);
  // Its two stages: the setup into `out` (replacing its contents), which
  // depends on the framebuffer's size only, and the fragments of set-up
  // triangles (the counters of fragments, depth_passed, bounds_culled).  A
  // draw is the setup, then its fragments with the same state; a setup can be
  // rasterized again with any state that has the same_setup.
  void set_up(const std::vector<Vec4f>& clip_vertices, const DrawState& state, const RasterSettings& raster,
              SetUpTriangles& out) const;
  // `keep`, where given: the fragments covered, for replay(), where they are
  // at most `keep_at_most`; else no bands (keeping stops once past it).
  DrawCounters rasterize(const SetUpTriangles& triangles, const DrawState& state, const RasterSettings& raster,
                         CoveredFragments* keep = nullptr, std::size_t keep_at_most = SIZE_MAX);
  // The fragment stage of a draw whose triangles `rasterize` kept the
  // covered fragments of: its counters (fragments, depth_passed,
  // bounds_culled, in_view) and buffers as rasterizing them with `state`.
  DrawCounters replay(const CoveredFragments& covered, const DrawState& state, const RasterSettings& raster);
  // The same for an indexed draw (glDrawElements): triangle t's corners are
  // vertices[corners[3t]], vertices[corners[3t + 1]] and
  // vertices[corners[3t + 2]].  The triangles and counters of the gathered
  // corners' draw, bit for bit; each vertex's clip code, and its window
  // position and snapping where clipping leaves it as it is, computed once.
  DrawCounters draw(const std::vector<Vec4f>& vertices, const std::vector<std::uint32_t>& corners,
                    const DrawState& state, const RasterSettings& raster);
  void set_up(const std::vector<Vec4f>& vertices, const std::vector<std::uint32_t>& corners, const DrawState& state,
              const RasterSettings& raster, SetUpTriangles& out) const;

 private:
  DrawCounters rasterize_set_up(const SetUpTriangles& triangles, const DrawState& state, const RasterSettings& raster);
  class FragmentStage;
  int width_, height_;
  DepthFormat format_;
  std::vector<std::uint32_t> depth_;
  std::vector<std::uint8_t> stencil_;
  std::vector<std::int32_t> objects_;
};

// The guard band (in NDC units) that keeps snapped window coordinates inside
// the rasterizer's range for this viewport and sub-pixel precision.
float safe_guard_band(int width, int height, int subpixel_bits);

// Perspective divide and viewport transform of one clip-space vertex.  z is
// not clamped here: depth clamp, like the depth range, applies to each
// fragment's interpolated depth (Framebuffer::encode_depth).
WindowVertex to_window(const Vec4f& clip, int width, int height, DepthMapping mapping = DepthMapping::Standard);
// The same with the chosen arithmetic; `from_clipper`: the clipper made this
// vertex (it matters for ViewportArithmetic::Llvmpipe only).
WindowVertex to_window(const Vec4f& clip, int width, int height, ViewportArithmetic arithmetic, bool from_clipper,
                       DepthMapping mapping = DepthMapping::Standard);

}  // namespace nearcap::gl
