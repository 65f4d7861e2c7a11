// nearcap/judge/crack_distances.hpp — the crack distance (exact/crack_distance.hpp)
// of a frame's wrong pixels, measured once per pixel for every method.
//
// The crack distance is a property of the exact image, not of the method, so
// one CrackDistances per (scene, light), beside its PixelReferenceTracer,
// serves every method's report: measure() fills wrong_by_distance, cracks and
// distance (crack_map.hpp).
//
// Which squares are proven.  Proving each wrong pixel's six squares one by one
// costs six proofs per pixel, and Z-pass gets whole frames wrong.  So:
//   1. Tiles: the window is covered by aligned square tiles of 32 pixels, each
//      split into four down to single pixels (a quadtree).  For a wrong pixel,
//      its tiles are tried from 32 pixels down until one is proven constant
//      (each tile at most once per CrackDistances, whoever asks).  A tile
//      whose pixel centres (from the full-frame reference) do not all see the
//      same triangle with the same status cannot be proven and is not tried:
//      the shortcut changes no answer, it only skips proofs that would fail.
//      A pixel in
//      a proven tile has every square inside that tile proven: level 4 (its
//      own pixel square, r = 1/2), 5 when its centre is >= 2 pixels from the
//      tile's edges, 6 when >= 8.
//   2. Pixels: a wrong pixel in no proven tile (not even its own 1-pixel
//      tile, which is its r = 1/2 square) tries its own squares r = 1/8,
//      1/64, 1/512 from the largest down, and the first proven gives its
//      level (3 to 1; 0 when none is).
// A pixel's level depends only on the exact scene and the pixel, never on
// which other pixels are wrong or in what order methods are measured.  It is
// a lower bound of the largest proven-constant square of exact/crack_distance
// (a square around the pixel centre not inside one aligned tile is not tried),
// so a crack may be counted as noise, never noise as a crack.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "nearcap/exact/pixel_reference.hpp"
#include "nearcap/judge/crack_map.hpp"

namespace nearcap {

class CrackDistances {
 public:
  static constexpr int kLargestTile = 32;  // pixels; then 16, 8, 4, 2, 1

  // `reference` is the tracer's full-frame reference (compute_pixel_reference).
  CrackDistances(const PixelReferenceTracer& tracer, const PixelReference& reference);

  // Measures every wrong pixel of the report not measured yet (all cores),
  // then fills the report's crack-distance fields.
  void measure(CrackReport& report);
  // The levels of arbitrary pixels (measured if needed).
  std::vector<int> levels(const std::vector<std::pair<int, int>>& pixels);

  const FilterStats& stats() const { return stats_; }
  std::size_t proofs() const { return proofs_; }  // squares tried, all calls
  double ms() const { return ms_; }               // time spent measuring, all calls

 private:
  void resolve(const std::vector<std::size_t>& pixels);

  bool tile_may_be_constant(int size, int a, int b) const;

  const PixelReferenceTracer& tracer_;
  const PixelReference& reference_;
  int width_, height_;
  std::vector<std::int8_t> level_;  // -1: not measured yet
  // Proven tiles by (size, tile column, tile row) key; false: tried, not proven.
  std::unordered_map<std::uint64_t, bool> tiles_;
  FilterStats stats_;
  std::size_t proofs_ = 0;
  double ms_ = 0;
};

}  // namespace nearcap
