#pragma once
// The reaction-constraint response (Platt and Barr 1988) used by Kurihara, Anjyo and
// Thalmann (1993) for inelastic hair–body contact. All quantities per unit mass.
#include <Eigen/Core>

namespace hair
{

struct ReactionConstraintOptions
{
  double stiffness = 1.0e4; ///< k, 1/s²: pulls the node back to the surface
  /// c, 1/s. Negative: critical damping c = 2√k, so the depth returns to zero without
  /// overshoot. (shared/design/kurihara-collision.md writes √(2k), which is a damping ratio
  /// of 1/√2, not critical; see docs/collision-tables.md.)
  double damping = -1;
  bool inelastic = true; ///< apply the constraint only while F_in pushes into the surface
  double criticalDamping() const;
};

/// The force that replaces F_in on a node P inside a body part, with velocity V (relative
/// to the surface), T the nearest surface point and N the outward unit normal there:
///   F_out = F_in − (F_in·N) N − (k (P − T)·N + c V·N) N
/// With `inelastic`, when F_in·N ≥ 0 (the input force already lifts the node away) the
/// constraint is not applied and F_out = F_in. `damping` (optional) receives the damper's
/// part of F_out − F_in, −c (V·N) N (zero when the constraint is not applied), for energy
/// budgets that report what the damper dissipates.
Eigen::Vector3d reactionConstraint(const Eigen::Vector3d& forceIn, const Eigen::Vector3d& velocity,
                                   const Eigen::Vector3d& position, const Eigen::Vector3d& nearest,
                                   const Eigen::Vector3d& normal,
                                   const ReactionConstraintOptions& options = {},
                                   Eigen::Vector3d* damping = nullptr);

} // namespace hair
