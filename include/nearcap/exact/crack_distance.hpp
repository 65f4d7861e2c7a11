// nearcap/exact/crack_distance.hpp — how far a wrong pixel is from the exact shadow
// boundary: rasterization noise or a crack a person sees.
//
// Every method, Z-fail included, gets a few pixels wrong whose centre lies
// within a rasterization error of an exact shadow boundary: the float pipeline
// snaps vertices to 1/256 pixel, interpolates depth in float32, and decides a
// pixel by its centre, so the exact boundary and the rasterized one differ by
// a fraction of a pixel.  A crack is something else: a pixel whose exact shadow
// status is the same over its whole pixel square, so no rounding of the
// boundary could excuse it.
//
// The crack distance of pixel (i, j) is the largest radius r of
// kCrackDistanceRadii (1/512, 1/64, 1/8, 1/2, 2, 8 pixels) for which the exact
// shadow status is PROVEN constant over the square of half-width r centred on
// the pixel centre; level 0 when not even r = 1/512 is proven.  A wrong pixel
// of level >= kCrackLevel (r >= 1/2: the whole pixel square) is a crack.  How
// the squares are chosen so that a frame with thousands of wrong pixels is
// measured in a few proofs per pixel: judge/crack_distances.hpp.
//
// The proof (PixelReferenceTracer::proven_status_over_square), on the near
// plane where the sample point P moves over a square S: every test of the
// reference is the sign of an affine form in P (pixel_reference.hpp), and an
// affine form has one strict sign over S exactly when it has that strict sign
// at S's four corners (S is their convex hull).  So, with T the triangle seen
// at the pixel centre, the status is proven constant when
//   1. T is hit over all of S: its three edge forms, its beyond-near and
//      before-far forms have sign(d_T) at all four corners;
//   2. every other triangle the eye grid lists for S's directions is hidden
//      over all of S: one of its edge, near or far forms has the wrong sign at
//      all four corners (never hit), or the depth-order form puts T's plane
//      strictly first at all four corners;
//   3. the shadow status of q(P), T's point seen through P, is constant: either
//      one light-front-facing triangle L is crossed by (l, q(P)) for all P in S
//      (its three edge forms share one strict sign at the four corners and its
//      side form is on the crossing side at the four corners): in shadow; or
//      every L the light grid (the camera-space one, around the light) lists
//      for S's points q(P) is proven never crossed
//      (its side form on the other side at all four corners, or two of its
//      edge forms of strictly opposite signs at all four corners): lit.
// Each form is first bounded over the whole square from its value at the
// centre and the square's half-sides (src/exact/square_sign_filter.hpp: one
// sign at every corner, or two corners certainly of opposite signs); where
// that is not certain, each corner sign is filtered (BoundedDouble) and
// recomputed over rationals when the filter cannot decide; a zero at a
// corner is "not proven".  Nothing
// is ever claimed that is not proven, so a level can only be an underestimate:
// a few cracks may be counted as noise, never the reverse.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "nearcap/exact/pixel_reference.hpp"

namespace nearcap {

inline constexpr std::size_t kCrackDistanceLevels = 7;  // levels 0..6
// Half-widths, in pixels, of the squares of levels 1..6 (and as multiples of
// 2^-10 pixel, exactly).
inline constexpr std::array<double, 6> kCrackDistanceRadii{1.0 / 512, 1.0 / 64, 1.0 / 8, 0.5, 2.0, 8.0};
inline constexpr std::array<std::int64_t, 6> kCrackDistanceRadiiFixed{2, 16, 128, 512, 2048, 8192};
inline constexpr int kCrackDistanceShift = 10;
inline constexpr int kCrackLevel = 4;  // r >= 1/2

// "lt_1/512" (level 0), "1/512", "1/64", "1/8", "1/2", "2", "8": names for
// records and CSV columns.
inline constexpr std::array<std::string_view, kCrackDistanceLevels> kCrackDistanceNames{
    "lt_1/512", "1/512", "1/64", "1/8", "1/2", "2", "8"};

// The square of half-width (kCrackDistanceRadiiFixed[k - 1] / 2^10) pixels
// around pixel (i, j)'s centre: level k's square.
inline WindowPoint crack_square_centre(int i, int j) {
  return {(2 * std::int64_t{i} + 1) << (kCrackDistanceShift - 1),
          (2 * std::int64_t{j} + 1) << (kCrackDistanceShift - 1), kCrackDistanceShift};
}

}  // namespace nearcap
