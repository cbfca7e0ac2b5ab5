#include "contact/SegmentGeometry.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace hair
{

namespace
{
double clamp01(double x)
{
  return x < 0 ? 0 : (x > 1 ? 1 : x);
}
} // namespace

double lengthInCylinder(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                        const Eigen::Vector3d& q0, const Eigen::Vector3d& q1, double R)
{
  const Eigen::Vector3d axis = q1 - q0, d = p1 - p0;
  const double lengthB = axis.norm();
  if (!(lengthB > 0))
    return 0;
  const Eigen::Vector3d e = axis / lengthB;
  // Along the axis: t(u) = t0 + u t1 must lie in [0, |B|]; across it: w(u) = w0 + u w1 with
  // |w(u)|² < R², a quadratic in u. Both are intervals of u; their overlap with [0, 1].
  const Eigen::Vector3d r0 = p0 - q0;
  const double t0 = r0.dot(e), t1 = d.dot(e);
  double lo = 0, hi = 1;
  if (std::abs(t1) > 1e-15 * (std::abs(t0) + lengthB))
  {
    const double a = -t0 / t1, b = (lengthB - t0) / t1;
    lo = std::max(lo, std::min(a, b));
    hi = std::min(hi, std::max(a, b));
  }
  else if (t0 < 0 || t0 > lengthB)
    return 0;
  const Eigen::Vector3d w0 = r0 - t0 * e, w1 = d - t1 * e;
  const double qa = w1.squaredNorm(), qb = 2 * w0.dot(w1), qc = w0.squaredNorm() - R * R;
  if (qa > 1e-30 * (qc > 0 ? qc : R * R))
  {
    const double disc = qb * qb - 4 * qa * qc;
    if (!(disc > 0))
      return 0;
    const double root = std::sqrt(disc);
    lo = std::max(lo, (-qb - root) / (2 * qa));
    hi = std::min(hi, (-qb + root) / (2 * qa));
  }
  else if (!(qc < 0))
    return 0; // parallel to the axis, at or beyond R
  return hi > lo ? (hi - lo) * d.norm() : 0;
}

double closestPointsOfSegments(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                               const Eigen::Vector3d& q0, const Eigen::Vector3d& q1, double& u,
                               double& v)
{
  // Minimize |p0 + u d1 − q0 − v d2|² over [0, 1]²: the unconstrained minimum, clamped
  // to one parameter's range, then the other re-solved and clamped (the standard result for
  // a convex quadratic on a square; e.g. Ericson, Real-Time Collision Detection, §5.1.9).
  const Eigen::Vector3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  const double tiny = 1e-300;
  if (a <= tiny && e <= tiny)
    u = v = 0;
  else if (a <= tiny)
  {
    u = 0;
    v = clamp01(f / e);
  }
  else
  {
    const double c = d1.dot(r);
    if (e <= tiny)
    {
      v = 0;
      u = clamp01(-c / a);
    }
    else
    {
      const double b = d1.dot(d2);
      const double denom = a * e - b * b;
      if (denom > 1e-12 * a * e)
        u = clamp01((b * f - c * e) / denom);
      else
      {
        // Parallel: any point of the overlap is closest; take the middle of the overlap of
        // [q0, q1] projected on [p0, p1] (the nearest end when they do not overlap), so
        // that parallel strands get contacts spread along them rather than at vertices.
        const double t0 = -c / a, t1 = (d2 - r).dot(d1) / a;
        const double lo = std::max(0.0, std::min(t0, t1)), hi = std::min(1.0, std::max(t0, t1));
        u = lo <= hi ? 0.5 * (lo + hi) : clamp01(0.5 * (t0 + t1));
      }
      v = (b * u + f) / e;
      if (v < 0)
      {
        v = 0;
        u = clamp01(-c / a);
      }
      else if (v > 1)
      {
        v = 1;
        u = clamp01((b - c) / a);
      }
    }
  }
  return (p0 + u * d1 - q0 - v * d2).squaredNorm();
}

} // namespace hair
