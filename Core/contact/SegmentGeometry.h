#pragma once
// Closest points and overlaps of two straight segments: the geometry of a contact between
// two pieces of strands (contact/HairHairContacts).
#include <Eigen/Core>

namespace hair
{

/// Length of the part of segment [p0, p1] that lies within distance R of the line through
/// q0, q1 and projects onto that line between q0 and q1 (0 for a degenerate [q0, q1]).
double lengthInCylinder(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                        const Eigen::Vector3d& q0, const Eigen::Vector3d& q1, double R);

/// Closest points of segments [p0, p1] and [q0, q1]: parameters u, v in [0, 1] such that
/// p0 + u (p1 − p0) and q0 + v (q1 − q0) are closest; returns the squared distance.
double closestPointsOfSegments(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                               const Eigen::Vector3d& q0, const Eigen::Vector3d& q1, double& u,
                               double& v);

} // namespace hair
