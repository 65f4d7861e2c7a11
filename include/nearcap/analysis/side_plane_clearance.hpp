// nearcap/analysis/side_plane_clearance.hpp — how close to the eye the side
// planes of an occluder's shadow volume pass, against a bound from float32
// rounding of the side quads' clip coordinates.
//
// AtomicZP (docs/atomiczp.md) draws the volume's side quads, one per
// silhouette edge [a, d], with depth clamp: (d, 1) (a, 1) (a - l, 0)
// (d - l, 0), l the light.  A side plane (through a, d and l) that nearly
// holds the eye is seen almost edge-on: its quad, not clipped at the near
// plane, reaches from in front of the eye to behind it and covers about
// half the frame, bounded by the image of the plane.  The rasterizer finds
// that boundary from the quad's float32 clip coordinates; where the eye is
// closer to the exact plane than those coordinates' rounding moves the
// plane, the float quad covers pixels the exact one does not (the eye count
// being right and no tie at the eye: sampled configuration 11 of seed 28,
// kind eye-near-volume).
//
// Frames: camera space (the eye is the origin), exact, from CameraSpaceScene.
// The side planes are those of the quads the frame draws: the float
// silhouette's edges (engine_classification.hpp, as the emulation and the
// real GL's renderer extract them).
//
// The bound, per edge: kSidePlaneBoundUnits * 2^-24 * M * lever, M the
// edge's coordinate magnitude (side_plane_magnitude below): the largest
// |coordinate| any float32 operation of the quad's vertex transforms sees,
// and the lever (side_plane_lever) how far a vertex's movement moves the
// plane at the eye.  A float32 clip coordinate is a sum of products of such
// terms, so its rounding error is a few units of 2^-24 M; the bound is that
// error at the eye with a margin the measurement in
// tests/atomiczp_side_plane_test.cpp justifies (docs/atomiczp.md, "The
// side-plane condition").
#pragma once

#include <cstddef>
#include <limits>

#include "nearcap/exact/camera_space.hpp"

namespace nearcap::analysis {

// The bound in units of side_plane_unit (2^-24, float32's unit roundoff,
// times the edge's coordinate magnitude and lever).  Measured on the 40
// eye-near-volume configurations of seed 28, the eye moved off a side plane
// by 1/16 to 8,192 units: frames wrong where Z-fail is right up to 32.55
// units from their nearest side plane, none from 45 on (docs/findings/
// atomiczp.md, "The side-plane bound"); 64 is about twice the farthest.
inline constexpr double kSidePlaneBoundUnits = 64;

struct SidePlaneClearance {
  std::size_t edges = 0;  // side quads examined: the float silhouette's edges
  // Exact: some side plane passes the eye closer than its bound
  // (distance < bound_units * side_plane_unit, decided by a filter with an
  // exact fallback).
  bool within_bound = false;
  // Estimate (double; rationals where the double triple product cannot
  // tell the eye from the plane): the smallest distance from the eye to a
  // side plane over the edges, in units of side_plane_unit; +inf without
  // edges.  For reports and measurements, not for decisions.
  double nearest_units = std::numeric_limits<double>::infinity();
  std::size_t exact_fallbacks = 0;  // edges the filter could not decide
};

// The side planes of occluder o's volume under `light` against the bound.
// A degenerate side plane (a, d and l collinear: its quad has no area) is
// never within the bound.
SidePlaneClearance side_plane_clearance(const CameraSpaceScene& cs, std::size_t o, std::size_t light,
                                        double bound_units = kSidePlaneBoundUnits);

// M for the edge [a, d] of object o (object-space vertices): the largest
// row sum of |view| |object_to_world| (|v|, 1) over v = a, d and of
// |view| (|light|, 1), in double: the magnitude of the terms the float32
// modelview transform of the quad's vertices adds (world coordinates far
// from the origin count with their size, as they do in float32).
double side_plane_magnitude(const Scene& scene, std::size_t o, VertexIndex a, VertexIndex d, std::size_t light);

// How far the rounding of the quad's vertices moves its plane at the eye,
// per unit of their own movement: 1 + L / |d - a| + L / min(|a - l|,
// |d - l|), L = max(|a|, |d|) the edge's reach from the eye (camera space,
// estimates).  A vertex of the edge moved by r turns the plane about the
// other by up to r / |d - a|, and the extrusion direction a - l, off by r,
// turns it by up to r / |a - l|; at the eye, L away, either moves the plane
// by that angle times L.  +inf for a degenerate edge (a = d, or a vertex at
// the light).
double side_plane_lever(const CameraSpaceScene& cs, std::size_t o, VertexIndex a, VertexIndex d, std::size_t light);

// The unit of the bound for the edge [a, d]: 2^-24 M times the lever.
double side_plane_unit(const CameraSpaceScene& cs, std::size_t o, VertexIndex a, VertexIndex d, std::size_t light);

}  // namespace nearcap::analysis
