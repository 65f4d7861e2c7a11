// nearcap/gl/shadow_methods.hpp — the stencil shadow methods, run through the
// software GL pipeline for one light: what a GPU's stencil buffer holds.
//
// Every method starts with a depth pre-pass of all objects (receivers and
// occluders; depth test LESS, depth and object id written), then counts into
// the 8-bit wrapping stencil buffer:
//   zpass             sides; front faces +1, back faces -1 on depth pass.
//   zfail             sides, light cap and dark cap at infinity; back faces +1,
//                     front faces -1 on depth fail (Everitt and Kilgard 2002),
//                     with the infinite far plane or depth clamp (ZFailFar).
//                     Depth clamp disables near clipping too, so a light-cap
//                     triangle that crosses the near plane is clipped at w_min,
//                     not where the depth pre-pass clipped it: its depths are no
//                     longer bit-identical to the surface's, and the depth test
//                     breaks the tie either way (wrong pixels on such faces).
//   zpplus            ZP+ as published (section 3): the near-cap pass (every
//                     occluder through M_l and P_l, back faces culled when
//                     alpha = 1, front faces when alpha = -1, +1 per fragment,
//                     no depth test), then zpass.
//   zpplus-corrected  section 5: the same near-cap pass, then the sides with
//                     the Figure 7 program plus corrective quads for C1 and C2;
//                     an occluder with a case-D quad (float detection) switches
//                     to zfail with depth clamp for this light (section 5.2) and
//                     is left out of the near-cap pass.
//   preload           Doom 3 BFG's "stencil preload" (DrawStencilShadowPass with
//                     r_useStencilShadowPreload): the whole closed volume (sides
//                     and caps) counted whatever the depth test says (front -1,
//                     back +1 on both depth fail and depth pass) preloads the
//                     number of volumes the near plane is in, then the same
//                     volume again as Z-pass; infinite far plane.
//   atomiczp          AtomicZP (Usta et al., HPG 2019), as nearcap
//                     reconstructs it (docs/atomiczp.md): the stencil
//                     cleared to the float32 count of the light's volumes
//                     containing the eye (eye_count.hpp: a pass over the
//                     occluder triangles into an atomic counter), then the
//                     sides counted as zpass with GL_DEPTH_CLAMP (no near
//                     clipping: the crossings between the eye and the near
//                     plane count too, at the clamped depth).  Clearing to
//                     the count is the lighting pass's comparison with it
//                     (glStencilFunc(GL_EQUAL, -count)), moved to the clear so
//                     that "shadowed where the stencil is not 0" holds for
//                     every method.  Right wherever the float count is the
//                     exact one; where it is not, every pixel is off by the
//                     difference: the whole frame inverts.
// When the light lies in the near plane there is no light frustum: both ZP+
// methods fall back to zfail for the light (ShadowFrame::fallback says so).
// With LightProjection::ClippedSides (light_frustum.hpp) both ZP+ methods
// are zpass plus the near-cap fan of gl/near_plane_cap.hpp: no light
// frustum, so no fallback, no case-D switch and no corrective quads.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "nearcap/exact/quad_case.hpp"
#include "nearcap/gl/light_frustum.hpp"
#include "nearcap/gl/pipeline.hpp"
#include "nearcap/gl/tight_near_plane.hpp"
#include "nearcap/named_values.hpp"

namespace nearcap::gl {

enum class ShadowMethod { ZPass, ZFail, ZPPlus, ZPPlusCorrected, Preload, AtomicZP };
// The methods' names (named_values.hpp), in the order "all" lists them.
inline constexpr NamedValue<ShadowMethod> kShadowMethodTable[] = {
    {ShadowMethod::ZPass, "zpass", "Z-pass"},
    {ShadowMethod::ZFail, "zfail", "Z-fail with caps (Everitt and Kilgard 2002)"},
    {ShadowMethod::ZPPlus, "zpplus", "ZP+ as published (section 3)"},
    {ShadowMethod::ZPPlusCorrected, "zpplus-corrected", "ZP+ with section 5's corrections"},
    {ShadowMethod::Preload, "preload", "Doom 3 BFG's stencil preload"},
    {ShadowMethod::AtomicZP, "atomiczp", "AtomicZP: the stencil cleared to the eye's count"},
};
constexpr const auto& named_values(ShadowMethod) { return kShadowMethodTable; }
static_assert(names_are_unique<ShadowMethod>());
inline constexpr auto kAllShadowMethods = values_of<ShadowMethod>();
inline std::string_view to_string(ShadowMethod m) { return name_of(m); }
inline std::optional<ShadowMethod> shadow_method_from_string(std::string_view name) {
  return value_named<ShadowMethod>(name);
}
bool uses_near_cap(ShadowMethod m);

enum class ZFailFar {
  Infinite,       // infinite far plane (Everitt and Kilgard); its own depth pre-pass
  DepthClamp,     // the finite frustum with GL_DEPTH_CLAMP (NV_depth_clamp: near and far)
  DepthClampFar,  // the finite frustum, clamped at the far plane only (GL_AMD_depth_clamp_separate)
  FarCap,         // ZF+: the finite frustum, no clamp, and the far-plane cap its clipped volume leaves
                  // (near_plane_cap.hpp: far_plane_cap_triangles), counted as Z-fail counts back faces
};
inline constexpr NamedValue<ZFailFar> kZFailFarTable[] = {
    {ZFailFar::Infinite, "infinite", ""},
    {ZFailFar::DepthClamp, "clamp", "GL_DEPTH_CLAMP"},
    {ZFailFar::DepthClampFar, "clamp-far", "far plane only"},
    {ZFailFar::FarCap, "far-cap", "ZF+: no clamp, the far-plane cap of the clipped volume"},
};
constexpr const auto& named_values(ZFailFar) { return kZFailFarTable; }
static_assert(names_are_unique<ZFailFar>());
inline std::string_view to_string(ZFailFar f) { return name_of(f); }
inline std::optional<ZFailFar> zfail_far_from_string(std::string_view name) { return value_named<ZFailFar>(name); }

// How a ZP+ method's switch to Z-fail (case D, or no light frustum) clamps
// depth: the paper's NV_depth_clamp, or far only.  A type of its own, without
// ZFailFar::Infinite: the depth pre-pass of ZP+ uses the finite frustum
// (section 5.2), so the switch cannot use an infinite far plane.
enum class SwitchClamp {
  DepthClamp,     // GL_DEPTH_CLAMP (near and far)
  DepthClampFar,  // far only (GL_AMD_depth_clamp_separate)
  FarCap,         // no clamp: ZF+, the far-plane cap (section 5.2's alternative)
};
// Z-pass's projection: the finite frustum (the method's own), or the infinite
// far plane (Everitt and Kilgard; Doom 3 draws everything so): far more depth
// precision near the camera when the near plane is tiny against the scene.
// A frame with a ZP+ method keeps the finite one (section 5.2), unless its
// cap is LightProjection::ClippedSides: that ZP+ is Z-pass plus a cap the
// sides' own projection clips, and takes this choice like Z-pass.
enum class ZPassFar { Finite, Infinite };
inline constexpr NamedValue<ZPassFar> kZPassFarTable[] = {
    {ZPassFar::Finite, "finite", "its own frustum"},
    {ZPassFar::Infinite, "infinite",
     "the infinite far plane, as Doom 3 draws; kept finite in a frame with a ZP+ method"},
};
constexpr const auto& named_values(ZPassFar) { return kZPassFarTable; }
static_assert(names_are_unique<ZPassFar>());
inline std::string_view to_string(ZPassFar f) { return name_of(f); }
inline std::optional<ZPassFar> zpass_far_from_string(std::string_view name) { return value_named<ZPassFar>(name); }

// The same names as the ZFailFar each one is (as_zfail_far).
inline constexpr NamedValue<SwitchClamp> kSwitchClampTable[] = {
    {SwitchClamp::DepthClamp, "clamp", ""},
    {SwitchClamp::DepthClampFar, "clamp-far", ""},
    {SwitchClamp::FarCap, "far-cap", "ZF+: no clamp, the far-plane cap"},
};
constexpr const auto& named_values(SwitchClamp) { return kSwitchClampTable; }
static_assert(names_are_unique<SwitchClamp>());
inline std::string_view to_string(SwitchClamp c) { return name_of(c); }
inline std::optional<SwitchClamp> switch_clamp_from_string(std::string_view name) {
  return value_named<SwitchClamp>(name);
}
ZFailFar as_zfail_far(SwitchClamp c);

// Volume culling (volume_bounds.hpp): each occluder's draws limited to the
// scissor rectangle, the depth bounds, or both, of the region its volume
// can change; the final stencil is the same (timing options of the paper's
// speed argument; the real GL needs GL_EXT_depth_bounds_test for depth
// bounds).
enum class VolumeCulling { None, Scissor, DepthBounds, Both };
inline constexpr NamedValue<VolumeCulling> kVolumeCullingTable[] = {
    {VolumeCulling::None, "none", ""},
    {VolumeCulling::Scissor, "scissor", "glScissor"},
    {VolumeCulling::DepthBounds, "depth-bounds", "GL_EXT_depth_bounds_test"},
    {VolumeCulling::Both, "both", ""},
};
constexpr const auto& named_values(VolumeCulling) { return kVolumeCullingTable; }
static_assert(names_are_unique<VolumeCulling>());
inline std::string_view to_string(VolumeCulling c) { return name_of(c); }
inline std::optional<VolumeCulling> volume_culling_from_string(std::string_view name) {
  return value_named<VolumeCulling>(name);
}

struct EmulationSettings {
  RasterSettings raster;
  DepthFormat depth = DepthFormat::Fixed24;
  Arithmetic arithmetic = Arithmetic::Separate;
  LightFrustumChoice light_frustum;
  ZFailFar zfail_far = ZFailFar::Infinite;
  // How a ZP+ method's switch to Z-fail (case D, or no light frustum) clamps.
  SwitchClamp switch_clamp = SwitchClamp::DepthClamp;
  ZPassFar zpass_far = ZPassFar::Finite;
  // The infinite projection's depth row (float_transforms.hpp), wherever a
  // frame draws with the far plane at infinity.
  InfiniteFar infinite_far = InfiniteFar::Exact;
  // The camera's depth mapping (float_transforms.hpp): standard, or reversed
  // (GL_ZERO_TO_ONE, near at depth 1, tested GL_GREATER), for every camera
  // pass; a light-frustum near-cap pass (no depth test) keeps its own
  // standard clip space, as an application switching glClipControl around it.
  DepthMapping depth_mapping = DepthMapping::Standard;
  // The camera's near plane: the scene's, or pushed out to half the depth
  // of the nearest point in view (tight_near_plane.hpp).
  NearPlane near_plane = NearPlane::Scene;
  // The clipped-sides cap pass skips an occluder that certainly holds no
  // point of the light pyramid (light_pyramid_cull.hpp): an empty cap, so
  // the same frame, without evaluating z + w at its every vertex.  Off only
  // to check that claim (tests/light_pyramid_cull_test.cpp).
  bool cull_light_pyramid = true;
  VolumeCulling volume_culling = VolumeCulling::None;
  // Keep every draw call of each frame (ShadowFrame::draws), for a real GL to
  // replay; changes nothing else.
  bool record_draws = false;
};

struct PassTimes {
  double depth_ms = 0, cap_ms = 0, volume_ms = 0, setup_ms = 0;  // setup: silhouettes and vertex arrays
  double total() const { return depth_ms + cap_ms + volume_ms + setup_ms; }
};

// The CPU work a renderer does for one occluder of a frame, as the
// emulation does it (steady_clock wall time): its silhouette and volume
// geometry (engine_silhouette, shadow_volume_geometry: computed once per
// ShadowFrameBatch, and every method's frame reports it as its own, as
// PassTimes::setup_ms does), and the clipped-sides cap's construction
// (LightProjection::ClippedSides: the near-plane distances, the extrusion
// program on the triangles that reach the near plane, the fan; the
// emulation's rasterization of the fan left out, a GL's work).  The other
// caps and volumes are built by the GL's vertex programs: no CPU time here.
struct OccluderCpuTimes {
  std::size_t object = 0;  // scene object index
  double silhouette_ms = 0, cap_build_ms = 0;
};

// A frame's CPU work (what a GL's timers do not see): the tight near plane
// (NearPlane::Tight), ZP+'s light frustum (both once per batch, reported by
// each frame that needs them) and each occluder's.
struct FrameCpuTimes {
  double near_plane_ms = 0, light_frustum_ms = 0;
  std::vector<OccluderCpuTimes> occluders;  // one per occluder, scene order
  double total() const {
    double t = near_plane_ms + light_frustum_ms;
    for (const OccluderCpuTimes& o : occluders) t += o.silhouette_ms + o.cap_build_ms;
    return t;
  }
};

struct ShadowFrame {
  ShadowMethod method = ShadowMethod::ZPass;
  std::size_t light = 0;
  int width = 0, height = 0;
  std::vector<std::uint8_t> stencil;                      // row 0 at the bottom
  std::vector<std::int32_t> object;                       // visible object per pixel, -1 for none
  std::vector<std::uint8_t> near_cap;                     // the near-cap pass alone (ZP+ methods; empty otherwise)
  std::array<std::size_t, kQuadCaseCount> float_cases{};  // the engine's cases, all occluders
  std::vector<std::size_t> zfail_objects;                 // occluders drawn with zfail instead (case D)
  std::string fallback;  // why the whole light fell back to zfail, or "" (`nearcap cracks` writes it "zfail: WHY")
  LightFrustum light_frustum;  // ZP+ methods
  // AtomicZP: the float32 eye count the stencil was cleared to (mod 256),
  // and the triangles its pass tested; absent for the other methods.
  std::optional<std::size_t> eye_count;
  std::size_t eye_count_triangles = 0;
  // Each occluder's method (object index, method): all `method` unless the
  // frame was rendered per occluder (`mixed`, ShadowFrameBatch::render with
  // a method per object).
  std::vector<std::pair<std::size_t, ShadowMethod>> object_methods;
  bool mixed = false;
  DrawCounters depth_pass, cap_pass, volume_pass;
  PassTimes times;
  FrameCpuTimes cpu;
  // With EmulationSettings::record_draws: the frame's draw calls in order
  // (the depth pre-pass, the near-cap pass, the volumes), as drawn here.
  std::vector<DrawCall> draws;
  // The near plane the frame was drawn with (NearPlane::Tight may move it
  // out: then its near_cap is not the scene camera's and is not judged).
  double near = 0;
  bool near_moved = false;
  std::size_t index(int i, int j) const { return static_cast<std::size_t>(j) * width + i; }
};

ShadowFrame render_shadow_frame(const Scene& scene, std::size_t light, ShadowMethod method,
                                const EmulationSettings& settings = {});

// Several methods of one (scene, light, settings), sharing what they have in
// common as an engine would within a frame: vertex arrays, the silhouettes
// and shadow-volume geometry, and the depth pre-pass per projection (each
// method's frame reports that pass's counters and time, and the silhouettes'
// time in its setup, as its own: frame times stay comparable).  Each
// render(m) returns exactly what render_shadow_frame(scene, light, m,
// settings) returns, times aside (tests/shadow_methods_test.cpp).  Keeps a
// reference to the scene.
class ShadowFrameBatch {
 public:
  ShadowFrameBatch(const Scene& scene, std::size_t light, const EmulationSettings& settings = {});
  ~ShadowFrameBatch();
  ShadowFrameBatch(const ShadowFrameBatch&) = delete;
  ShadowFrameBatch& operator=(const ShadowFrameBatch&) = delete;

  ShadowFrame render(ShadowMethod method);
  // One frame with a method per scene object (entries of non-occluders are
  // unused), as an engine that decides per occluder draws it: the near-cap
  // pass for the occluders with a ZP+ method, each occluder's volume by its
  // method.  The projection is the infinite one when some occluder uses
  // preload or Z-fail with its default infinite far plane and none uses a
  // ZP+ method (ZP+'s depth pre-pass needs the finite one; Z-fail then
  // clamps as the case-D switch does: `switch_clamp`), else the finite one;
  // ZP+ with the clipped-sides cap needs neither and counts as Z-pass.
  // Preload beside a ZP+ method with a light-frustum cap is refused (error
  // (usage)).  With every
  // occluder on one method the frame equals render(method), `mixed` aside.
  ShadowFrame render(const std::vector<ShadowMethod>& object_methods);
  // ZP+'s light frustum for these settings: computed once per batch (its
  // l_near rule may measure the distance from the light to every occluder
  // triangle) and shared by every ZP+ method rendered.
  const LightFrustum& light_frustum();

  struct SharedWork;  // src/gl/shadow_methods.cpp

 private:
  double tight_ms_ = 0;           // finding the tight near plane, in every frame's setup time (before tight_)
  std::unique_ptr<Scene> tight_;  // the scene with the tight near plane (NearPlane::Tight)
  const Scene& scene_;
  double scene_near_;  // the scene file's near plane
  std::size_t light_;
  EmulationSettings settings_;
  std::unique_ptr<SharedWork> shared_;
};

}  // namespace nearcap::gl
