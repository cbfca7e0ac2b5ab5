#pragma once
// A groom for the projective model: equal segments along a guide curve, and a sag-free rest
// shape — the rest angles (θ⁰, φ⁰) chosen so that the strand's shape at t = 0 is a static
// equilibrium under gravity and the reaction constraint, κ (q − q⁰) = Q(q), with Q the
// step's own generalized forces at rest (ProjectiveStrands::restMoments). As for the
// Super-Helix, the stability of that equilibrium is the potential's Hessian
// H = κ I − ∂Q/∂q, in which q⁰ does not appear; a shape that is not stable is replaced by the
// closest stable one. docs/projective-strands.md, "A groom and a sag-free rest shape".
#include "common/Status.h"
#include "model/GroomReport.h"
#include "projective/ProjectiveStrands.h"

#include <Eigen/Core>

#include <vector>

namespace hair
{

/// `segments` + 1 nodes on the polyline `curve`, from its first point to its last, each
/// the first point of the curve at the same distance d from the one before (d found by
/// bisection): the chain of equal segments inscribed in the curve. (On a curve that comes
/// back near itself no d may put the last node exactly on the end; the chain then stops short
/// of it, its segments still equal.) `fitError` receives the largest distance of the curve's
/// points from the chain, or of its end from the chain's end if that is larger. The curve
/// must have passed curveProblem (strands/GuideCurves.h).
Status segmentsAlongCurve(const std::vector<Eigen::Vector3d>& curve, int segments,
                          std::vector<Eigen::Vector3d>& nodes, double& fitError);

struct ProjectiveSagFree
{
  std::vector<Eigen::Vector2d> rest;  ///< (θ⁰, φ⁰) per segment
  std::vector<Eigen::Vector2d> start; ///< the angles to start from: its shape, or the closest
  GroomReport report;                 ///< outcome, deviation, stability, reason (fitError unset)
  double imbalance = 0; ///< |κ (start − rest) − Q(start)| / |Q(start)|: round-off when held
};

/// The sag-free rest shape of strand `s` of `strands` (initialized, at time 0, in the shape
/// to hold, rates zero). The strand is left in `result.start` with rest angles
/// `result.rest`; the other strands are not touched (their energy budgets restart, as with
/// setState).
Status projectiveSagFree(ProjectiveStrands& strands, int s, const SagFreeOptions& options,
                         ProjectiveSagFree& result);

} // namespace hair
