// The cube-map grid (exact/central_grid.hpp) never loses a candidate: every
// triangle that a direction of the query meets is listed, for point queries
// and for region queries, including regions that span several cube faces,
// reach the face diagonals, or surround the centre.
#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "nearcap/exact/central_grid.hpp"

namespace nearcap {
namespace {

// Whether the ray from the origin along d meets triangle (a, b, c) clearly
// inside (barycentric margin): then no rounding of the grid may lose it.
bool ray_meets_clearly(const Vec3d& d, const std::array<Vec3d, 3>& v) {
  const Vec3d e1 = v[1] - v[0], e2 = v[2] - v[0];
  const Vec3d p = cross(d, e2);
  const double det = dot(e1, p);
  if (std::fabs(det) < 1e-12) return false;
  const Vec3d s = Vec3d{0, 0, 0} - v[0];
  const double u = dot(s, p) / det;
  const Vec3d q = cross(s, e1);
  const double w = dot(d, q) / det;
  const double t = dot(e2, q) / det;
  constexpr double kMargin = 1e-7;
  return t > kMargin && u > kMargin && w > kMargin && u + w < 1 - kMargin;
}

struct Fixture {
  Vec3d centre;
  std::vector<CentralGrid::Triangle> triangles;  // relative to the origin
};

// Triangles scattered on a sphere shell around the centre, many near the
// cube map's face boundaries (|x| = |y| and the like), some large, some
// passing close to the centre.
Fixture make_fixture(std::mt19937& rng, int count) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0), size(0.01, 0.5), radius(0.5, 4.0);
  Fixture f;
  f.centre = {unit(rng) * 10, unit(rng) * 10, unit(rng) * 10};
  for (int i = 0; i < count; ++i) {
    Vec3d dir{unit(rng), unit(rng), unit(rng)};
    if (i % 3 == 0) dir.y = std::copysign(std::fabs(dir.x), dir.y);  // on a face boundary
    const double r = radius(rng) / std::sqrt(dot(dir, dir));
    const double s = (i % 17 == 0) ? 3.0 : size(rng);
    CentralGrid::Triangle t;
    for (auto& v : t.vertex)
      v = f.centre + Vec3d{dir.x * r + unit(rng) * s, dir.y * r + unit(rng) * s, dir.z * r + unit(rng) * s};
    t.error = 1e-15;
    t.id = static_cast<std::uint32_t>(i);
    f.triangles.push_back(t);
  }
  return f;
}

TEST(CentralGrid, RegionQueriesListEveryTriangleTheRegionMeets) {
  std::mt19937 rng(20261130);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), unit01(0.0, 1.0);
  std::size_t regions = 0, listed_regions = 0, multi_face = 0, hits = 0;
  for (int scene = 0; scene < 20; ++scene) {
    const Fixture f = make_fixture(rng, 300);
    const CentralGrid grid(f.centre, 1e-15, f.triangles);
    std::vector<std::array<Vec3d, 3>> rel;
    for (const auto& t : f.triangles)
      rel.push_back({t.vertex[0] - f.centre, t.vertex[1] - f.centre, t.vertex[2] - f.centre});
    for (int q = 0; q < 200; ++q) {
      Vec3d w{unit(rng), unit(rng), unit(rng)};
      if (q % 2 == 0) w.y = std::copysign(std::fabs(w.x) * (1 + 0.01 * unit(rng)), w.y);  // straddles two faces
      if (q % 5 == 0) w.z = std::copysign(std::fabs(w.x), w.z);                           // near a cube corner
      w = 3.0 * w;
      const double err = std::pow(10.0, -6.0 + 6.5 * unit01(rng));  // 1e-6 .. 3
      std::vector<std::uint32_t> ids;
      ++regions;
      if (!grid.candidates_in(w, err, ids)) continue;
      ++listed_regions;
      EXPECT_TRUE(std::is_sorted(ids.begin(), ids.end()));
      int faces_touched = 0;
      for (int a = 0; a < 3; ++a)
        faces_touched += (std::fabs(w[a]) + err >= std::max({std::fabs(w.x), std::fabs(w.y), std::fabs(w.z)}) - err);
      if (faces_touched > 1) ++multi_face;
      // Sample the region: its corners, centre and random points.
      std::vector<Vec3d> samples{w};
      for (int c = 0; c < 8; ++c)
        samples.push_back({w.x + ((c & 1) ? err : -err), w.y + ((c & 2) ? err : -err), w.z + ((c & 4) ? err : -err)});
      for (int k = 0; k < 40; ++k)
        samples.push_back({w.x + err * unit(rng), w.y + err * unit(rng), w.z + err * unit(rng)});
      for (const Vec3d& d : samples)
        for (std::size_t t = 0; t < rel.size(); ++t)
          if (ray_meets_clearly(d, rel[t])) {
            ++hits;
            EXPECT_TRUE(std::binary_search(ids.begin(), ids.end(), f.triangles[t].id))
                << "triangle " << t << " missing for region " << w.x << "," << w.y << "," << w.z << " +- " << err;
          }
    }
  }
  // The test means something only if regions were listed, spanned faces, and met triangles.
  EXPECT_GT(listed_regions, regions / 2);
  EXPECT_GT(multi_face, std::size_t{100});
  EXPECT_GT(hits, std::size_t{1000});
}

// ... and keeps it past the per-triangle box filter (EntryRange::may_contain),
// which drops listed triangles the direction certainly misses.
TEST(CentralGrid, PointQueriesListEveryTriangleTheDirectionMeets) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::size_t hits = 0, listed = 0, dropped = 0;
  for (int scene = 0; scene < 10; ++scene) {
    const Fixture f = make_fixture(rng, 300);
    const CentralGrid grid(f.centre, 1e-15, f.triangles);
    for (int q = 0; q < 2000; ++q) {
      Vec3d w{unit(rng), unit(rng), unit(rng)};
      if (q % 2 == 0) w.x = std::copysign(std::fabs(w.z), w.x);
      const CentralGrid::EntryRange range = grid.candidates(w, 1e-14);
      for (const CentralGrid::Entry& e : range) {
        ++listed;
        dropped += !range.may_contain(e.id);
      }
      for (const auto& t : f.triangles) {
        const std::array<Vec3d, 3> rel{t.vertex[0] - f.centre, t.vertex[1] - f.centre, t.vertex[2] - f.centre};
        if (!ray_meets_clearly(w, rel)) continue;
        ++hits;
        EXPECT_TRUE(std::any_of(range.begin(), range.end(), [&](const CentralGrid::Entry& e) { return e.id == t.id; }));
        EXPECT_TRUE(range.may_contain(t.id))
            << "triangle " << t.id << " dropped for direction " << w.x << "," << w.y << "," << w.z;
      }
    }
  }
  EXPECT_GT(hits, std::size_t{1000});
  // The filter means something: it drops a part of the listed triangles.
  EXPECT_GT(dropped, listed / 10) << "of " << listed << " listed";
  std::printf("point queries: %zu listed, %zu dropped by the boxes, %zu hits kept\n", listed, dropped, hits);
}

// A region around the centre itself meets every direction, on all six faces.
// On a coarse grid its cells are few enough to list: every triangle is
// listed.
TEST(CentralGrid, RegionAroundTheCentreListsEverything) {
  std::mt19937 rng(3);
  const Fixture f = make_fixture(rng, 50);
  const CentralGrid grid(f.centre, 0.0, f.triangles);
  std::vector<std::uint32_t> ids;
  ASSERT_TRUE(grid.candidates_in({0.1, 0.0, 0.0}, 0.5, ids)) << "a few hundred cells at most";
  EXPECT_EQ(ids.size(), f.triangles.size());
}

// On a fine grid the same region covers more cells than a query lists
// (kMaxCells in central_grid.cpp): the caller is told to take all().
TEST(CentralGrid, RegionAroundTheCentreOnAFineGridAsksForAll) {
  std::mt19937 rng(3);
  const Fixture f = make_fixture(rng, 50);
  const CentralGrid grid(f.centre, 0.0, f.triangles, 200.0);  // 200 cells per triangle
  std::vector<std::uint32_t> ids;
  EXPECT_FALSE(grid.candidates_in({0.1, 0.0, 0.0}, 0.5, ids));
}

// Each cube face is built when a query first reaches it: a grid queried from
// several threads at once, faces first reached in a shuffled order, lists
// exactly what a grid queried face by face in order lists (the same entries,
// in the same order), for point and region queries.
TEST(CentralGrid, FacesBuiltOnDemandListTheSameInAnyOrder) {
  std::mt19937 rng(31);
  const Fixture f = make_fixture(rng, 400);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Vec3d> directions;
  for (int k = 0; k < 600; ++k) directions.push_back({unit(rng), unit(rng), unit(rng)});
  auto answers = [&](const CentralGrid& grid, std::size_t k) {
    std::vector<std::uint32_t> out;
    for (const CentralGrid::Entry& e : grid.candidates(directions[k], 0.0)) out.push_back(e.id);
    std::vector<std::uint32_t> ids;
    out.push_back(grid.candidates_in(directions[k], 0.01, ids) ? 1u : 0u);
    out.insert(out.end(), ids.begin(), ids.end());
    return out;
  };
  const CentralGrid in_order(f.centre, 0.0, f.triangles);
  // Faces in order +x, -x, +y, -y, +z, -z first.
  for (int axis = 0; axis < 3; ++axis)
    for (const double sign : {1.0, -1.0}) {
      Vec3d w{0, 0, 0};
      w[axis] = sign;
      in_order.candidates(w, 0.0);
    }
  std::vector<std::vector<std::uint32_t>> expected;
  for (std::size_t k = 0; k < directions.size(); ++k) expected.push_back(answers(in_order, k));

  for (int run = 0; run < 4; ++run) {
    const CentralGrid shuffled(f.centre, 0.0, f.triangles);
    std::vector<std::size_t> order(directions.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::shuffle(order.begin(), order.end(), rng);
    std::vector<std::vector<std::uint32_t>> got(directions.size());
    tbb::parallel_for(std::size_t{0}, order.size(),
                      [&](std::size_t n) { got[order[n]] = answers(shuffled, order[n]); });
    std::size_t differ = 0;
    for (std::size_t k = 0; k < directions.size(); ++k) differ += got[k] != expected[k];
    EXPECT_EQ(differ, 0u) << "run " << run;
    EXPECT_EQ(shuffled.listed_entries(), in_order.listed_entries()) << "run " << run;
  }
}

}  // namespace
}  // namespace nearcap
