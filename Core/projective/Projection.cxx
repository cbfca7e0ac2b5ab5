// The projective model's collision response at the placement of the segments (Kurihara,
// Anjyo and Thalmann 1993, §3.3): after the angular step, each segment is placed from the
// root to the tip at the parts' poses at the end of the step, and a segment whose end node
// entered a part is turned back outside, its rate losing the inward part (inelastic); the
// segments it carries keep their absolute directions. The reaction-constraint force that
// acts during the step is in ProjectiveStrands::forces.
#include "projective/ProjectiveStrands.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace hair
{

namespace
{
constexpr double Pi = 3.14159265358979323846;
} // namespace

void ProjectiveStrands::place(Strand& s, const StepFrame& f, ProjectiveStepStats& stats) const
{
  const std::size_t k = s.q.size();
  // Root to tip: place each segment; turn it back outside if its end node entered a part.
  const Eigen::Vector3d root = f.root1 * s.rootRest;
  const Eigen::Matrix3d rootFrame = f.root1.linear() * s.frameRest;
  if (World.parts.empty())
  {
    forward(s, root, rootFrame);
    return;
  }
  double before = 0;
  const double inelasticBefore = s.inelasticDissipated;
  bool projected = false;
  s.P[0] = root;
  s.R[0] = rootFrame;
  const double margin = Options.contactMargin;
  // When a segment is turned, the part of the strand it carries is translated, not turned
  // with it: its children keep their absolute directions and rates (as far as two angles
  // can), so that a correction of a millimetre at one node does not swing the whole tip.
  bool parentTurned = false;
  Eigen::Matrix3d parentBefore;
  Eigen::Vector3d parentSpin = Eigen::Vector3d::Zero();
  auto angleAxes = [&](std::size_t i, Eigen::Vector3d& wt, Eigen::Vector3d& wp)
  {
    wp = -s.R[i - 1].col(0);
    wt = -s.R[i].col(1);
  };
  auto setDirection = [&](std::size_t i, const Eigen::Vector3d& u)
  {
    const Eigen::Vector3d l = s.R[i - 1].transpose() * u;
    const double theta = std::acos(std::clamp(l.x(), -1.0, 1.0));
    double phi = std::atan2(l.y(), l.z());
    phi += 2 * Pi * std::round((s.q[i - 1].y() - phi) / (2 * Pi));
    s.q[i - 1] = Eigen::Vector2d(theta, phi);
    s.R[i] = s.R[i - 1] * segmentRotation(theta, phi);
    s.P[i] = s.P[i - 1] + s.d * s.R[i].col(2);
  };
  for (std::size_t i = 1; i <= k; ++i)
  {
    if (parentTurned)
    {
      const Eigen::Vector3d keep =
          parentBefore * segmentRotation(s.q[i - 1].x(), s.q[i - 1].y()).col(2);
      setDirection(i, keep);
      // Cancel the parent's change of spin across this segment: least squares on the two
      // angle rates, (ω_parent change + w_θ δθ̇ + w_φ δφ̇) × u = 0. Where the segment folds
      // onto its parent's pole (θ near 0 or π) the two rates turn it about nearly the same
      // axis: the normal matrix is near singular and its inverse would turn a small spin into
      // rates of 10⁴ rad/s (measured: the explicit step then blows up within ten steps).
      // There only the well-determined combination is corrected (a truncated
      // pseudo-inverse, its eigenvalues below 1 % of the largest left out).
      Eigen::Vector3d wt, wp;
      angleAxes(i, wt, wp);
      const Eigen::Vector3d u = s.R[i].col(2);
      Eigen::Matrix<double, 3, 2> m;
      m.col(0) = wt.cross(u);
      m.col(1) = wp.cross(u);
      const Eigen::Matrix2d mtm = m.transpose() * m;
      const Eigen::Vector2d rhs = m.transpose() * (-parentSpin.cross(u));
      const double half = 0.5 * mtm.trace();
      const double spread = std::sqrt(std::max(half * half - mtm.determinant(), 0.0));
      const double largest = half + spread, smallest = half - spread;
      if (smallest > 1e-2 * largest)
      {
        s.qd[i - 1] += mtm.inverse() * rhs;
      }
      else if (largest > 0)
      {
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(mtm);
        const Eigen::Vector2d v = eig.eigenvectors().col(1); // of the largest eigenvalue
        s.qd[i - 1] += v * (v.dot(rhs) / eig.eigenvalues()(1));
      }
    }
    else
    {
      s.R[i] = s.R[i - 1] * segmentRotation(s.q[i - 1].x(), s.q[i - 1].y());
      s.P[i] = s.P[i - 1] + s.d * s.R[i].col(2);
    }
    parentTurned = false;
    PartContact c;
    deepest(f.parts1, s.P[i], c);
    if (c.part >= 0)
    {
      stats.maxDepthBefore = std::max(stats.maxDepthBefore, c.depth);
    }
    if (Options.projectOutside && c.part >= 0 && c.depth > 0)
    {
      if (!projected)
      {
        // Energy of the state before any projection, for the contact work.
        before = unprojectedEnergy(s, root, rootFrame);
        projected = true;
      }
      ++stats.projections;
      const PartContact c0 = c;
      parentBefore = s.R[i];
      Eigen::Vector3d u = s.R[i].col(2);
      for (int iter = 0; iter < 6 && c.part >= 0 && c.depth > 0; ++iter)
      {
        // Along the normal first; where the table's normal does not lead out (a surface
        // the projection describes poorly, under the chin say), along the table's ray.
        Eigen::Vector3d target = s.P[i] + (c.depth + margin) * c.normal;
        if (iter >= 2)
        {
          const Eigen::Vector3d ray = c.surface - s.P[i];
          const double len = ray.norm();
          target = len > 0 ? Eigen::Vector3d(c.surface + margin * ray / len) : target;
        }
        u = (target - s.P[i - 1]).normalized();
        s.P[i] = s.P[i - 1] + s.d * u;
        deepest(f.parts1, s.P[i], c);
      }
      setDirection(i, u);
      // Inelastic: the segment's own rate loses the part that drives its end node into the
      // surface (the position correction itself does not become a velocity). Cancelling
      // the whole inward velocity, ancestors' share included, through this segment's rates
      // alone is unstable (tried: the rates blow up where J is small).
      Eigen::Vector3d wt, wp;
      angleAxes(i, wt, wp);
      const Eigen::Vector3d arm = s.d * s.R[i].col(2);
      const Eigen::Vector2d jac(c0.normal.dot(wt.cross(arm)), c0.normal.dot(wp.cross(arm)));
      const double vn = jac.dot(s.qd[i - 1]);
      parentSpin.setZero();
      if (vn < 0 && jac.squaredNorm() > 0)
      {
        const Eigen::Vector2d change = -(vn / jac.squaredNorm()) * jac;
        // The segment's kinetic energy ½ I |q̇|² loses ½ I (J·q̇)²/|J|² (≥ 0): what the
        // inelastic rule dissipates.
        s.inelasticDissipated += 0.5 * s.inertia[i - 1] * vn * vn / jac.squaredNorm();
        s.qd[i - 1] += change;
        parentSpin = wt * change.x() + wp * change.y();
      }
      parentTurned = true;
    }
    if (c.part >= 0 && c.depth > stats.maxDepthAfter)
    {
      stats.maxDepthAfter = c.depth;
      stats.deepestPoint = s.P[i];
      stats.deepestPart = c.part;
    }
    s.contact[i] = c;
  }
  if (projected)
  {
    // The projections' change of energy, less what the inelastic rule dissipated: the work
    // of moving the nodes back out (and of keeping the carried segments' directions and spin).
    const double work = strandEnergy(s) - before + (s.inelasticDissipated - inelasticBefore);
    s.contactWork += work;
    s.projectionWork += work;
  }
}

} // namespace hair
