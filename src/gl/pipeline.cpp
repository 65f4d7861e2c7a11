// The software GL back end (see pipeline.hpp).
#include "nearcap/gl/pipeline.hpp"

#include "nearcap/error.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <functional>
#include <memory>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

namespace nearcap::gl {
namespace {

std::uint8_t apply(StencilOp op, std::uint8_t s) {
  switch (op) {
    case StencilOp::Keep:
      return s;
    case StencilOp::IncrementWrap:
      return static_cast<std::uint8_t>(s + 1);
    case StencilOp::DecrementWrap:
      return static_cast<std::uint8_t>(s - 1);
  }
  return s;
}

bool culled(CullFace cull, bool front) {
  return (cull == CullFace::Back && !front) || (cull == CullFace::Front && front);
}

// A draw's large working buffers (its set-up triangles, their bins by
// band): each thread keeps the last draw's for its next one, so that a
// frame's draws of a large mesh reuse memory instead of allocating (and
// faulting in) buffers of its size every time.  A draw takes the thread's
// buffer out and gives it back when done: a draw nested in it (TBB running
// another task on this thread while the bands are drawn) finds none and
// makes its own.
template <class Buffer>
std::unique_ptr<Buffer>& spare_buffer() {
  thread_local std::unique_ptr<Buffer> spare;
  return spare;
}
template <class Buffer>
std::unique_ptr<Buffer> take_buffer() {
  std::unique_ptr<Buffer> b = std::move(spare_buffer<Buffer>());
  if (!b) b = std::make_unique<Buffer>();
  return b;
}
template <class Buffer>
void give_back(std::unique_ptr<Buffer> b) {
  spare_buffer<Buffer>() = std::move(b);
}
using Bins = std::vector<std::vector<std::uint32_t>>;

}  // namespace

DrawCounters& DrawCounters::operator+=(const DrawCounters& o) {
  triangles += o.triangles;
  clipped += o.clipped;
  culled += o.culled;
  rasterized += o.rasterized;
  in_view += o.in_view;
  fragments += o.fragments;
  bounds_culled += o.bounds_culled;
  depth_passed += o.depth_passed;
  return *this;
}

Framebuffer::Framebuffer(int width, int height, DepthFormat format)
    : width_(width),
      height_(height),
      format_(format),
      depth_(static_cast<std::size_t>(width) * height),
      stencil_(depth_.size()),
      objects_(depth_.size()) {
  clear_depth();
  clear_stencil();
  clear_objects();
}

void Framebuffer::clear_depth(float value) { std::fill(depth_.begin(), depth_.end(), encode_depth(value)); }
void Framebuffer::clear_stencil(std::uint8_t value) { std::fill(stencil_.begin(), stencil_.end(), value); }
void Framebuffer::clear_objects() { std::fill(objects_.begin(), objects_.end(), -1); }

std::uint32_t Framebuffer::encode_depth(float z) const {
  z = std::clamp(z, 0.0f, 1.0f);  // GL clamps the fragment depth to the depth range before conversion
  if (format_ == DepthFormat::Fixed24) return static_cast<std::uint32_t>(std::lrint(double{z} * 16777215.0));
  std::uint32_t bits;
  std::memcpy(&bits, &z, sizeof bits);
  return bits;
}

std::uint32_t Framebuffer::encode_depth_llvmpipe(float z) const {
  if (format_ != DepthFormat::Fixed24) return encode_depth(z);
  // lp_build_clamped_float_to_unsigned_norm: a float32 product, rounded to nearest even.
  return static_cast<std::uint32_t>(std::nearbyintf(std::clamp(z, 0.0f, 1.0f) * 16777215.0f));
}

float safe_guard_band(int width, int height, int subpixel_bits) {
  // |x_w| <= (g + 1) W / 2 must stay below 2^30 / 2^bits, with a factor 2 of margin.
  const double limit = std::ldexp(1.0, 29 - subpixel_bits);
  const double g = limit / (0.5 * std::max(width, height)) - 1.0;
  return static_cast<float>(std::min(8192.0, std::max(1.0, std::floor(g))));
}

WindowVertex to_window(const Vec4f& c, int width, int height, DepthMapping mapping) {
  const float x = c.x / c.w, y = c.y / c.w, z = c.z / c.w;
  const float half_w = 0.5f * static_cast<float>(width), half_h = 0.5f * static_cast<float>(height);
  // GL_ZERO_TO_ONE's depth viewport scale 1 and offset 0: z/w itself.
  return {(x + 1.0f) * half_w, (y + 1.0f) * half_h, mapping == DepthMapping::Standard ? z * 0.5f + 0.5f : z};
}

WindowVertex to_window(const Vec4f& c, int width, int height, ViewportArithmetic arithmetic, bool from_clipper,
                       DepthMapping mapping) {
  if (arithmetic == ViewportArithmetic::Divide) return to_window(c, width, height, mapping);
  const float r = 1.0f / c.w;
  const float half_w = 0.5f * static_cast<float>(width), half_h = 0.5f * static_cast<float>(height);
  const float x = c.x * r, y = c.y * r, z = c.z * r;
  const bool standard = mapping == DepthMapping::Standard;
  if (from_clipper) return {x * half_w + half_w, y * half_h + half_h, standard ? z * 0.5f + 0.5f : z};
  return {std::fma(x, half_w, half_w), std::fma(y, half_h, half_h), standard ? std::fma(z, 0.5f, 0.5f) : z};
}

bool same_setup(const DrawState& a, const DrawState& b) {
  return a.cull == b.cull && a.depth_mapping == b.depth_mapping && a.depth_clamp_near == b.depth_clamp_near &&
         a.depth_clamp_far == b.depth_clamp_far && a.clip_far == b.clip_far &&
         a.vertices_on_near_plane == b.vertices_on_near_plane && a.far_first == b.far_first &&
         a.vertices_on_far_plane == b.vertices_on_far_plane && a.clamp_w_min == b.clamp_w_min;
}

DrawCounters Framebuffer::draw(const std::vector<Vec4f>& clip_vertices, const DrawState& state,
                               const RasterSettings& raster) {
  std::unique_ptr<SetUpTriangles> triangles = take_buffer<SetUpTriangles>();
  set_up(clip_vertices, state, raster, *triangles);
  const DrawCounters counters = rasterize_set_up(*triangles, state, raster);
  give_back(std::move(triangles));
  return counters;
}

DrawCounters Framebuffer::draw(const std::vector<Vec4f>& vertices, const std::vector<std::uint32_t>& corners,
                               const DrawState& state, const RasterSettings& raster) {
  std::unique_ptr<SetUpTriangles> triangles = take_buffer<SetUpTriangles>();
  set_up(vertices, corners, state, raster, *triangles);
  const DrawCounters counters = rasterize_set_up(*triangles, state, raster);
  give_back(std::move(triangles));
  return counters;
}

DrawCounters Framebuffer::rasterize_set_up(const SetUpTriangles& triangles, const DrawState& state,
                                           const RasterSettings& raster) {
  DrawCounters counters = triangles.counters;
  const DrawCounters fragments = rasterize(triangles, state, raster);
  counters.fragments = fragments.fragments;
  counters.depth_passed = fragments.depth_passed;
  counters.bounds_culled = fragments.bounds_culled;
  counters.in_view = fragments.in_view;
  return counters;
}

namespace {

// A draw's vertex post-processing and setup (Framebuffer::set_up): each
// triangle clipped, its polygon divided and mapped to the viewport, drawn as
// a fan whose pieces of zero snapped area or culled by facing are dropped;
// in submission order.
class TriangleSetUp {
 public:
  TriangleSetUp(int width, int height, const DrawState& state, const RasterSettings& raster, SetUpTriangles& out)
      : width_(width),
        height_(height),
        state_(state),
        raster_(raster),
        clipper_(clip_settings(width, height, state, raster)),
        // |x_w| <= 2^(29 - bits) by the guard band's bound; the rasterizer's
        // snapping holds up to 2^(30 - bits).
        max_window_(static_cast<float>(std::ldexp(1.5, 29 - raster.subpixel_bits))),
        out_(out) {
    out_.counters = {};
    out_.triangles.clear();
  }

  // What the setup of an indexed draw computes once per vertex: its clip
  // code, and for a vertex inside every plane (which clipping passes on
  // unchanged) its window position, whether that is in range and its
  // snapped position.
  struct Vertex {
    TriangleClipper::VertexCode code;
    bool in_range = false;
    WindowVertex window;
    detail::FixedPoint snapped{0, 0};
  };
  Vertex vertex(const Vec4f& v) const {
    Vertex out;
    out.code = clipper_.code(v);
    if (!out.code.inside) return out;
    out.window = to_window(v, width_, height_, raster_.viewport, false, state_.depth_mapping);
    out.in_range = in_range(out.window);
    if (out.in_range) out.snapped = detail::snap(out.window, raster_.subpixel_bits);
    return out;
  }

  // Triangle (a, b, c).
  void add(const Vec4f& a, const Vec4f& b, const Vec4f& c) {
    ++out_.counters.triangles;
    clipper_.clip(a, b, c, polygon_);
    add_polygon(a, b, c);
  }
  // The same from its vertices' vertex(): the same triangles.
  void add(const Vec4f& a, const Vec4f& b, const Vec4f& c, const Vertex& va, const Vertex& vb, const Vertex& vc) {
    ++out_.counters.triangles;
    if (!(va.code.inside && vb.code.inside && vc.code.inside)) {
      clipper_.clip(a, b, c, va.code, vb.code, vc.code, polygon_);
      add_polygon(a, b, c);
      return;
    }
    // Unclipped: the triangle itself, its vertices the vertex stage's.
    const std::array<const Vertex*, 3> v{&va, &vb, &vc};
    const std::array<const Vec4f*, 3> clip{&a, &b, &c};
    for (std::size_t k = 0; k < 3; ++k)
      if (!v[k]->in_range) throw_out_of_range(v[k]->window, *clip[k]);
    const std::int64_t area = (vb.snapped.x - va.snapped.x) * (vc.snapped.y - va.snapped.y) -
                              (vc.snapped.x - va.snapped.x) * (vb.snapped.y - va.snapped.y);
    if (area == 0 || culled(state_.cull, area > 0)) {
      ++out_.counters.culled;
      return;
    }
    out_.triangles.push_back({va.window, vb.window, vc.window});
  }

  void finish() { out_.counters.rasterized = out_.triangles.size(); }

 private:
  static ClipSettings clip_settings(int width, int height, const DrawState& state, const RasterSettings& raster) {
    ClipSettings clip;
    clip.clip_near = !state.depth_clamp_near;
    clip.w_min = state.clamp_w_min;
    clip.clip_far = state.clip_far && !state.depth_clamp_far && !state.vertices_on_far_plane;
    clip.skip_near_side = state.vertices_on_near_plane;
    clip.far_first = state.far_first || state.vertices_on_far_plane;
    clip.depth_mapping = state.depth_mapping;
    clip.mesa = raster.mesa_clipper;
    // One depth side clamped: drawn on llvmpipe (no GL_AMD_depth_clamp_separate)
    // with GL_DEPTH_CLAMP and the other plane as a gl_ClipDistance.
    clip.depth_plane_as_clip_distance = one_sided_depth_clamp(state);
    clip.guard_band = std::min(raster.guard_band, safe_guard_band(width, height, raster.subpixel_bits));
    return clip;
  }

  // After clipping every vertex lies within the guard band; only a
  // degenerate homogeneous vertex ((0, 0, 0, 0): an extrusion whose
  // direction rounded to zero) can leave it.  Refused, never rasterized.
  bool in_range(const WindowVertex& w) const {
    return std::fabs(w.x) < max_window_ && std::fabs(w.y) < max_window_ && std::isfinite(w.z);
  }
  [[noreturn]] static void throw_out_of_range(const WindowVertex& w, const Vec4f& clip) {
    throw Error(ErrorKind::Range, "float pipeline: a clipped vertex has window coordinates (" + std::to_string(w.x) +
                                      ", " + std::to_string(w.y) + ", " + std::to_string(w.z) +
                                      ") (clip-space w = " + std::to_string(clip.w) +
                                      "): the float32 transforms of this scene are degenerate");
  }

  // The clipper's polygon_ of triangle (a, b, c).
  void add_polygon(const Vec4f& a, const Vec4f& b, const Vec4f& c) {
    if (polygon_.empty()) {
      ++out_.counters.clipped;
      return;
    }
    const std::array<const Vec4f*, 3> input{&a, &b, &c};
    window_.resize(polygon_.size());
    for (std::size_t k = 0; k < polygon_.size(); ++k) {
      // A vertex of the input triangle comes back from the clipper unchanged
      // (bit for bit); any other is one it made.
      // Only Mesa's arithmetic tells the two apart.
      const Vec4f& v = polygon_[k];
      bool original = raster_.viewport == ViewportArithmetic::Divide || state_.vertices_on_near_plane ||
                      state_.vertices_on_far_plane;
      for (std::size_t i = 0; i < 3 && !original; ++i) original = std::memcmp(input[i], &v, sizeof(Vec4f)) == 0;
      window_[k] = to_window(v, width_, height_, raster_.viewport, !original, state_.depth_mapping);
      if (!in_range(window_[k])) throw_out_of_range(window_[k], v);
    }
    // The clipped polygon is drawn as a fan from its first vertex, as Mesa's
    // clipper emits it; every piece has the facing of the whole.
    bool clipped_here = polygon_.size() != 3;
    for (std::size_t k = 0; k < 3 && !clipped_here; ++k)
      clipped_here = std::memcmp(&polygon_[k], input[k], sizeof(Vec4f)) != 0;
    for (std::size_t k = 1; k + 1 < window_.size(); ++k) {
      std::array<WindowVertex, 3> tri{window_[0], window_[k], window_[k + 1]};
      if (raster_.mesa_clipper && clipped_here) tri = {window_[k], window_[k + 1], window_[0]};
      const int orientation = snapped_orientation(tri, raster_.subpixel_bits);
      if (orientation == 0 || culled(state_.cull, orientation > 0)) {
        ++out_.counters.culled;
        continue;
      }
      out_.triangles.push_back(tri);
    }
  }

  int width_, height_;
  const DrawState& state_;
  const RasterSettings& raster_;
  TriangleClipper clipper_;
  float max_window_;
  SetUpTriangles& out_;
  std::vector<Vec4f> polygon_;
  std::vector<WindowVertex> window_;
};

// An indexed draw's per-vertex setup, kept per thread with its capacity.
using IndexedVertices = std::vector<TriangleSetUp::Vertex>;

}  // namespace

void Framebuffer::set_up(const std::vector<Vec4f>& clip_vertices, const DrawState& state, const RasterSettings& raster,
                         SetUpTriangles& out) const {
  TriangleSetUp setup(width_, height_, state, raster, out);
  for (std::size_t t = 0; t + 2 < clip_vertices.size(); t += 3)
    setup.add(clip_vertices[t], clip_vertices[t + 1], clip_vertices[t + 2]);
  setup.finish();
}

void Framebuffer::set_up(const std::vector<Vec4f>& vertices, const std::vector<std::uint32_t>& corners,
                         const DrawState& state, const RasterSettings& raster, SetUpTriangles& out) const {
  TriangleSetUp setup(width_, height_, state, raster, out);
  std::unique_ptr<IndexedVertices> buffer = take_buffer<IndexedVertices>();
  std::vector<TriangleSetUp::Vertex>& coded = *buffer;
  coded.resize(vertices.size());
  for (std::size_t v = 0; v < vertices.size(); ++v) coded[v] = setup.vertex(vertices[v]);
  for (std::size_t t = 0; t + 2 < corners.size(); t += 3) {
    const std::uint32_t a = corners[t], b = corners[t + 1], c = corners[t + 2];
    NEARCAP_CHECK(a < vertices.size() && b < vertices.size() && c < vertices.size());
    setup.add(vertices[a], vertices[b], vertices[c], coded[a], coded[b], coded[c]);
  }
  setup.finish();
  give_back(std::move(buffer));
}

std::size_t CoveredFragments::size() const {
  std::size_t n = 0;
  for (const std::vector<Covered>& band : bands) n += band.size();
  return n;
}

namespace {

constexpr int kBandRows = 32;  // rows per band of the parallel fragment stage

using FragmentCounts = std::array<std::uint64_t, 3>;  // fragments, depth test passed, dropped by the bounds

}  // namespace

// What happens to one fragment under a draw's state: volume culling, the
// depth test, the stencil operation, depth and object writes.
class Framebuffer::FragmentStage {
 public:
  FragmentStage(Framebuffer& fb, const DrawState& state, const RasterSettings& raster)
      : fb_(fb),
        state_(state),
        test_depth_(state.depth_func != DepthFunc::Always),
        greater_(state.depth_func == DepthFunc::Greater),
        needs_depth_(test_depth_ || state.depth_write),
        llvmpipe_depth_(raster.depth == DepthInterpolation::Llvmpipe),
        scissor_(state.scissor.has_value()),
        rect_(scissor_ ? *state.scissor : PixelRect{0, 0, fb.width_, fb.height_}),
        depth_bounds_(state.depth_bounds.has_value()),
        bounds_(depth_bounds_ ? *state.depth_bounds : std::array<double, 2>{0.0, 1.0}),
        fixed24_(fb.format_ == DepthFormat::Fixed24) {}

  bool scissor() const { return scissor_; }

  void operator()(std::size_t p, int x, int y, float depth, bool front, FragmentCounts& counts) const {
    // Volume culling: fragments outside the scissor, or where the stored
    // depth (decoded to window depth) lies outside the depth bounds, are
    // dropped before the stencil test and counted apart.
    if ((scissor_ && !rect_.contains(x, y)) || (depth_bounds_ && !in_bounds(fb_.depth_[p]))) {
      ++counts[2];
      return;
    }
    ++counts[0];
    // The near-cap pass neither tests nor writes depth.
    const std::uint32_t z = !needs_depth_     ? 0
                            : llvmpipe_depth_ ? fb_.encode_depth_llvmpipe(depth)
                                              : fb_.encode_depth(depth);
    const bool pass = !test_depth_ || (greater_ ? z > fb_.depth_[p] : z < fb_.depth_[p]);
    counts[1] += pass;
    const StencilOps& ops = front ? state_.front : state_.back;
    fb_.stencil_[p] = apply(pass ? ops.depth_pass : ops.depth_fail, fb_.stencil_[p]);
    if (pass && state_.depth_write) {
      fb_.depth_[p] = z;
      fb_.objects_[p] = state_.object_id;
    }
  }

 private:
  // The stored depth, decoded to window depth, within the bounds.
  bool in_bounds(std::uint32_t z) const {
    double stored;
    if (fixed24_) {
      stored = static_cast<double>(z) / 16777215.0;
    } else {
      float f;
      std::memcpy(&f, &z, sizeof f);
      stored = f;
    }
    return stored >= bounds_[0] && stored <= bounds_[1];
  }

  Framebuffer& fb_;
  const DrawState& state_;
  bool test_depth_, greater_, needs_depth_, llvmpipe_depth_, scissor_;
  PixelRect rect_;
  bool depth_bounds_;
  std::array<double, 2> bounds_;
  bool fixed24_;
};

namespace {

// `body(band, counts)` on each band, in parallel; the counts summed.
template <class Body>
FragmentCounts over_bands(int bands, Body&& body) {
  return tbb::parallel_reduce(
      tbb::blocked_range<int>(0, bands), FragmentCounts{0, 0, 0},
      [&](const tbb::blocked_range<int>& range, FragmentCounts counts) {
        for (int b = range.begin(); b != range.end(); ++b) body(b, counts);
        return counts;
      },
      [](const FragmentCounts& a, const FragmentCounts& b) {
        return FragmentCounts{a[0] + b[0], a[1] + b[1], a[2] + b[2]};
      });
}

DrawCounters fragment_counters(const FragmentCounts& counts, std::uint64_t in_view) {
  DrawCounters counters;
  counters.in_view = in_view;
  counters.fragments = counts[0];
  counters.depth_passed = counts[1];
  counters.bounds_culled = counts[2];
  return counters;
}

}  // namespace

DrawCounters Framebuffer::rasterize(const SetUpTriangles& prepared, const DrawState& state,
                                    const RasterSettings& raster, CoveredFragments* keep, std::size_t keep_at_most) {
  const std::vector<std::array<WindowVertex, 3>>& triangles = prepared.triangles;
  // Fragments: horizontal bands in parallel, each band seeing every triangle
  // in submission order, so every pixel gets its fragments in GL's order and
  // the result does not depend on the number of threads.
  const int bands = (height_ + kBandRows - 1) / kBandRows;
  // Bin the triangles by the bands their rows may touch (a conservative range
  // from the float y extent, widened by a pixel), keeping submission order.
  // A triangle whose bounds miss the viewport covers no pixel centre: it is
  // not binned, and not counted in view.
  std::unique_ptr<Bins> bins = take_buffer<Bins>();
  Bins& binned = *bins;
  binned.resize(static_cast<std::size_t>(bands));
  for (std::vector<std::uint32_t>& bin : binned) bin.clear();
  const float width = static_cast<float>(width_), height = static_cast<float>(height_);
  std::uint64_t in_view = 0;
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const auto& tri = triangles[t];
    const float lo = std::min({tri[0].y, tri[1].y, tri[2].y}), hi = std::max({tri[0].y, tri[1].y, tri[2].y});
    const float left = std::min({tri[0].x, tri[1].x, tri[2].x}), right = std::max({tri[0].x, tri[1].x, tri[2].x});
    if (hi < 0 || lo > height || right < 0 || left > width) continue;
    ++in_view;
    const int row0 = std::clamp(static_cast<int>(std::floor(lo)) - 1, 0, height_ - 1);
    const int row1 = std::clamp(static_cast<int>(std::floor(hi)) + 1, 0, height_ - 1);
    for (int b = row0 / kBandRows; b <= row1 / kBandRows; ++b)
      binned[static_cast<std::size_t>(b)].push_back(static_cast<std::uint32_t>(t));
  }
  if (keep) {
    NEARCAP_CHECK(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_) <= CoveredFragments::kFront);
    keep->bands.resize(static_cast<std::size_t>(bands));
    for (std::vector<CoveredFragments::Covered>& band : keep->bands) band.clear();
    keep->in_view = in_view;
  }
  // The fragments kept so far over all bands, each band's added after each
  // of its triangles; past keep_at_most, every band stops keeping.
  std::atomic<std::size_t> kept_in_all{0};
  std::atomic<bool> over{false};
  const FragmentStage stage(*this, state, raster);
  const FragmentCounts counts = over_bands(bands, [&](int b, FragmentCounts& band_counts) {
    const int row_begin = b * kBandRows, row_end = std::min(height_, row_begin + kBandRows);
    std::vector<CoveredFragments::Covered>* kept = keep ? &keep->bands[static_cast<std::size_t>(b)] : nullptr;
    for (std::uint32_t t : binned[static_cast<std::size_t>(b)]) {
      const std::size_t before = kept ? kept->size() : 0;
      rasterize_triangle_with(
          triangles[t], width_, height_, raster,
          [&](const Fragment& f) {
            const std::size_t p = index(f.x, f.y);
            if (kept)
              kept->push_back({static_cast<std::uint32_t>(p) | (f.front ? CoveredFragments::kFront : 0u), f.depth});
            stage(p, f.x, f.y, f.depth, f.front, band_counts);
          },
          row_begin, row_end);
      if (!kept) continue;
      const std::size_t added = kept->size() - before;
      if (over.load(std::memory_order_relaxed) ||
          kept_in_all.fetch_add(added, std::memory_order_relaxed) + added > keep_at_most) {
        over.store(true, std::memory_order_relaxed);
        kept = nullptr;
      }
    }
  });
  if (keep && over.load()) keep->bands.clear();
  give_back(std::move(bins));
  return fragment_counters(counts, in_view);
}

DrawCounters Framebuffer::replay(const CoveredFragments& covered, const DrawState& state,
                                 const RasterSettings& raster) {
  NEARCAP_CHECK(covered.bands.size() == static_cast<std::size_t>((height_ + kBandRows - 1) / kBandRows));
  const FragmentStage stage(*this, state, raster);
  const std::size_t width = static_cast<std::size_t>(width_);
  const FragmentCounts counts =
      over_bands(static_cast<int>(covered.bands.size()), [&](int b, FragmentCounts& band_counts) {
        for (const CoveredFragments::Covered& f : covered.bands[static_cast<std::size_t>(b)]) {
          const std::size_t p = f.pixel_and_facing & ~CoveredFragments::kFront;
          const bool front = (f.pixel_and_facing & CoveredFragments::kFront) != 0;
          // The pixel's column and row, for the scissor only.
          const int x = stage.scissor() ? static_cast<int>(p % width) : 0,
                    y = stage.scissor() ? static_cast<int>(p / width) : 0;
          stage(p, x, y, f.depth, front, band_counts);
        }
      });
  return fragment_counters(counts, covered.in_view);
}

}  // namespace nearcap::gl
