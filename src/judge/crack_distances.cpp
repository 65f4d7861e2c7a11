// Crack distances measured once per pixel, by tiles then pixels (see
// crack_distances.hpp).
#include "nearcap/judge/crack_distances.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>

#include "nearcap/check.hpp"

namespace nearcap {
namespace {

constexpr int kTileSizes[] = {32, 16, 8, 4, 2, 1};

std::uint64_t tile_key(int size, int a, int b) {
  return (static_cast<std::uint64_t>(size) << 48) | (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 24) |
         static_cast<std::uint64_t>(static_cast<std::uint32_t>(b));
}

// The level a proven tile gives pixel (i, j) inside it: every square around
// the pixel centre that the tile contains.  Distances in half pixels.
int level_in_tile(int size, int a, int b, int i, int j) {
  const int dx = std::min(2 * (i - a * size) + 1, 2 * ((a + 1) * size - i) - 1);
  const int dy = std::min(2 * (j - b * size) + 1, 2 * ((b + 1) * size - j) - 1);
  const int d = std::min(dx, dy);  // >= 1: half a pixel
  return d >= 16 ? 6 : d >= 4 ? 5 : 4;
}

}  // namespace

CrackDistances::CrackDistances(const PixelReferenceTracer& tracer, const PixelReference& reference)
    : tracer_(tracer),
      reference_(reference),
      width_(tracer.scene().scene().camera.width),
      height_(tracer.scene().scene().camera.height),
      level_(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_), -1) {}

// Every pixel centre of the tile inside the viewport sees the same triangle
// with the same shadow status: necessary for a proof (which needs one
// triangle seen over the whole tile and one status).
bool CrackDistances::tile_may_be_constant(int size, int a, int b) const {
  const PixelReference& ref = reference_;
  const int i0 = a * size, j0 = b * size;
  const int i1 = std::min(width_, i0 + size), j1 = std::min(height_, j0 + size);
  const std::size_t first = ref.index(i0, j0);
  if (!ref.seen(i0, j0)) return false;
  for (int j = j0; j < j1; ++j)
    for (int i = i0; i < i1; ++i) {
      const std::size_t p = ref.index(i, j);
      if (ref.object[p] != ref.object[first] || ref.face[p] != ref.face[first] ||
          (ref.stencil[p] > 0) != (ref.stencil[first] > 0) || !ref.seen(i, j))
        return false;
    }
  return true;
}

void CrackDistances::resolve(const std::vector<std::size_t>& pixels) {
  const auto t0 = std::chrono::steady_clock::now();
  tbb::enumerable_thread_specific<FilterStats> stats;
  // Per thread, the light triangle that last proved a square in shadow: tried
  // first on the next square (the levels do not depend on it).
  tbb::enumerable_thread_specific<std::uint32_t> last_shadower(PixelReferenceTracer::kNoShadower);
  std::vector<std::size_t> pending;
  for (std::size_t p : pixels)
    if (level_[p] < 0) pending.push_back(p);
  std::sort(pending.begin(), pending.end());
  pending.erase(std::unique(pending.begin(), pending.end()), pending.end());

  // 1. Tiles, largest first: each needed tile proven once, in parallel.
  std::vector<std::uint64_t> one_pixel_tiles;
  std::vector<PixelReferenceTracer::CentreHit> one_pixel_hits;
  for (int size : kTileSizes) {
    std::vector<std::uint64_t> todo;
    std::vector<std::size_t> still;
    for (std::size_t p : pending) {
      const int i = static_cast<int>(p % width_), j = static_cast<int>(p / width_);
      const int a = i / size, b = j / size;
      const auto it = tiles_.find(tile_key(size, a, b));
      if (it == tiles_.end()) todo.push_back(tile_key(size, a, b));
      still.push_back(p);
    }
    std::sort(todo.begin(), todo.end());
    todo.erase(std::unique(todo.begin(), todo.end()), todo.end());
    std::vector<char> proven(todo.size(), 0);
    // The one-pixel tiles' centres are their pixels' centres: what their
    // proofs trace there serves the pixels' own squares below.
    if (size == 1) {
      one_pixel_tiles = todo;
      one_pixel_hits.assign(todo.size(), {});
    }
    tbb::parallel_for(std::size_t{0}, todo.size(), [&](std::size_t k) {
      const auto a = static_cast<std::int64_t>((todo[k] >> 24) & 0xffffffu),
                 b = static_cast<std::int64_t>(todo[k] & 0xffffffu);
      // The tile's centre and half-width in units of 2^-10 pixel.
      const std::int64_t half = std::int64_t{size} << (kCrackDistanceShift - 1);
      const WindowPoint centre{(2 * a + 1) * half, (2 * b + 1) * half, kCrackDistanceShift};
      // Every pixel centre of a tile that may be constant has the status of
      // its first: a proof of the other status cannot succeed.
      proven[k] =
          tile_may_be_constant(size, static_cast<int>(a), static_cast<int>(b)) &&
          tracer_
              .proven_status_over_square(centre, half, &stats.local(), &last_shadower.local(),
                                         size == 1 ? &one_pixel_hits[k] : nullptr,
                                         reference_.shadowed(static_cast<int>(a) * size, static_cast<int>(b) * size))
              .has_value();
    });
    proofs_ += todo.size();
    for (std::size_t k = 0; k < todo.size(); ++k) tiles_[todo[k]] = proven[k] != 0;
    pending.clear();
    for (std::size_t p : still) {
      const int i = static_cast<int>(p % width_), j = static_cast<int>(p / width_);
      const int a = i / size, b = j / size;
      if (tiles_.at(tile_key(size, a, b)))
        level_[p] = static_cast<std::int8_t>(level_in_tile(size, a, b, i, j));
      else
        pending.push_back(p);
    }
  }

  // 2. Pixels in no proven tile: their own squares r = 1/8, 1/64, 1/512,
  // largest first (a proven square holds every smaller one around the same
  // centre; on fine meshes most wrong pixels are proven at 1/64 or 1/8, so
  // this order tries fewer squares than the smallest first).
  std::vector<std::size_t> tried(pending.size(), 0);
  tbb::parallel_for(std::size_t{0}, pending.size(), [&](std::size_t k) {
    const std::size_t p = pending[k];
    const int i = static_cast<int>(p % width_), j = static_cast<int>(p / width_);
    int level = 0;
    PixelReferenceTracer::CentreHit centre_hit;
    const auto tile = std::lower_bound(one_pixel_tiles.begin(), one_pixel_tiles.end(), tile_key(1, i, j));
    if (tile != one_pixel_tiles.end() && *tile == tile_key(1, i, j))
      centre_hit = one_pixel_hits[static_cast<std::size_t>(tile - one_pixel_tiles.begin())];
    for (int r = kCrackLevel - 2; r >= 0; --r) {
      ++tried[k];
      if (tracer_.proven_status_over_square(
              crack_square_centre(i, j), kCrackDistanceRadiiFixed[r], &stats.local(), &last_shadower.local(),
              &centre_hit, reference_.seen(i, j) ? std::optional<bool>(reference_.shadowed(i, j)) : std::nullopt)) {
        level = r + 1;
        break;
      }
    }
    level_[p] = static_cast<std::int8_t>(level);
  });
  for (std::size_t n : tried) proofs_ += n;
  for (const FilterStats& s : stats) stats_.merge(s);
  ms_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

std::vector<int> CrackDistances::levels(const std::vector<std::pair<int, int>>& pixels) {
  std::vector<std::size_t> index;
  for (const auto& [i, j] : pixels) {
    NEARCAP_CHECK(i >= 0 && j >= 0 && i < width_ && j < height_);
    index.push_back(static_cast<std::size_t>(j) * width_ + i);
  }
  resolve(index);
  std::vector<int> out;
  for (std::size_t p : index) out.push_back(level_[p]);
  return out;
}

void CrackDistances::measure(CrackReport& report) {
  NEARCAP_CHECK(report.verdict.size() == level_.size());
  auto wrong = [&](std::size_t p) {
    return report.verdict[p] == PixelVerdict::WrongLit || report.verdict[p] == PixelVerdict::WrongShadowed;
  };
  std::vector<std::size_t> pixels;
  for (std::size_t p = 0; p < level_.size(); ++p)
    if (wrong(p)) pixels.push_back(p);
  resolve(pixels);

  std::array<std::size_t, kCrackDistanceLevels> buckets{};
  std::size_t cracks = 0;
  report.distance.assign(level_.size(), -1);
  for (std::size_t p : pixels) {
    report.distance[p] = level_[p];
    ++buckets[static_cast<std::size_t>(level_[p])];
    if (level_[p] >= kCrackLevel) ++cracks;
  }
  report.wrong_by_distance = buckets;
  report.cracks = cracks;
}

}  // namespace nearcap
