#include "strands/GuideStrand.h"

#include <Eigen/Geometry>

#include <cmath>
#include <sstream>

namespace hair
{

Status GuideStrand::validate(const std::string& what) const
{
  if (!root.allFinite() || !growth.allFinite() || !(growth.norm() >= 1e-12) || !normal.allFinite())
  {
    return Status::Error(what + " has a NaN root or a zero or NaN growth direction.");
  }
  if (elements < 1 || elements > maxElements || !(length > 0 && length <= maxLength))
  {
    std::ostringstream m;
    m << what << " has " << elements << " elements and length " << length << " m: give 1 to "
      << maxElements << " elements and a length in (0, " << maxLength << "] m.";
    return Status::Error(m.str());
  }
  if (Status s = hair.validate(); !s)
  {
    return Status::Error(what + ": " + s.message());
  }
  return Status::Ok();
}

Eigen::Matrix3d orthonormalFrame(const Eigen::Vector3d& first, const Eigen::Vector3d& second)
{
  const Eigen::Vector3d n0 = first.normalized();
  Eigen::Vector3d n1 = second - second.dot(n0) * n0;
  if (n1.norm() < 1e-6 * second.norm() || n1.norm() == 0)
  {
    n1 = n0.unitOrthogonal();
  }
  n1.normalize();
  Eigen::Matrix3d f;
  f.col(0) = n0;
  f.col(1) = n1;
  f.col(2) = n0.cross(n1);
  return f;
}

Eigen::Matrix3d GuideStrand::rootFrame() const
{
  return orthonormalFrame(growth, normal);
}

} // namespace hair
