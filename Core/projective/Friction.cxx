// Coulomb friction with the body for the projective strands, solved at the contact nodes
// through the step's own compliance (docs/projective-strands.md, "Friction").
//
// The angular step updates every joint from the moments of the forces on what it carries:
// a force F acting over the step at node l changes the rates of each joint j ≤ l by
//   Δq̇_j = g_j (w_j × r_jl)ᵀ F,  g_j = (h / I_j) / (1 + h γ_j / I_j),  r_jl = P_l − P_{j−1},
// for both of its axes w_j (θ and φ), and node i's velocity by Σ_{j ≤ i} Δq̇_j (w_j × r_ji).
// So the contact nodes' velocities at the end of the step are affine in their friction
// forces, u = u_free + W F, W = J G Jᵀ, W_il = Σ_{j ≤ min(i,l)} g_j (w_j × r_ji)(w_j × r_jl)ᵀ.
// The nodes that stick take the tangential forces that bring them to their targets (back to
// their anchors) together, W_SS F_S = target − u_free − W_S,slide F_slide, solved directly
// (W is semi-definite: a straight chain's nodes cannot move along it, see pseudoSolve):
// W is dense and ill-conditioned along a chain (every node shares its ancestors' joints),
// and projected Gauss–Seidel on it did not converge in 200 sweeps. A node whose force
// leaves its disc (μ_s λ) slides with μ λ (1 + a cos ψ) against the force that would have
// held it, and the rest are solved again. The rates change by Δq̇ = G Jᵀ F.
#include "projective/ProjectiveStrands.h"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>

namespace hair
{

namespace
{
/// The active set's rounds (each solves the sticking nodes once) before it gives up and
/// keeps what it has.
constexpr int MaxRounds = 50;

/// x with W x = b where W is symmetric positive semi-definite: by LDLᵀ with pivoting, the
/// pivots below 1e-10 of the largest (directions no force can move: along a straight
/// chain, its nodes cannot slide along it) taken as zero, so that no force goes there.
Eigen::VectorXd pseudoSolve(const Eigen::MatrixXd& w, const Eigen::VectorXd& b)
{
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(w);
  const Eigen::VectorXd d = ldlt.vectorD();
  const double floor = 1e-10 * d.cwiseAbs().maxCoeff();
  Eigen::VectorXd y = ldlt.transpositionsP() * b;
  ldlt.matrixL().solveInPlace(y);
  for (Eigen::Index i = 0; i < y.size(); ++i)
  {
    y(i) = std::abs(d(i)) > floor ? y(i) / d(i) : 0.0;
  }
  ldlt.matrixU().solveInPlace(y);
  return ldlt.transpositionsP().transpose() * y;
}
} // namespace

void ProjectiveStrands::friction(Strand& s, const StepFrame& f, ProjectiveStepStats& stats) const
{
  const std::size_t k = s.q.size();
  const double h = f.h, band = contactBand();
  const double mu = Options.friction;
  const double muStick = std::max(Options.staticFriction, mu);
  const double a = Options.anisotropy;

  struct Node
  {
    std::size_t i = 0;
    /// Rows t1 (the fibre's direction in the plane) and t2.
    Eigen::Matrix<double, 2, 3> basis = Eigen::Matrix<double, 2, 3>::Zero();
    Eigen::Vector2d free = Eigen::Vector2d::Zero(), target = Eigen::Vector2d::Zero();
    double lambda = 0;
    bool sliding = false; ///< was sliding at the step's start: kinetic bound until it stops
  };
  std::vector<Node> nodes;
  for (std::size_t i = 1; i <= k; ++i)
  {
    Strand::Anchor& an = s.anchors[i];
    const PartContact& c = s.contact[i];
    if (c.part < 0 || c.depth < -band || (an.part >= 0 && an.part != c.part))
    {
      an = Strand::Anchor(); // left the part (or went to another): touches anew, stuck
      if (c.part < 0 || c.depth < -band)
      {
        continue;
      }
    }
    if (!(s.load[i] > 0))
    {
      continue; // nothing presses it this step: nothing holds it (its anchor stays)
    }
    const PosedPart& part = f.parts0[c.part];
    if (an.part < 0 || !an.placed)
    {
      an.part = c.part;
      an.placed = true;
      an.rest = part.toRest(s.P[i]);
    }
    Node n;
    n.i = i;
    n.lambda = s.load[i];
    n.sliding = an.sliding;
    const Eigen::Vector3d normal = c.normal;
    Eigen::Vector3d t1 = s.R[i].col(2) - s.R[i].col(2).dot(normal) * normal;
    if (t1.norm() < 1e-6) // the segment along the normal: any direction in the plane
    {
      t1 = normal.unitOrthogonal();
    }
    t1.normalize();
    n.basis.row(0) = t1.transpose();
    n.basis.row(1) = normal.cross(t1).transpose();
    n.target = Eigen::Vector2d::Zero();
    if (!an.sliding)
    {
      n.target = -n.basis * (s.P[i] - part.pose * an.rest) / h; // back to where it stuck
    }
    nodes.push_back(n);
  }
  if (nodes.empty())
  {
    return;
  }

  // The nodes' velocities with the rates the step has given (before friction); relative to
  // their parts below.
  nodeVelocities(s, f.rootRates);
  // J in the nodes' tangent bases (2 rows per node, 2 columns per joint) and W = J G Jᵀ,
  // joint j's axes θ: −e2 of segment j, φ: −e1 of its parent.
  const int rows = 2 * static_cast<int>(nodes.size()), cols = 2 * static_cast<int>(k);
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(rows, cols);
  Eigen::VectorXd free(rows), want(rows), g(cols);
  for (std::size_t m = 0; m < nodes.size(); ++m)
  {
    Node& n = nodes[m];
    const PosedPart& part = f.parts0[s.contact[n.i].part];
    n.free = n.basis * (s.v[n.i] - part.velocityAt(s.P[n.i]));
    free.segment<2>(2 * m) = n.free;
    want.segment<2>(2 * m) = n.target;
    for (std::size_t j = 1; j <= n.i; ++j)
    {
      const Eigen::Vector3d r = s.P[n.i] - s.P[j - 1];
      J.block<2, 1>(2 * m, 2 * (j - 1)) = n.basis * (-s.R[j].col(1)).cross(r);
      J.block<2, 1>(2 * m, 2 * (j - 1) + 1) = n.basis * (-s.R[j - 1].col(0)).cross(r);
    }
  }
  for (std::size_t j = 0; j < k; ++j)
  {
    g(2 * j) = g(2 * j + 1) = s.gain[j] * s.damper[j];
  }
  const Eigen::MatrixXd W = J * g.asDiagonal() * J.transpose();

  // Active set. The sticking nodes take together the forces that bring them to their
  // targets, the sliding ones' forces held; a sticking node whose force leaves its disc
  // (μ_s λ) slides; a sliding node's force is the kinetic one against its sliding velocity
  // (found by fixed point: the velocity depends on all the forces), and it sticks again when
  // the kinetic force alone could stop it. The directions are the nodes' own: in a chain the
  // force that would hold all of them at once can point anywhere at one node.
  const int count = static_cast<int>(nodes.size());
  std::vector<char> slides(nodes.size(), 0);
  Eigen::VectorXd force = Eigen::VectorXd::Zero(rows);
  auto kineticAgainst = [&](const Node& n, const Eigen::Vector2d& velocity) -> Eigen::Vector2d
  {
    const double speed = velocity.norm();
    if (!(speed > 0))
    {
      return Eigen::Vector2d::Zero();
    }
    // μ (1 + a cos ψ) λ, ψ between the fibre (t1) and the sliding velocity.
    return -(mu * (1 + a * velocity.x() / speed) * n.lambda / speed) * velocity;
  };
  for (int m = 0; m < count; ++m)
  {
    slides[m] = nodes[m].sliding;
    if (slides[m])
    {
      force.segment<2>(2 * m) = kineticAgainst(nodes[m], nodes[m].free);
    }
  }
  for (int round = 0; round < MaxRounds; ++round)
  {
    std::vector<int> stick;
    for (int m = 0; m < count; ++m)
    {
      if (!slides[m])
      {
        stick.push_back(2 * m);
        stick.push_back(2 * m + 1);
        force.segment<2>(2 * m).setZero();
      }
    }
    if (!stick.empty())
    {
      const int ns = static_cast<int>(stick.size());
      Eigen::MatrixXd wss(ns, ns);
      Eigen::VectorXd rhs(ns);
      const Eigen::VectorXd fixed = want - free - W * force; // the sliding ones' forces only
      for (int p = 0; p < ns; ++p)
      {
        rhs(p) = fixed(stick[p]);
        for (int q = 0; q < ns; ++q)
        {
          wss(p, q) = W(stick[p], stick[q]);
        }
      }
      const Eigen::VectorXd held = pseudoSolve(wss, rhs);
      for (int p = 0; p < ns; ++p)
      {
        force(stick[p]) = held(p);
      }
    }
    const Eigen::VectorXd velocity = free + W * force;
    bool changed = false;
    for (int m = 0; m < count; ++m)
    {
      const Node& n = nodes[m];
      const Eigen::Vector2d f = force.segment<2>(2 * m);
      const Eigen::Matrix2d wmm = W.block<2, 2>(2 * m, 2 * m);
      // Its velocity without its own friction.
      const Eigen::Vector2d bare = velocity.segment<2>(2 * m) - wmm * f;
      if (!slides[m])
      {
        if (f.norm() > muStick * n.lambda * (1 + 1e-12))
        {
          slides[m] = 1;
          force.segment<2>(2 * m) = kineticAgainst(n, bare);
          changed = true;
        }
        continue;
      }
      // The force that alone would bring it to its target.
      const Eigen::Vector2d stop = pseudoSolve(wmm, n.target - bare);
      if (stop.norm() <= kineticAgainst(n, -stop).norm())
      {
        slides[m] = 0; // kinetic friction stops it: it sticks
        changed = true;
      }
      else
      {
        const Eigen::Vector2d next = kineticAgainst(n, velocity.segment<2>(2 * m));
        if ((next - f).norm() > 1e-9 * n.lambda)
        {
          force.segment<2>(2 * m) = next;
          changed = true;
        }
      }
    }
    if (!changed)
    {
      break;
    }
  }
  const Eigen::VectorXd rates = g.asDiagonal() * (J.transpose() * force);
  const Eigen::VectorXd after = free + J * rates;
  std::vector<Eigen::Vector2d> change(k);
  for (std::size_t j = 0; j < k; ++j)
  {
    change[j] = rates.segment<2>(2 * j);
  }

  // The rates and angles take the change; the work of friction is the kinetic energy it
  // changes, ½ I (|q̇ + Δq̇|² − |q̇|²); what sliding dissipates, −h F·u with u the velocity
  // relative to the part at the step's end (the one friction opposes), is booked apart, the rest
  // (the work of the moving parts through friction) with the contacts' work.
  double work = 0;
  for (std::size_t j = 0; j < k; ++j)
  {
    work += s.inertia[j] * change[j].dot(s.qd[j] + 0.5 * change[j]);
    s.qd[j] += change[j];
    s.q[j] += h * change[j];
  }
  double dissipated = 0;
  for (int m = 0; m < count; ++m)
  {
    const Node& n = nodes[m];
    dissipated -= h * force.segment<2>(2 * m).dot(after.segment<2>(2 * m));
    Strand::Anchor& an = s.anchors[n.i];
    if (slides[m])
    {
      ++stats.sliding;
      an.sliding = true;
      an.placed = false; // the anchor follows it
    }
    else
    {
      ++stats.stuck;
      if (an.sliding)
      {
        an.sliding = false; // stopped: it sticks where it ends the step
        an.placed = false;
      }
    }
  }
  s.frictionDissipated += dissipated;
  s.contactWork += work + dissipated;
}

} // namespace hair
