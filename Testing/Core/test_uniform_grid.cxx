// geometry/UniformGrid against brute force on random boxes and points (fixed seeds): the
// overlapping pairs of different groups, once each and the same on 1 and 2 threads; the
// points within a radius; the k nearest, ties by index. Negative coordinates, boxes spanning
// many cells, anisotropic cells, points sparse or all in one cell, exact ties, empty grids.
#include "geometry/UniformGrid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

using namespace hair;

namespace
{
const double Infinity = std::numeric_limits<double>::infinity();

Eigen::Vector3d uniformPoint(std::mt19937& rng, double lo, double hi)
{
  std::uniform_real_distribution<double> u(lo, hi);
  return Eigen::Vector3d(u(rng), u(rng), u(rng));
}

/// `count` boxes with corners in [-span, span]³ and sides in [smallest, largest] per axis.
std::vector<Box3> randomBoxes(std::mt19937& rng, int count, double span, double smallest,
                              double largest)
{
  std::uniform_real_distribution<double> side(smallest, largest);
  std::vector<Box3> boxes(static_cast<std::size_t>(count));
  for (Box3& b : boxes)
  {
    b.lo = uniformPoint(rng, -span, span);
    b.hi = b.lo + Eigen::Vector3d(side(rng), side(rng), side(rng));
  }
  return boxes;
}

std::vector<int> randomGroups(std::mt19937& rng, int count, int groups)
{
  std::uniform_int_distribution<int> g(-1, groups - 1); // -1: in no group
  std::vector<int> out(static_cast<std::size_t>(count));
  for (int& x : out)
    x = g(rng);
  return out;
}

std::vector<std::pair<int, int>> brutePairs(const std::vector<Box3>& boxes,
                                            const std::vector<int>& groups)
{
  std::vector<std::pair<int, int>> out;
  for (int i = 0; i < static_cast<int>(boxes.size()); ++i)
    for (int j = i + 1; j < static_cast<int>(boxes.size()); ++j)
    {
      const bool together = !groups.empty() && groups[i] >= 0 && groups[i] == groups[j];
      if (!together && boxes[i].overlaps(boxes[j]))
        out.emplace_back(i, j);
    }
  return out;
}

std::vector<int> bruteWithin(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& p,
                             double radius)
{
  std::vector<int> out;
  for (int i = 0; i < static_cast<int>(points.size()); ++i)
    if ((points[i] - p).norm() <= radius)
      out.push_back(i);
  return out;
}

std::vector<int> bruteNearest(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& p,
                              int k, double maxDistance = Infinity)
{
  std::vector<std::pair<double, int>> all;
  for (int i = 0; i < static_cast<int>(points.size()); ++i)
  {
    const double d = (points[i] - p).norm();
    if (d <= maxDistance)
      all.emplace_back(d, i);
  }
  std::sort(all.begin(), all.end());
  std::vector<int> out;
  for (int i = 0; i < std::min<int>(k, static_cast<int>(all.size())); ++i)
    out.push_back(all[i].second);
  return out;
}

std::vector<int> within(const UniformGrid& grid, const Eigen::Vector3d& p, double radius)
{
  std::vector<int> out;
  grid.forEachWithin(p, radius, [&](int i) { out.push_back(i); });
  std::sort(out.begin(), out.end());
  return out;
}

/// Queries: at some of the points, near them, inside and around their box, and far outside.
std::vector<Eigen::Vector3d> queries(std::mt19937& rng, const std::vector<Eigen::Vector3d>& points,
                                     double span)
{
  std::vector<Eigen::Vector3d> out;
  for (std::size_t i = 0; i < points.size() && i < 20; ++i)
    out.push_back(points[i * 7 % points.size()]);
  for (int i = 0; i < 40; ++i)
    out.push_back(uniformPoint(rng, -1.5 * span, 1.5 * span));
  out.push_back(Eigen::Vector3d(-20 * span, 3 * span, 0));
  out.push_back(Eigen::Vector3d::Constant(1e6 * span));
  return out;
}

/// Points of a cubic lattice of side `n` and spacing 0.125 (exact in binary) about
/// `corner`, in a shuffled order (indices do not follow the lattice).
std::vector<Eigen::Vector3d> lattice(int n, const Eigen::Vector3d& corner, std::mt19937& rng)
{
  std::vector<Eigen::Vector3d> out;
  for (int x = 0; x < n; ++x)
    for (int y = 0; y < n; ++y)
      for (int z = 0; z < n; ++z)
        out.push_back(corner + 0.125 * Eigen::Vector3d(x, y, z));
  std::shuffle(out.begin(), out.end(), rng);
  return out;
}
} // namespace

TEST(UniformGrid, OverlappingPairsAreTheBruteForcePairsOnceEach)
{
  struct Case
  {
    const char* what;
    int boxes;
    double smallest, largest;
    Eigen::Array3d cell;
    int groups; // 0: no groups
  };
  const Case cases[] = {
      {"boxes about a cell", 800, 0.01, 0.2, Eigen::Array3d::Constant(0.1), 40},
      {"no groups", 400, 0.01, 0.2, Eigen::Array3d::Constant(0.1), 0},
      {"boxes spanning many cells", 80, 0.2, 0.8, Eigen::Array3d::Constant(0.05), 10},
      {"anisotropic cells", 600, 0.0, 0.3, Eigen::Array3d(0.02, 0.1, 0.4), 30},
      {"one cell for all", 300, 0.01, 0.2, Eigen::Array3d::Constant(10.0), 5},
      {"cells far smaller than the boxes", 20, 0.5, 1.0, Eigen::Array3d::Constant(0.04), 3},
  };
  std::mt19937 rng(20261203);
  for (const Case& c : cases)
    for (double span : {1.0, 1e-3})
    {
      SCOPED_TRACE(std::string(c.what) + ", span " + std::to_string(span));
      std::vector<Box3> boxes =
          randomBoxes(rng, c.boxes, span, c.smallest * span, c.largest * span);
      const std::vector<int> groups =
          c.groups > 0 ? randomGroups(rng, c.boxes, c.groups) : std::vector<int>();
      UniformGrid grid;
      grid.build(boxes, groups, c.cell * span);
      EXPECT_EQ(grid.size(), boxes.size());
      EXPECT_GE(grid.entries(), boxes.size());
      EXPECT_TRUE((grid.cellSize() == c.cell * span).all());
      std::vector<std::pair<int, int>> one, two;
      grid.overlappingPairs(one, 1);
      grid.overlappingPairs(two, 2);
      const std::vector<std::pair<int, int>> expected = brutePairs(boxes, groups);
      EXPECT_FALSE(expected.empty());
      EXPECT_EQ(one, expected); // sorted, each pair once
      EXPECT_EQ(two, one);
    }
}

TEST(UniformGrid, BoxesTouchingOnCellBoundariesArePaired)
{
  // Cubes of side 0.125 on a lattice of the same spacing, with cells of that size: every
  // box's faces lie on cell boundaries, and neighbours share faces, edges or corners
  // (closed boxes overlap there). Each cube its own group, then every other one in one.
  std::mt19937 rng(7);
  const std::vector<Eigen::Vector3d> corners = lattice(6, Eigen::Vector3d(-0.5, -0.25, 0), rng);
  std::vector<Box3> boxes;
  for (const Eigen::Vector3d& x : corners)
    boxes.push_back({x, x + Eigen::Vector3d::Constant(0.125)});
  std::vector<int> own(boxes.size()), halves(boxes.size());
  std::iota(own.begin(), own.end(), 0);
  for (std::size_t i = 0; i < boxes.size(); ++i)
    halves[i] = static_cast<int>(i % 2);
  for (const std::vector<int>* groups : {&own, &halves})
    for (double cell : {0.125, 0.0625, 0.3})
    {
      UniformGrid grid;
      grid.build(boxes, *groups, Eigen::Array3d::Constant(cell));
      std::vector<std::pair<int, int>> one, two;
      grid.overlappingPairs(one, 1);
      grid.overlappingPairs(two, 2);
      const std::vector<std::pair<int, int>> expected = brutePairs(boxes, *groups);
      EXPECT_EQ(one, expected) << "cell " << cell;
      EXPECT_EQ(two, one);
    }
  // 26 neighbours for an inner cube of the 6³ lattice, each pair once: 3 · 6 · 6 · 5 face
  // pairs, 2 · 3 · 6 · 5 · 5 edge pairs, 4 · 5³ corner pairs.
  UniformGrid grid;
  grid.build(boxes, own, Eigen::Array3d::Constant(0.125));
  std::vector<std::pair<int, int>> pairs;
  grid.overlappingPairs(pairs);
  EXPECT_EQ(pairs.size(), std::size_t(3 * 36 * 5 + 2 * 3 * 6 * 25 + 4 * 125));
}

TEST(UniformGrid, ForEachWithinIsTheBruteForceSet)
{
  std::mt19937 rng(11);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 1500; ++i)
    points.push_back(uniformPoint(rng, -1, 1));
  for (int i = 0; i < 300; ++i) // a dense clump, and duplicates
    points.push_back(Eigen::Vector3d(-0.7, 0.2, -0.9) + uniformPoint(rng, -0.01, 0.01));
  for (int i = 0; i < 20; ++i)
    points.push_back(points[static_cast<std::size_t>(i) * 13]);
  for (double cell : {0.003, 0.05, 0.3, 10.0})
  {
    UniformGrid grid;
    grid.build(points, cell);
    EXPECT_EQ(grid.size(), points.size());
    EXPECT_EQ(grid.entries(), points.size());
    for (const Eigen::Vector3d& p : queries(rng, points, 1))
      for (double radius : {0.0, 0.004, 0.05, 0.13, 0.7, 5.0})
        EXPECT_EQ(within(grid, p, radius), bruteWithin(points, p, radius))
            << "cell " << cell << ", radius " << radius << ", at " << p.transpose();
  }
}

TEST(UniformGrid, ForEachWithinKeepsPointsExactlyAtTheRadius)
{
  // A lattice of spacing 0.125: from a lattice point, its 6 face neighbours are at 0.125
  // (exactly, where the lattice's corner is exact in binary) and the 12 edge neighbours at
  // 0.125 √2, with cells of the spacing or not, and about negative coordinates.
  std::mt19937 rng(3);
  for (const Eigen::Vector3d& corner :
       {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(-3.3, -0.1, -17.0), Eigen::Vector3d(5, -2, 1)})
  {
    const std::vector<Eigen::Vector3d> points = lattice(5, corner, rng);
    for (double cell : {0.125, 0.1, 0.25, 0.0625})
    {
      UniformGrid grid;
      grid.build(points, cell);
      for (const Eigen::Vector3d& p : points)
        for (double radius : {0.0, 0.125, 0.125 * std::sqrt(2.0), 0.25, 0.1})
          EXPECT_EQ(within(grid, p, radius), bruteWithin(points, p, radius))
              << "cell " << cell << ", radius " << radius;
      if (corner.x() != -3.3) // lattice points exact in binary
      {
        const Eigen::Vector3d centre = corner + Eigen::Vector3d::Constant(0.25);
        EXPECT_EQ(within(grid, centre, 0.125).size(), 7u); // itself and 6 face neighbours
      }
    }
  }
}

TEST(UniformGrid, NearestIsTheBruteForceKNearest)
{
  std::mt19937 rng(5);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 1000; ++i)
    points.push_back(uniformPoint(rng, -1, 1));
  for (int i = 0; i < 100; ++i) // a dense clump
    points.push_back(Eigen::Vector3d(0.5, -0.5, 0.1) + uniformPoint(rng, -0.02, 0.02));
  const int count = static_cast<int>(points.size());
  // Cells from sparse (a point per ~10⁵ cells) to all the points in one cell.
  for (double cell : {0.002, 0.02, 0.1, 0.5, 100.0})
  {
    UniformGrid grid;
    grid.build(points, cell);
    std::vector<int> found;
    for (const Eigen::Vector3d& p : queries(rng, points, 1))
      for (int k : {1, 2, 4, 11, count - 1, count, count + 5})
        for (double maxDistance : {Infinity, 0.3, 0.05, 0.0})
        {
          grid.nearest(p, k, found, maxDistance);
          EXPECT_EQ(found, bruteNearest(points, p, k, maxDistance))
              << "cell " << cell << ", k " << k << ", maxDistance " << maxDistance << ", at "
              << p.transpose();
        }
  }
}

TEST(UniformGrid, NearestBreaksTiesByIndex)
{
  // A shuffled lattice of spacing 0.125: from the centre of a lattice cube its 8 corners are
  // equally near, from a lattice point its 6 face neighbours; from a point duplicated, the
  // copies. The nearest k take the lowest indices among equals.
  std::mt19937 rng(9);
  std::vector<Eigen::Vector3d> points = lattice(6, Eigen::Vector3d(-0.4, -0.3, -0.2), rng);
  for (int i = 0; i < 10; ++i)
    points.push_back(points[static_cast<std::size_t>(i) * 17]);
  for (double cell : {0.125, 0.1, 0.3, 1.0})
  {
    UniformGrid grid;
    grid.build(points, cell);
    std::vector<int> found;
    for (std::size_t i = 0; i < points.size(); i += 3)
      for (const Eigen::Vector3d& p :
           {points[i], Eigen::Vector3d(points[i] + Eigen::Vector3d::Constant(0.0625))})
        for (int k : {1, 2, 3, 5, 9, 20})
          for (double maxDistance : {Infinity, 0.125, 0.0625 * std::sqrt(3.0)})
          {
            grid.nearest(p, k, found, maxDistance);
            EXPECT_EQ(found, bruteNearest(points, p, k, maxDistance))
                << "cell " << cell << ", k " << k << ", maxDistance " << maxDistance;
          }
  }
}

TEST(UniformGrid, NearestAmongSparsePoints)
{
  // Points far apart (kilometres, at negative coordinates) on small cells: rings would be
  // many and empty; and a few points far from a dense set.
  std::mt19937 rng(13);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 60; ++i)
    points.push_back(uniformPoint(rng, -5000, -1000));
  for (int i = 0; i < 200; ++i)
    points.push_back(uniformPoint(rng, 0, 0.1));
  UniformGrid grid;
  grid.build(points, 0.01);
  std::vector<int> found;
  for (const Eigen::Vector3d& p : queries(rng, points, 3000))
    for (int k : {1, 3, 70})
    {
      grid.nearest(p, k, found);
      EXPECT_EQ(found, bruteNearest(points, p, k));
      grid.nearest(p, k, found, 100.0);
      EXPECT_EQ(found, bruteNearest(points, p, k, 100.0));
    }
}

TEST(UniformGrid, EmptyGridsAndTheOtherKindOfItems)
{
  UniformGrid grid;
  std::vector<int> found{1, 2};
  std::vector<std::pair<int, int>> pairs{{0, 1}};
  int calls = 0;
  auto count = [&](int) { ++calls; };

  grid.nearest(Eigen::Vector3d::Zero(), 3, found); // never built
  EXPECT_TRUE(found.empty());
  grid.build(std::vector<Eigen::Vector3d>(), 0.1);
  EXPECT_EQ(grid.size(), 0u);
  EXPECT_EQ(grid.entries(), 0u);
  grid.nearest(Eigen::Vector3d::Zero(), 3, found);
  EXPECT_TRUE(found.empty());
  grid.forEachWithin(Eigen::Vector3d::Zero(), 1e9, count);
  grid.overlappingPairs(pairs);
  EXPECT_TRUE(pairs.empty());

  grid.build(std::vector<Box3>(), {}, Eigen::Array3d::Constant(0.1));
  EXPECT_EQ(grid.size(), 0u);
  pairs = {{0, 1}};
  grid.overlappingPairs(pairs, 2);
  EXPECT_TRUE(pairs.empty());

  // Boxes answer no point query; points no pair query.
  std::mt19937 rng(17);
  const std::vector<Box3> boxes = randomBoxes(rng, 50, 1, 0.1, 0.5);
  grid.build(boxes, {}, Eigen::Array3d::Constant(0.2));
  found = {1};
  grid.nearest(Eigen::Vector3d::Zero(), 3, found);
  EXPECT_TRUE(found.empty());
  grid.forEachWithin(Eigen::Vector3d::Zero(), 1e9, count);
  std::vector<Eigen::Vector3d> points;
  for (const Box3& b : boxes)
    points.push_back(b.lo);
  grid.build(points, 0.2);
  grid.overlappingPairs(pairs);
  EXPECT_TRUE(pairs.empty());
  EXPECT_EQ(calls, 0);

  // No answer for k ≤ 0 or a negative or NaN maxDistance; one grid rebuilt answers as a new
  // one.
  grid.nearest(Eigen::Vector3d::Zero(), 0, found);
  EXPECT_TRUE(found.empty());
  grid.nearest(Eigen::Vector3d::Zero(), 2, found, -1);
  EXPECT_TRUE(found.empty());
  grid.nearest(Eigen::Vector3d::Zero(), 2, found, std::nan(""));
  EXPECT_TRUE(found.empty());
  grid.nearest(Eigen::Vector3d::Zero(), 5, found);
  EXPECT_EQ(found, bruteNearest(points, Eigen::Vector3d::Zero(), 5));
  grid.build(boxes, {}, Eigen::Array3d::Constant(0.2));
  grid.overlappingPairs(pairs);
  EXPECT_EQ(pairs, brutePairs(boxes, {}));
}

TEST(UniformGrid, CellsAreFlooredFromTheLowestItem)
{
  const std::vector<Eigen::Vector3d> points = {{-1.0, -2.0, 0.5}, {0.3, -0.1, -0.7}};
  UniformGrid grid;
  grid.build(points, 0.5);
  EXPECT_TRUE((grid.cellSize() == 0.5).all());
  EXPECT_TRUE((grid.cellOf(Eigen::Vector3d(-1.0, -2.0, -0.7)) == Eigen::Array3i(0, 0, 0)).all());
  EXPECT_TRUE((grid.cellOf(points[1]) == Eigen::Array3i(2, 3, 0)).all());
  EXPECT_TRUE((grid.cellOf(Eigen::Vector3d(-1.1, -2.0, -0.7)) == Eigen::Array3i(-1, 0, 0)).all());
  // Far outside: clamped, not overflowed.
  const Eigen::Array3i far = grid.cellOf(Eigen::Vector3d(1e300, -1e300, 0));
  EXPECT_GT(far.x(), 1 << 28);
  EXPECT_LT(far.y(), -(1 << 28));
}
