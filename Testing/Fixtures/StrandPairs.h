#pragma once
// Helpers shared by the tests of strands meeting strands (hair–hair contacts, the near
// field): a frame for a root, the distance between two centrelines, the strands as drawn.
#include "contact/SegmentGeometry.h"
#include "superhelix/SuperHelix.h"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace hair
{

/// A right-handed frame whose first column is `tangent`.
inline Eigen::Matrix3d frameWithTangent(const Eigen::Vector3d& tangent)
{
  Eigen::Matrix3d f;
  f.col(0) = tangent.normalized();
  f.col(1) = f.col(0).unitOrthogonal();
  f.col(2) = f.col(0).cross(f.col(1));
  return f;
}

/// Smallest distance between the centrelines of two strands (8 points per element).
inline double centrelineDistance(const SuperHelix& a, const SuperHelix& b)
{
  std::vector<Eigen::Vector3d> pa, pb;
  a.polyline(8, pa);
  b.polyline(8, pb);
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i + 1 < pa.size(); ++i)
    for (size_t j = 0; j + 1 < pb.size(); ++j)
    {
      double u, v;
      best = std::min(best, closestPointsOfSegments(pa[i], pa[i + 1], pb[j], pb[j + 1], u, v));
    }
  return std::sqrt(best);
}

/// The strands' drawn points, `perElement` per element (the pass-through count is taken on
/// them).
inline std::vector<std::vector<Eigen::Vector3d>>
drawnStrands(const std::vector<SuperHelix>& strands, int perElement)
{
  std::vector<std::vector<Eigen::Vector3d>> lines(strands.size());
  for (size_t k = 0; k < strands.size(); ++k)
    strands[k].polyline(perElement, lines[k]);
  return lines;
}

} // namespace hair
