#pragma once
// Helpers shared by the tests of strands meeting strands (hair–hair contacts, the near
// field): a frame for a root, the distance between two centrelines, the strands as drawn.
#include "contact/PassThrough.h"
#include "contact/SegmentGeometry.h"
#include "superhelix/SuperHelix.h"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <functional>
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

/// Two straight 20 cm strands of 10 elements, gravity off: B along z, its root fixed at the
/// origin; A along x, its root at (x, 0.01 − speed t, z), driven down through B at `speed`.
inline Status drivenPair(double speed, double x, double z, std::vector<SuperHelix>& strands)
{
  const HairParameters hair = HairParameters::roundStraight();
  strands.assign(2, SuperHelix());
  for (int i = 0; i < 2; ++i)
  {
    StrandSpec s = StrandSpec::uniform(0.2, 10, hair);
    s.id = i;
    s.gravity.setZero();
    if (i == 0)
      s.root = [speed, x, z](double t)
      {
        RootState r;
        r.position = Eigen::Vector3d(x, 0.01 - speed * t, z);
        r.velocity = Eigen::Vector3d(0, -speed, 0);
        r.orientation = frameWithTangent({1, 0, 0});
        return r;
      };
    else
    {
      RootState r;
      r.orientation = frameWithTangent({0, 0, 1});
      s.root = [r](double) { return r; };
    }
    if (Status st = strands[i].initialize(s); !st)
      return st;
  }
  return Status::Ok();
}

/// `frames` calls of `step` on a pair of strands: the pass-throughs between frames counted on
/// the strands drawn at `perElement` points per element within `distance`, and the closest
/// approach of their centrelines.
inline Status runPair(std::vector<SuperHelix>& strands, int frames, int perElement, double distance,
                      const std::function<Status(std::vector<SuperHelix>&)>& step, long& passes,
                      double& closest)
{
  passes = 0;
  closest = std::numeric_limits<double>::infinity();
  std::vector<std::vector<Eigen::Vector3d>> before = drawnStrands(strands, perElement);
  for (int f = 0; f < frames; ++f)
  {
    if (Status st = step(strands); !st)
      return st;
    const std::vector<std::vector<Eigen::Vector3d>> after = drawnStrands(strands, perElement);
    passes += static_cast<long>(findPassThroughs(before, after, distance).size());
    closest = std::min(closest, centrelineDistance(strands[0], strands[1]));
    before = after;
  }
  return Status::Ok();
}

} // namespace hair
