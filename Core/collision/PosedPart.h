#pragma once
// A body part at one instant: its collision table, where the part is and how it moves. The
// one form in which both models, their contact responses and the penetration measure see
// the body, so that all of them look at the same part in the same place at the same time.
#include "collision/CollisionTable.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <vector>

namespace hair
{

struct PosedPart
{
  const CollisionTable* table = nullptr; ///< must outlive every use
  /// Part at rest (where its table was built) → part now.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  /// The part's velocity field: a point x of it moves at velocity + ω × (x − reference).
  Eigen::Vector3d reference = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d angularVelocity = Eigen::Vector3d::Zero();

  /// A part at rest where its table was built.
  static PosedPart still(const CollisionTable& table);

  Eigen::Vector3d velocityAt(const Eigen::Vector3d& x) const
  {
    return velocity + angularVelocity.cross(x - reference);
  }
  /// World point → the coordinates of the part at rest, R^T (x − t).
  Eigen::Vector3d toRest(const Eigen::Vector3d& x) const
  {
    return pose.linear().transpose() * (x - pose.translation());
  }
  /// The table's answer for a world point, with Q, N and T in world coordinates.
  TableQuery query(const Eigen::Vector3d& x) const;
  /// False when the world point is certainly farther than `slack` outside the part's
  /// table (a ball or a slab about the table's axis holding every sample): the cheap test
  /// that saves the look-up.
  bool near(const Eigen::Vector3d& x, double slack) const;
};

/// Where a point is deepest in (or nearest to) a set of parts.
struct PartContact
{
  int part = -1;    ///< index in the set; −1: no part's table covers the point
  double depth = 0; ///< (Q − P)·N, > 0 inside; its sign follows the table's inside test
  Eigen::Vector3d normal = Eigen::Vector3d::UnitY(); ///< N at Q, world, out of the part
  Eigen::Vector3d surface = Eigen::Vector3d::Zero(); ///< Q, world
};

/// Of the parts whose table covers x and that are near() it within `slack`, the one x is
/// deepest in (or least outside of). Returns false, with `contact` reset, when none is.
bool deepestPart(const std::vector<PosedPart>& parts, const Eigen::Vector3d& x, double slack,
                 PartContact& contact);

/// Whether x is inside any of the parts (the table's inside test alone: no depth, no normal).
bool insideAny(const std::vector<PosedPart>& parts, const Eigen::Vector3d& x);

/// Drapes a polyline (root first) over the parts it enters, the root kept: from the root on,
/// each segment keeps its direction and length, carried by the points before it as they
/// were moved (as the projective model's projection carries a strand); a point the table
/// says is inside a part is put `clearance` outside along the surface normal and then back to
/// its segment's length from the point before (a few times, as the projection does). Returns
/// the largest distance a point moved (0: no point was inside). A strand grown straight
/// through the shoulders comes out lying on them.
double drapeOutside(const std::vector<PosedPart>& parts, double clearance,
                    std::vector<Eigen::Vector3d>& points);

/// Whether x is inside any of the parts, and the largest depth among those it is inside
/// (0 when inside none): the penetration measure of a point.
bool insideDepth(const std::vector<PosedPart>& parts, const Eigen::Vector3d& x, double& depth);

} // namespace hair
