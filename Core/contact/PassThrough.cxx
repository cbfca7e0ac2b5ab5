#include "contact/PassThrough.h"

#include "contact/SegmentGeometry.h"
#include "geometry/UniformGrid.h"

#include <algorithm>
#include <cmath>

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
  // Every piece's box over both frames, grown by distance / 2, in a uniform grid of cell size
  // `distance` × 4: its pairs of overlapping boxes of different strands.
  struct Piece
  {
    int strand, piece;
  };
  std::vector<Piece> pieces;
  std::vector<Box3> boxes;
  std::vector<int> strandOf;
  for (int i = 0; i < strands; ++i)
  {
    const int n = static_cast<int>(std::min(before[i].size(), after[i].size()));
    for (int k = 0; k + 1 < n; ++k)
    {
      Box3 b{before[i][k], before[i][k]};
      for (const Eigen::Vector3d& p : {before[i][k + 1], after[i][k], after[i][k + 1]})
      {
        b.lo = b.lo.cwiseMin(p);
        b.hi = b.hi.cwiseMax(p);
      }
      b.lo.array() -= 0.5 * distance;
      b.hi.array() += 0.5 * distance;
      pieces.push_back({i, k});
      boxes.push_back(b);
      strandOf.push_back(i);
    }
  }
  UniformGrid grid;
  grid.build(boxes, strandOf, Eigen::Array3d::Constant(4 * distance));
  std::vector<std::pair<int, int>> pairs;
  grid.overlappingPairs(pairs);
  auto interior = [](double u) { return u > 0 && u < 1; };
  for (const auto& [first, second] : pairs)
  {
    // Pieces are numbered strand by strand: the first pair member is on the lower strand.
    const Piece& a = pieces[first];
    const Piece& b = pieces[second];
    const auto& A0 = before[a.strand];
    const auto& B0 = before[b.strand];
    const auto& A1 = after[a.strand];
    const auto& B1 = after[b.strand];
    double u0, v0, u1, v1;
    const double d0 = std::sqrt(closestPointsOfSegments(A0[a.piece], A0[a.piece + 1], B0[b.piece],
                                                        B0[b.piece + 1], u0, v0));
    const double d1 = std::sqrt(closestPointsOfSegments(A1[a.piece], A1[a.piece + 1], B1[b.piece],
                                                        B1[b.piece + 1], u1, v1));
    if (!interior(u0) || !interior(v0) || !interior(u1) || !interior(v1))
      continue;
    const Eigen::Vector3d n0 = A0[a.piece] + u0 * (A0[a.piece + 1] - A0[a.piece]) - B0[b.piece] -
                               v0 * (B0[b.piece + 1] - B0[b.piece]);
    const Eigen::Vector3d n1 = A1[a.piece] + u1 * (A1[a.piece + 1] - A1[a.piece]) - B1[b.piece] -
                               v1 * (B1[b.piece + 1] - B1[b.piece]);
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
  // In order (strandA, pieceA, strandB, pieceB): the pairs come sorted.
  return out;
}

} // namespace hair
