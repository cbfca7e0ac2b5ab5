#pragma once
// The one spatial index of Core: items (points, or axis-aligned boxes) binned into the cells
// of a uniform grid, the cells hashed (no bounds to fit, no memory for empty space) and the
// entries counting-sorted by hashed cell, O(items). Every neighbour search of Core goes
// through it: the hair–hair near field's pair search (contact/NearField), the coupled
// solve's broad phase (contact/HairHairContacts), the pass-through count
// (contact/PassThrough), Hair Interpolation's binding of rendered strands to guides
// (render/HairInterpolation) and the ghost strands of MPI runs (simulation/GhostStrands).
#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace hair
{

/// An axis-aligned box [lo, hi].
struct Box3
{
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
  bool overlaps(const Box3& o) const
  {
    return !((lo.array() > o.hi.array()).any() || (o.lo.array() > hi.array()).any());
  }
};

class UniformGrid
{
public:
  /// Bins boxes into every cell each overlaps, cells of size `cell` per axis (each > 0).
  /// `groups` (empty, or one per box): boxes of the same group are never paired
  /// (overlappingPairs), e.g. the pieces of one strand.
  void build(const std::vector<Box3>& boxes, const std::vector<int>& groups,
             const Eigen::Array3d& cell);
  /// Bins points, one cell each, cubic cells of side `cell` > 0.
  void build(const std::vector<Eigen::Vector3d>& points, double cell);

  std::size_t size() const { return Count; }
  const Eigen::Array3d& cellSize() const { return Cell; }
  /// Entries (item, cell) binned: for boxes, the cells each spans summed over the boxes.
  std::size_t entries() const { return Sorted.size(); }

  /// Boxes only: every pair (i, j), i < j, of overlapping boxes of different groups, once
  /// each, sorted, found on up to `threads` threads (the same pairs on any number).
  void overlappingPairs(std::vector<std::pair<int, int>>& out, int threads = 1) const;

  /// Points only: calls f(i) for every point within `radius` of p ((point − p).norm() ≤
  /// radius, exactly), in no particular order (a radius spanning more cells than there are
  /// points measures every point).
  template <class F>
  void forEachWithin(const Eigen::Vector3d& p, double radius, F&& f) const;
  /// Points only: the (up to) k points nearest to p, among those within maxDistance, nearest
  /// first by (point − p).norm(), ties by index. Searches rings of cells outwards until the
  /// k found are closer than any point of the next ring could be; a search that would visit
  /// more cells than there are points (a point far from the others, k about the count)
  /// measures every point instead.
  void nearest(const Eigen::Vector3d& p, int k, std::vector<int>& out,
               double maxDistance = std::numeric_limits<double>::infinity()) const;

  /// The cell holding x (integer coordinates; clamped to ±2²⁹ for x far outside the
  /// items, so that the conversion and the searches' cell arithmetic stay in range).
  Eigen::Array3i cellOf(const Eigen::Vector3d& x) const
  {
    return ((x - Origin).array() * Inverse).floor().max(-FarCell).min(FarCell).cast<int>();
  }

private:
  static constexpr double FarCell = 536870912.0; // 2^29
  // A point's cell is found within this fraction of a cell of where exact arithmetic puts
  // it, for coordinates up to ~10^9 cells from the origin: searches widen by it.
  static constexpr double CellSlack = 1e-6;
  struct Entry
  {
    int item, group;
    int ix, iy, iz;
    std::uint8_t low; // boxes: bit a set where the cell is the box's first along axis a
  };
  std::uint32_t bucketOf(int x, int y, int z) const
  {
    return (static_cast<std::uint32_t>(x) * 73856093u ^ static_cast<std::uint32_t>(y) * 19349663u ^
            static_cast<std::uint32_t>(z) * 83492791u) &
           Mask;
  }
  void sortEntries();
  // Calls f(entry) for each entry of cell (x, y, z).
  template <class F>
  void forEachInCell(int x, int y, int z, F&& f) const
  {
    const std::uint32_t b = bucketOf(x, y, z);
    for (std::uint32_t e = Start[b]; e < Start[b + 1]; ++e)
    {
      const Entry& en = Sorted[e];
      if (en.ix == x && en.iy == y && en.iz == z)
        f(en);
    }
  }

  bool Boxes = false;
  std::size_t Count = 0;
  Eigen::Vector3d Origin = Eigen::Vector3d::Zero();
  Eigen::Array3d Cell = Eigen::Array3d::Ones(), Inverse = Eigen::Array3d::Ones();
  std::vector<Box3> BoxList;
  std::vector<Eigen::Vector3d> Points;
  std::vector<Entry> Entries, Sorted;
  std::vector<std::uint32_t> Start, Keys;
  std::uint32_t Mask = 0;
  Eigen::Array3i Lowest = Eigen::Array3i::Zero(), Highest = Eigen::Array3i::Zero();
};

template <class F>
void UniformGrid::forEachWithin(const Eigen::Vector3d& p, double radius, F&& f) const
{
  if (Boxes || Count == 0 || !(radius >= 0))
    return;
  const Eigen::Array3d reach = radius + CellSlack * Cell;
  const Eigen::Array3i lo = cellOf(p.array() - reach).max(Lowest);
  const Eigen::Array3i hi = cellOf(p.array() + reach).min(Highest);
  // norm() ≤ radius exactly: the squares decide except within rounding of the boundary.
  const double r2 = radius * radius, near2 = r2 * (1 + 1e-12);
  auto test = [&](int item)
  {
    const double d2 = (Points[item] - p).squaredNorm();
    if (d2 <= r2 || (d2 <= near2 && std::sqrt(d2) <= radius))
      f(item);
  };
  if ((hi < lo).any())
    return;
  const Eigen::Array<std::int64_t, 3, 1> span = (hi - lo + 1).cast<std::int64_t>();
  if (span.prod() > static_cast<std::int64_t>(Count) + 27)
  {
    // More cells than points (a radius of many cells): every point is measured instead.
    for (std::size_t i = 0; i < Count; ++i)
      test(static_cast<int>(i));
    return;
  }
  for (int x = lo.x(); x <= hi.x(); ++x)
    for (int y = lo.y(); y <= hi.y(); ++y)
      for (int z = lo.z(); z <= hi.z(); ++z)
        forEachInCell(x, y, z, [&](const Entry& e) { test(e.item); });
}

} // namespace hair
