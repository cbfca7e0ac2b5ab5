#include "geometry/UniformGrid.h"

#include "common/Parallel.h"

#include <algorithm>

namespace hair
{

void UniformGrid::build(const std::vector<Box3>& boxes, const std::vector<int>& groups,
                        const Eigen::Array3d& cell)
{
  Boxes = true;
  Count = boxes.size();
  BoxList = boxes;
  Points.clear();
  Cell = cell.max(1e-300);
  Inverse = Cell.inverse();
  Origin = boxes.empty() ? Eigen::Vector3d::Zero() : boxes[0].lo;
  for (const Box3& b : boxes)
    Origin = Origin.cwiseMin(b.lo);
  Entries.clear();
  for (std::size_t k = 0; k < boxes.size(); ++k)
  {
    const Eigen::Array3i lo = cellOf(boxes[k].lo), hi = cellOf(boxes[k].hi);
    const int group = groups.empty() ? -1 : groups[k];
    for (int x = lo.x(); x <= hi.x(); ++x)
      for (int y = lo.y(); y <= hi.y(); ++y)
        for (int z = lo.z(); z <= hi.z(); ++z)
          Entries.push_back(
              {static_cast<int>(k), group, x, y, z,
               static_cast<std::uint8_t>((x == lo.x()) | (y == lo.y()) << 1 | (z == lo.z()) << 2)});
  }
  sortEntries();
}

void UniformGrid::build(const std::vector<Eigen::Vector3d>& points, double cell)
{
  Boxes = false;
  Count = points.size();
  Points = points;
  BoxList.clear();
  Cell.setConstant(std::max(cell, 1e-300));
  Inverse = Cell.inverse();
  Origin = points.empty() ? Eigen::Vector3d::Zero() : points[0];
  for (const Eigen::Vector3d& p : points)
    Origin = Origin.cwiseMin(p);
  Entries.clear();
  Entries.reserve(points.size());
  for (std::size_t k = 0; k < points.size(); ++k)
  {
    const Eigen::Array3i c = cellOf(points[k]);
    Entries.push_back({static_cast<int>(k), -1, c.x(), c.y(), c.z(), 7});
  }
  sortEntries();
}

void UniformGrid::sortEntries()
{
  // Counting sort by hashed cell: O(entries). Cells with the same hash share a bucket and
  // are told apart by their coordinates.
  std::uint32_t buckets = 1;
  while (buckets < 2 * Entries.size())
    buckets <<= 1;
  Mask = buckets - 1;
  Start.assign(buckets + 1, 0);
  std::vector<std::uint32_t>& key = Keys;
  key.resize(Entries.size());
  Lowest.setConstant(std::numeric_limits<int>::max());
  Highest.setConstant(std::numeric_limits<int>::min());
  for (std::size_t e = 0; e < Entries.size(); ++e)
  {
    const Entry& en = Entries[e];
    key[e] = bucketOf(en.ix, en.iy, en.iz);
    ++Start[key[e] + 1];
    Lowest = Lowest.min(Eigen::Array3i(en.ix, en.iy, en.iz));
    Highest = Highest.max(Eigen::Array3i(en.ix, en.iy, en.iz));
  }
  for (std::uint32_t b = 0; b < buckets; ++b)
    Start[b + 1] += Start[b];
  Sorted.resize(Entries.size());
  std::vector<std::uint32_t> fill(Start.begin(), Start.end() - 1);
  for (std::size_t e = 0; e < Entries.size(); ++e)
    Sorted[fill[key[e]]++] = Entries[e];
}

void UniformGrid::overlappingPairs(std::vector<std::pair<int, int>>& out, int threads) const
{
  out.clear();
  if (!Boxes || Sorted.empty())
    return;
  // Pairs in each cell; a pair whose boxes share several cells is kept only in the cell
  // holding the low corner of the boxes' intersection. Blocks of buckets on the threads,
  // then sorted: the same pairs on any number of threads.
  const std::int64_t buckets = static_cast<std::int64_t>(Start.size()) - 1;
  const std::int64_t grain = std::max<std::int64_t>(256, buckets / 64);
  std::vector<std::vector<std::pair<int, int>>> found(
      static_cast<std::size_t>(blockCount(buckets, grain)));
  parallelBlocks(buckets, grain, threads,
                 [&](std::int64_t first, std::int64_t last)
                 {
                   std::vector<std::pair<int, int>>& mine = found[first / grain];
                   for (std::int64_t b = first; b < last; ++b)
                     for (std::uint32_t i = Start[b]; i + 1 < Start[b + 1]; ++i)
                     {
                       const Entry& ei = Sorted[i];
                       const Box3& bi = BoxList[ei.item];
                       for (std::uint32_t j = i + 1; j < Start[b + 1]; ++j)
                       {
                         const Entry& ej = Sorted[j];
                         if ((ei.group >= 0 && ei.group == ej.group) || ei.ix != ej.ix ||
                             ei.iy != ej.iy || ei.iz != ej.iz)
                           continue; // one group, or another cell with the same hash
                         // The low corner of the boxes' intersection is in the larger of
                         // their first cells along each axis: here if one of them starts
                         // here along each axis.
                         if ((ei.low | ej.low) != 7 || !bi.overlaps(BoxList[ej.item]))
                           continue;
                         mine.emplace_back(std::min(ei.item, ej.item), std::max(ei.item, ej.item));
                       }
                     }
                 });
  // Sorted by two counting sorts, on the second item then (stable) on the first: O(pairs +
  // items), no comparisons.
  std::size_t total = 0;
  for (const auto& list : found)
    total += list.size();
  std::vector<std::size_t> at(Count + 1, 0);
  auto cumulate = [&]()
  {
    for (std::size_t i = 0; i < Count; ++i)
      at[i + 1] += at[i];
  };
  for (const auto& list : found)
    for (const std::pair<int, int>& p : list)
      ++at[static_cast<std::size_t>(p.second) + 1];
  cumulate();
  std::vector<std::pair<int, int>> bySecond(total);
  for (const auto& list : found)
    for (const std::pair<int, int>& p : list)
      bySecond[at[static_cast<std::size_t>(p.second)]++] = p;
  found.clear();
  std::fill(at.begin(), at.end(), 0);
  for (const std::pair<int, int>& p : bySecond)
    ++at[static_cast<std::size_t>(p.first) + 1];
  cumulate();
  out.resize(total);
  for (const std::pair<int, int>& p : bySecond)
    out[at[static_cast<std::size_t>(p.first)]++] = p;
}

void UniformGrid::nearest(const Eigen::Vector3d& p, int k, std::vector<int>& out,
                          double maxDistance) const
{
  out.clear();
  if (Boxes || Count == 0 || k <= 0 || !(maxDistance >= 0))
    return;
  k = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(k), Count));
  // The best k so far, (distance, index), a max-heap: its top is the one to beat.
  using Found = std::pair<double, int>;
  std::vector<Found> best;
  best.reserve(static_cast<std::size_t>(k) + 1);
  auto consider = [&](int item)
  {
    const double d = (Points[item] - p).norm();
    if (!(d <= maxDistance))
      return;
    const Found f(d, item);
    if (static_cast<int>(best.size()) < k)
    {
      best.push_back(f);
      std::push_heap(best.begin(), best.end());
    }
    else if (f < best.front())
    {
      std::pop_heap(best.begin(), best.end());
      best.back() = f;
      std::push_heap(best.begin(), best.end());
    }
  };
  auto measureAll = [&]()
  {
    best.clear();
    for (std::size_t i = 0; i < Count; ++i)
      consider(static_cast<int>(i));
  };
  // Rings of cells (Chebyshev distance `ring` from p's cell c), clipped to the box of the
  // occupied cells: every point within ring × the cell's side of p lies in rings 0 … ring
  // (p may sit anywhere in its cell), so once the k-th nearest found is within that, no
  // later ring can hold a point as near (nor one at the same distance: ties stay by index).
  const Eigen::Array3i c = cellOf(p);
  const double side = Cell.minCoeff();
  const int first = std::max({(Lowest - c).maxCoeff(), (c - Highest).maxCoeff(), 0});
  const int last = std::max((c - Lowest).abs().maxCoeff(), (Highest - c).abs().maxCoeff());
  // Cells of the clipped cube of rings 0 … ring.
  auto cubeCells = [&](int ring) -> std::int64_t
  {
    if (ring < 0)
      return 0;
    const Eigen::Array3i lo = (c - ring).max(Lowest), hi = (c + ring).min(Highest);
    if ((hi < lo).any())
      return 0;
    return std::int64_t(hi.x() - lo.x() + 1) * (hi.y() - lo.y() + 1) * (hi.z() - lo.z() + 1);
  };
  // A cell costs about as much to look up as a point to measure.
  const std::int64_t budget = static_cast<std::int64_t>(Count) + 27;
  if (k == static_cast<int>(Count) && std::isinf(maxDistance))
    measureAll(); // every point is an answer
  else
    for (int ring = first; ring <= last; ++ring)
    {
      if (cubeCells(ring) > budget)
      {
        measureAll();
        break;
      }
      const Eigen::Array3i lo = (c - ring).max(Lowest), hi = (c + ring).min(Highest);
      for (int x = lo.x(); x <= hi.x(); ++x)
        for (int y = lo.y(); y <= hi.y(); ++y)
        {
          auto visit = [&](int z)
          { forEachInCell(x, y, z, [&](const Entry& e) { consider(e.item); }); };
          if (std::abs(x - c.x()) == ring || std::abs(y - c.y()) == ring)
            for (int z = lo.z(); z <= hi.z(); ++z)
              visit(z);
          else
          {
            if (c.z() - ring >= lo.z())
              visit(c.z() - ring);
            if (ring > 0 && c.z() + ring <= hi.z())
              visit(c.z() + ring);
          }
        }
      // Every point nearer than this has been seen (less a sliver for the rounding of the
      // points' cells).
      const double reach = (ring - CellSlack) * side;
      if (static_cast<int>(best.size()) == k && best.front().first <= reach)
        break;
      if (reach >= maxDistance)
        break;
    }
  std::sort_heap(best.begin(), best.end());
  out.resize(best.size());
  for (std::size_t i = 0; i < best.size(); ++i)
    out[i] = best[i].second;
}

} // namespace hair
