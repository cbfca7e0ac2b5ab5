#include "contact/PassThrough.h"

#include "contact/SegmentGeometry.h"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <unordered_map>

namespace hair
{

std::vector<PassThrough> findPassThroughs(const std::vector<std::vector<Eigen::Vector3d>>& before,
                                          const std::vector<std::vector<Eigen::Vector3d>>& after,
                                          double distance)
{
  std::vector<PassThrough> out;
  const int strands = static_cast<int>(std::min(before.size(), after.size()));
  if (!(distance > 0))
    return out;
  // Every piece's box over both frames, grown by distance / 2, in the cells of a uniform
  // grid of cell size `distance` × 4 (hashed); pairs of pieces of different strands sharing
  // a cell are tested once (in the cell of their boxes' low common corner).
  struct Box
  {
    int strand, piece;
    Eigen::Vector3d lo, hi;
  };
  std::vector<Box> boxes;
  for (int i = 0; i < strands; ++i)
  {
    const int n = static_cast<int>(std::min(before[i].size(), after[i].size()));
    for (int k = 0; k + 1 < n; ++k)
    {
      Box b{i, k, before[i][k], before[i][k]};
      for (const Eigen::Vector3d& p : {before[i][k + 1], after[i][k], after[i][k + 1]})
      {
        b.lo = b.lo.cwiseMin(p);
        b.hi = b.hi.cwiseMax(p);
      }
      b.lo.array() -= 0.5 * distance;
      b.hi.array() += 0.5 * distance;
      boxes.push_back(b);
    }
  }
  const double cell = 4 * distance;
  auto cellOf = [cell](const Eigen::Vector3d& x)
  { return (x.array() / cell).floor().cast<long long>().eval(); };
  struct Key
  {
    long long x, y, z;
    bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
  };
  struct Hash
  {
    size_t operator()(const Key& k) const
    {
      return static_cast<size_t>(k.x * 73856093LL ^ k.y * 19349663LL ^ k.z * 83492791LL);
    }
  };
  std::unordered_map<Key, std::vector<int>, Hash> grid;
  for (int b = 0; b < static_cast<int>(boxes.size()); ++b)
  {
    const auto lo = cellOf(boxes[b].lo), hi = cellOf(boxes[b].hi);
    for (long long x = lo.x(); x <= hi.x(); ++x)
      for (long long y = lo.y(); y <= hi.y(); ++y)
        for (long long z = lo.z(); z <= hi.z(); ++z)
          grid[{x, y, z}].push_back(b);
  }
  auto interior = [](double u) { return u > 0 && u < 1; };
  for (const auto& [key, list] : grid)
    for (size_t i = 0; i < list.size(); ++i)
      for (size_t j = i + 1; j < list.size(); ++j)
      {
        const Box &p = boxes[list[i]], &q = boxes[list[j]];
        if (p.strand == q.strand || (p.lo.array() > q.hi.array()).any() ||
            (q.lo.array() > p.hi.array()).any())
          continue;
        const auto corner = cellOf(p.lo.cwiseMax(q.lo));
        if (corner.x() != key.x || corner.y() != key.y || corner.z() != key.z)
          continue;
        const Box& a = p.strand < q.strand ? p : q;
        const Box& b = p.strand < q.strand ? q : p;
        const auto& A0 = before[a.strand];
        const auto& B0 = before[b.strand];
        const auto& A1 = after[a.strand];
        const auto& B1 = after[b.strand];
        double u0, v0, u1, v1;
        const double d0 = std::sqrt(closestPointsOfSegments(A0[a.piece], A0[a.piece + 1],
                                                            B0[b.piece], B0[b.piece + 1], u0, v0));
        const double d1 = std::sqrt(closestPointsOfSegments(A1[a.piece], A1[a.piece + 1],
                                                            B1[b.piece], B1[b.piece + 1], u1, v1));
        if (!interior(u0) || !interior(v0) || !interior(u1) || !interior(v1))
          continue;
        const Eigen::Vector3d n0 = A0[a.piece] + u0 * (A0[a.piece + 1] - A0[a.piece]) -
                                   B0[b.piece] - v0 * (B0[b.piece + 1] - B0[b.piece]);
        const Eigen::Vector3d n1 = A1[a.piece] + u1 * (A1[a.piece + 1] - A1[a.piece]) -
                                   B1[b.piece] - v1 * (B1[b.piece + 1] - B1[b.piece]);
        if (!(n0.dot(n1) < 0))
          continue;
        // Within the contact distance at some moment of the motion from one frame to the
        // other, taken linear: the distance of the segment from n0 to n1 to the origin.
        const Eigen::Vector3d dn = n1 - n0;
        const double t =
            dn.squaredNorm() > 0 ? std::clamp(-n0.dot(dn) / dn.squaredNorm(), 0.0, 1.0) : 0.0;
        if ((n0 + t * dn).norm() < distance)
          out.push_back({a.strand, a.piece, b.strand, b.piece, d0, d1});
      }
  std::sort(out.begin(), out.end(),
            [](const PassThrough& x, const PassThrough& y)
            {
              return std::tie(x.strandA, x.pieceA, x.strandB, x.pieceB) <
                     std::tie(y.strandA, y.pieceA, y.strandB, y.pieceB);
            });
  return out;
}

} // namespace hair
