#include "strands/GuideStrand.h"

#include <Eigen/Geometry>

#include <algorithm>

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
  if (!curve.empty())
  {
    if (curve.size() < 2)
    {
      return Status::Error(what + " has a guide curve of one point: a curve needs a root and "
                                  "at least one more point.");
    }
    double length = 0;
    for (std::size_t j = 0; j < curve.size(); ++j)
    {
      if (!curve[j].allFinite())
      {
        return Status::Error(what + ": point " + std::to_string(j) +
                             " of its guide curve is NaN or infinite.");
      }
      length += j > 0 ? (curve[j] - curve[j - 1]).norm() : 0.0;
    }
    for (std::size_t j = 1; j < curve.size(); ++j)
    {
      if (!((curve[j] - curve[j - 1]).norm() > 1e-9 * length))
      {
        return Status::Error(what + ": points " + std::to_string(j - 1) + " and " +
                             std::to_string(j) +
                             " of its guide curve are the same point; remove the repeated one.");
      }
    }
    if (!((curve[0] - root).norm() <= 1e-9 * std::max(1.0, root.norm())))
    {
      return Status::Error(what + ": its guide curve does not start at its root.");
    }
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
