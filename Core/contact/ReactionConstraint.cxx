#include "contact/ReactionConstraint.h"

#include <cmath>

namespace hair
{

double ReactionConstraintOptions::criticalDamping() const
{
  return damping >= 0 ? damping : 2.0 * std::sqrt(stiffness);
}

Eigen::Vector3d reactionConstraint(const Eigen::Vector3d& forceIn, const Eigen::Vector3d& velocity,
                                   const Eigen::Vector3d& position, const Eigen::Vector3d& nearest,
                                   const Eigen::Vector3d& normal,
                                   const ReactionConstraintOptions& options,
                                   Eigen::Vector3d* damping)
{
  const double fn = forceIn.dot(normal);
  if (options.inelastic && fn >= 0)
  {
    if (damping)
    {
      damping->setZero();
    }
    return forceIn;
  }
  const Eigen::Vector3d unconstrained = forceIn - fn * normal;
  const double k = options.stiffness, c = options.criticalDamping();
  const double vn = velocity.dot(normal);
  if (damping)
  {
    *damping = -(c * vn) * normal;
  }
  const Eigen::Vector3d constrained = -(k * (position - nearest).dot(normal) + c * vn) * normal;
  return unconstrained + constrained;
}

} // namespace hair
