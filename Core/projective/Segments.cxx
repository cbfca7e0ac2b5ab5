#include "projective/Segments.h"

#include <algorithm>
#include <cmath>

namespace hair
{

namespace
{
bool finite(double x)
{
  return std::isfinite(x);
}
} // namespace

Eigen::Vector3d segmentDirection(double theta, double phi)
{
  const double st = std::sin(theta), ct = std::cos(theta);
  return Eigen::Vector3d(ct, st * std::sin(phi), st * std::cos(phi));
}

Eigen::Matrix3d segmentRotation(double theta, double phi)
{
  const double st = std::sin(theta), ct = std::cos(theta), sp = std::sin(phi), cp = std::cos(phi);
  Eigen::Matrix3d a;
  a << st, 0, ct, -sp * ct, cp, sp * st, -cp * ct, -sp, cp * st;
  return a;
}

void nodeFrames(const Eigen::Matrix3d& rootFrame, const double* angles, int segments,
                std::vector<Eigen::Vector3d>& tangents, std::vector<Eigen::Vector3d>& directors)
{
  tangents.clear();
  directors.clear();
  Eigen::Matrix3d r = rootFrame;
  tangents.push_back(r.col(2));
  directors.push_back(r.col(0));
  for (int i = 0; i < segments; ++i)
  {
    r = r * segmentRotation(angles[2 * i], angles[2 * i + 1]);
    tangents.push_back(r.col(2));
    directors.push_back(r.col(0));
  }
}

Eigen::Matrix3d materialFrame(const Eigen::Matrix3d& segmentFrame)
{
  Eigen::Matrix3d m;
  m << segmentFrame.col(2), segmentFrame.col(0), segmentFrame.col(1);
  return m;
}

Eigen::Matrix3d segmentFrame(const Eigen::Matrix3d& materialFrame)
{
  Eigen::Matrix3d r;
  r << materialFrame.col(1), materialFrame.col(2), materialFrame.col(0);
  return r;
}

Status strandFromPolyline(const std::vector<Eigen::Vector3d>& points,
                          const Eigen::Vector3d& rootSide, ProjectiveStrand& strand)
{
  if (points.size() < 2)
  {
    return Status::Error("strand polyline: it needs at least two points (one segment)");
  }
  for (const auto& p : points)
  {
    if (!p.allFinite())
    {
      return Status::Error("strand polyline: a point holds NaN or infinite coordinates");
    }
  }
  const std::size_t k = points.size() - 1;
  double dmin = 1e300, dmax = 0, sum = 0;
  for (std::size_t i = 0; i < k; ++i)
  {
    const double d = (points[i + 1] - points[i]).norm();
    dmin = std::min(dmin, d);
    dmax = std::max(dmax, d);
    sum += d;
  }
  const double d = sum / k;
  if (!(dmin > 0) || (dmax - dmin) > 1e-6 * d)
  {
    return Status::Error("strand polyline: segments must have equal, non-zero lengths "
                         "(resample the polyline first)");
  }
  const Eigen::Vector3d e3 = (points[1] - points[0]).normalized();
  Eigen::Vector3d e1 = rootSide - rootSide.dot(e3) * e3;
  if (!(e1.norm() > 1e-9 * std::max(1.0, rootSide.norm())))
  {
    return Status::Error("strand polyline: the root side vector is parallel to the first "
                         "segment; give one across it");
  }
  e1.normalize();
  Eigen::Matrix3d r;
  r.col(0) = e1;
  r.col(1) = e3.cross(e1);
  r.col(2) = e3;
  strand.root = points[0];
  strand.rootFrame = r;
  strand.segmentLength = d;
  strand.restAngles = anglesAlong(r, points);
  return Status::Ok();
}

std::vector<Eigen::Vector2d> anglesAlong(const Eigen::Matrix3d& rootFrame,
                                         const std::vector<Eigen::Vector3d>& points)
{
  std::vector<Eigen::Vector2d> angles(points.empty() ? 0 : points.size() - 1);
  Eigen::Matrix3d parent = rootFrame;
  for (std::size_t i = 0; i < angles.size(); ++i)
  {
    const Eigen::Vector3d u = (points[i + 1] - points[i]).normalized();
    const Eigen::Vector3d l = parent.transpose() * u;
    const double theta = std::acos(std::clamp(l.x(), -1.0, 1.0));
    const double phi = std::atan2(l.y(), l.z());
    angles[i] = Eigen::Vector2d(theta, phi);
    parent = parent * segmentRotation(theta, phi);
  }
  return angles;
}

Status ProjectiveParameters::validate() const
{
  if (!finite(linearDensity) || !finite(bendingStiffness) || !finite(dampingRate) ||
      !finite(dragDiameter) || !finite(airDensity) || !finite(dragCoefficient))
  {
    return Status::Error("strand parameters: NaN or infinite values");
  }
  if (!(linearDensity > 0))
  {
    return Status::Error("strand parameters: the linear density must be > 0 kg/m");
  }
  if (bendingStiffness < 0 || dampingRate < 0 || dragDiameter < 0 || !finite(stiffnessDamping) ||
      stiffnessDamping < 0)
  {
    return Status::Error(
        "strand parameters: bending stiffness, damping rate and drag diameter must be ≥ 0");
  }
  if (airDensity < 0 || dragCoefficient < 0)
  {
    return Status::Error("strand parameters: air density and drag coefficient must be ≥ 0");
  }
  return Status::Ok();
}

Eigen::Vector3d segmentDrag(const ProjectiveParameters& material, const Eigen::Vector3d& air,
                            const Eigen::Vector3d& segmentVelocity, const Eigen::Vector3d& tangent,
                            double length)
{
  Eigen::Vector3d w = air - segmentVelocity;
  w -= w.dot(tangent) * tangent;
  return 0.5 * material.airDensity * material.dragCoefficient * material.dragDiameter * length *
         w.norm() * w;
}

} // namespace hair
