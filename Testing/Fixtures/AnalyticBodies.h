#pragma once
// Analytic bodies for the collision-table tests: exact ray crossings, exact normals, exact
// inside test and a lower bound of the distance to the surface. None of it comes from the
// code under test.
#include "geometry/TriangleMesh.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

namespace hairtest
{

struct AnalyticBody : hair::RayCaster
{
  virtual bool inside(const Eigen::Vector3d& p) const = 0;
  /// A lower bound of the distance from p to the surface.
  virtual double distanceBound(const Eigen::Vector3d& p) const = 0;
};

/// Ellipsoid with semi-axes (a, b, c) along x, y, z about `centre` (a sphere when equal).
struct Ellipsoid : AnalyticBody
{
  Eigen::Vector3d centre, semi;
  Ellipsoid(Eigen::Vector3d c, Eigen::Vector3d s) : centre(c), semi(s) {}
  void castAll(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
               std::vector<hair::RayHit>& hits) const override
  {
    hits.clear();
    const Eigen::Vector3d os = (o - centre).cwiseQuotient(semi), ds = d.cwiseQuotient(semi);
    const double A = ds.squaredNorm(), B = 2 * os.dot(ds), C = os.squaredNorm() - 1;
    const double disc = B * B - 4 * A * C;
    if (disc <= 0)
    {
      return;
    }
    const double sq = std::sqrt(disc);
    for (double t : {(-B - sq) / (2 * A), (-B + sq) / (2 * A)})
    {
      if (t > 0)
      {
        hits.push_back({t, normal(o + t * d)});
      }
    }
  }
  Eigen::Vector3d normal(const Eigen::Vector3d& p) const
  {
    return (p - centre).cwiseQuotient(semi.cwiseProduct(semi)).normalized();
  }
  double level(const Eigen::Vector3d& p) const { return (p - centre).cwiseQuotient(semi).norm(); }
  bool inside(const Eigen::Vector3d& p) const override { return level(p) < 1; }
  // p lies on the ellipsoid scaled by s = level(p) about the centre; two homothetic
  // ellipsoids are nowhere closer than |s - 1| times the smallest semi-axis.
  double distanceBound(const Eigen::Vector3d& p) const override
  {
    return std::abs(level(p) - 1) * semi.minCoeff();
  }
};

/// Capped cylinder: radius R about the vertical line through `centre`, heights
/// centre.y ± halfHeight, flat caps.
struct CappedCylinder : AnalyticBody
{
  Eigen::Vector3d centre;
  double R, halfHeight;
  CappedCylinder(Eigen::Vector3d c, double r, double h) : centre(c), R(r), halfHeight(h) {}
  void castAll(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
               std::vector<hair::RayHit>& hits) const override
  {
    hits.clear();
    const Eigen::Vector3d q = o - centre;
    // Slab in y and the infinite cylinder in x, z: the solid is their intersection.
    double t0 = 0, t1 = std::numeric_limits<double>::infinity();
    Eigen::Vector3d n0 = Eigen::Vector3d::Zero(), n1 = Eigen::Vector3d::Zero();
    if (std::abs(d.y()) < 1e-300)
    {
      if (std::abs(q.y()) >= halfHeight)
      {
        return;
      }
    }
    else
    {
      double ta = (-halfHeight - q.y()) / d.y(), tb = (halfHeight - q.y()) / d.y();
      Eigen::Vector3d na(0, -1, 0), nb(0, 1, 0);
      if (ta > tb)
      {
        std::swap(ta, tb);
        std::swap(na, nb);
      }
      t0 = ta;
      n0 = na;
      t1 = tb;
      n1 = nb;
    }
    const double A = d.x() * d.x() + d.z() * d.z(), B = 2 * (q.x() * d.x() + q.z() * d.z()),
                 C = q.x() * q.x() + q.z() * q.z() - R * R;
    double c0 = -std::numeric_limits<double>::infinity(), c1 = -c0;
    if (A < 1e-300)
    {
      if (C >= 0)
      {
        return;
      }
    }
    else
    {
      const double disc = B * B - 4 * A * C;
      if (disc <= 0)
      {
        return;
      }
      c0 = (-B - std::sqrt(disc)) / (2 * A);
      c1 = (-B + std::sqrt(disc)) / (2 * A);
    }
    auto side = [&](double t)
    {
      Eigen::Vector3d p = q + t * d;
      return Eigen::Vector3d(p.x(), 0, p.z()).normalized();
    };
    double enter = t0, leave = t1;
    Eigen::Vector3d nEnter = n0, nLeave = n1;
    if (c0 > enter)
    {
      enter = c0;
      nEnter = side(c0);
    }
    if (c1 < leave)
    {
      leave = c1;
      nLeave = side(c1);
    }
    if (!(enter < leave))
    {
      return;
    }
    if (enter > 0)
    {
      hits.push_back({enter, nEnter});
    }
    if (leave > 0)
    {
      hits.push_back({leave, nLeave});
    }
  }
  bool inside(const Eigen::Vector3d& p) const override
  {
    const Eigen::Vector3d q = p - centre;
    return std::hypot(q.x(), q.z()) < R && std::abs(q.y()) < halfHeight;
  }
  double distanceBound(const Eigen::Vector3d& p) const override
  {
    const Eigen::Vector3d q = p - centre;
    const double dr = std::hypot(q.x(), q.z()) - R, dy = std::abs(q.y()) - halfHeight;
    if (dr < 0 && dy < 0)
    {
      return std::min(-dr, -dy);
    }
    return std::hypot(std::max(dr, 0.0), std::max(dy, 0.0));
  }
};

/// A triangulated sphere: an octahedron subdivided `levels` times and pushed onto the
/// sphere; closed, outward.
inline hair::TriangleMesh triangulatedSphere(const Eigen::Vector3d& c, double R, int levels)
{
  hair::TriangleMesh m;
  m.points = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  m.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                 {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (int l = 0; l < levels; ++l)
  {
    std::vector<std::array<int, 3>> next;
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b)
    {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end())
      {
        return it->second;
      }
      m.points.push_back((m.points[a] + m.points[b]).normalized());
      const int id = static_cast<int>(m.points.size()) - 1;
      mid[key] = id;
      return id;
    };
    for (const auto& t : m.triangles)
    {
      const int ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
      next.push_back({t[0], ab, ca});
      next.push_back({ab, t[1], bc});
      next.push_back({ca, bc, t[2]});
      next.push_back({ab, bc, ca});
    }
    m.triangles = std::move(next);
  }
  for (auto& p : m.points)
  {
    p = c + R * p.normalized();
  }
  return m;
}

} // namespace hairtest
