// segmentsAlongCurve (the inscribed chain of equal segments, by bisection on their length)
// and projectiveSagFree (the rest angles from the step's own moments at rest, the Hessian by
// central differences of them, the closest stable shape by settling a copy of the strand
// alone in the scene held still).
#include "projective/ProjectiveGroom.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace hair
{

namespace
{

/// Walks `segments` chords of length d along the polyline from its start: each node the
/// first point past the previous one (in the polyline's parameter) at distance d from it.
/// Returns how far along the polyline (its own arc length) the last node lands, or more
/// than the polyline's length when the walk runs off its end.
double walk(const std::vector<Eigen::Vector3d>& c, const std::vector<double>& arc, int segments,
            double d, std::vector<Eigen::Vector3d>* nodes)
{
  const double beyond = arc.back() + 1;
  std::size_t seg = 0; // polyline segment [seg, seg + 1] holding the current node
  double t = 0;        // fraction along it
  Eigen::Vector3d p = c[0];
  if (nodes)
  {
    nodes->assign(1, p);
  }
  for (int k = 0; k < segments; ++k)
  {
    bool found = false;
    while (seg + 1 < c.size())
    {
      // |a + τ (b − a) − p| = d for the smallest τ ≥ t on this segment.
      const Eigen::Vector3d a = c[seg], e = c[seg + 1] - c[seg];
      const double A = e.squaredNorm(), B = 2 * e.dot(a - p), C = (a - p).squaredNorm() - d * d;
      const double disc = B * B - 4 * A * C;
      if (disc >= 0)
      {
        const double root = std::sqrt(disc);
        for (double tau : {(-B - root) / (2 * A), (-B + root) / (2 * A)})
        {
          if (tau >= t && tau <= 1)
          {
            t = tau;
            found = true;
            break;
          }
        }
      }
      if (found)
      {
        break;
      }
      ++seg;
      t = 0;
    }
    if (!found)
    {
      return beyond;
    }
    p = c[seg] + t * (c[seg + 1] - c[seg]);
    if (nodes)
    {
      nodes->push_back(p);
    }
  }
  return arc[seg] + t * (arc[seg + 1] - arc[seg]);
}

/// Largest distance of the points `x` from the polyline `chain`.
double distanceToChain(const std::vector<Eigen::Vector3d>& x,
                       const std::vector<Eigen::Vector3d>& chain)
{
  double worst = 0;
  for (const Eigen::Vector3d& p : x)
  {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i + 1 < chain.size(); ++i)
    {
      const Eigen::Vector3d e = chain[i + 1] - chain[i];
      const double t = std::clamp((p - chain[i]).dot(e) / e.squaredNorm(), 0.0, 1.0);
      best = std::min(best, (chain[i] + t * e - p).norm());
    }
    worst = std::max(worst, best);
  }
  return worst;
}

std::vector<Eigen::Vector3d> chainOf(ProjectiveStrands& sim, int s,
                                     const std::vector<Eigen::Vector2d>& angles)
{
  const std::vector<Eigen::Vector2d> zero(angles.size(), Eigen::Vector2d::Zero());
  sim.setState(s, angles, zero);
  return sim.nodes(s);
}

/// H = κ I − ∂Q/∂q (symmetrized; central differences of turns of 1e-6 rad) and Q at `q`.
void hessian(ProjectiveStrands& sim, int s, const std::vector<Eigen::Vector2d>& q,
             Eigen::MatrixXd& H, std::vector<Eigen::Vector2d>& Q)
{
  const int k = static_cast<int>(q.size());
  const std::vector<Eigen::Vector2d> zero(q.size(), Eigen::Vector2d::Zero());
  Eigen::MatrixXd G(2 * k, 2 * k);
  std::vector<Eigen::Vector2d> qp, qm, Qp, Qm;
  const double eps = 1e-6;
  for (int j = 0; j < 2 * k; ++j)
  {
    qp = q;
    qm = q;
    qp[j / 2](j % 2) += eps;
    qm[j / 2](j % 2) -= eps;
    sim.setState(s, qp, zero);
    sim.restMoments(s, Qp);
    sim.setState(s, qm, zero);
    sim.restMoments(s, Qm);
    for (int i = 0; i < k; ++i)
    {
      G.block<2, 1>(2 * i, j) = -(Qp[i] - Qm[i]) / (2 * eps);
    }
  }
  H = 0.5 * (G + G.transpose());
  H.diagonal().array() += sim.hingeStiffness(s);
  sim.setState(s, q, zero);
  sim.restMoments(s, Q);
}

/// A constant pose as a motion (two samples of it).
RigidMotion held(const Eigen::Isometry3d& pose)
{
  return RigidMotion::samples({0.0, 1.0}, {pose, pose});
}

/// Strand s settled from `from` with rest angles `rest`, alone in the scene held at t = 0,
/// its damping rate raised. Returns whether it settled.
bool settle(const ProjectiveStrands& sim, int s, const std::vector<Eigen::Vector2d>& rest,
            const std::vector<Eigen::Vector2d>& from, const SagFreeOptions& o,
            std::vector<Eigen::Vector2d>& out, std::string& failure)
{
  Scene scene = sim.scene();
  for (ScenePart& p : scene.parts)
  {
    p.motion = held(p.motion.pose(sim.time()));
  }
  scene.rootMotion = RigidMotion::still();
  scene.air = AirField();
  ProjectiveStrand one;
  one.root = sim.nodes(s)[0];
  one.rootFrame = sim.rootFrame(s);
  one.segmentLength = sim.segmentLength(s);
  one.restAngles = rest;
  one.angles = from;
  one.parameters = sim.material(s);
  one.parameters.dampingRate = std::max(one.parameters.dampingRate, o.relaxDamping);
  ProjectiveOptions options = sim.options();
  options.threads = 1;
  ProjectiveStrands alone;
  if (Status st = alone.initialize({one}, scene, options); !st)
  {
    failure = st.message();
    out = from;
    return false;
  }
  const long steps = std::lround(o.relaxTime / options.timeStep);
  // The rate is checked every 1/30 s, so that a slow swing is not taken for rest.
  const long every = std::max(1L, std::lround(1.0 / (30 * options.timeStep)));
  int quiet = 0;
  for (long i = 1; i <= steps; ++i)
  {
    if (Status st = alone.step(); !st)
    {
      failure = st.message();
      out = alone.angles(0);
      return false;
    }
    if (i % every == 0)
    {
      double fastest = 0;
      for (const Eigen::Vector2d& r : alone.rates(0))
      {
        fastest = std::max(fastest, r.norm());
      }
      quiet = fastest < o.settledRate ? quiet + 1 : 0;
      if (quiet >= 5)
      {
        out = alone.angles(0);
        return true;
      }
    }
  }
  out = alone.angles(0);
  std::ostringstream m;
  m << "it had not settled after " << o.relaxTime << " s";
  failure = m.str();
  return false;
}

double norm(const std::vector<Eigen::Vector2d>& v)
{
  double n = 0;
  for (const Eigen::Vector2d& x : v)
  {
    n += x.squaredNorm();
  }
  return std::sqrt(n);
}

} // namespace

Status segmentsAlongCurve(const std::vector<Eigen::Vector3d>& curve, int segments,
                          std::vector<Eigen::Vector3d>& nodes, double& fitError)
{
  if (curve.size() < 2 || segments < 1)
  {
    return Status::Error("segmentsAlongCurve: a curve of at least two points and at least one "
                         "segment are needed.");
  }
  std::vector<double> arc(curve.size(), 0.0);
  for (std::size_t j = 1; j < curve.size(); ++j)
  {
    arc[j] = arc[j - 1] + (curve[j] - curve[j - 1]).norm();
  }
  const double L = arc.back();
  // Chords are no longer than the arcs they span, so d = L / segments reaches the end (or
  // runs off it) and a small d stops short of it: bisect on d for the last node at the end.
  double lo = 0, hi = L / segments;
  for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; ++it)
  {
    const double mid = 0.5 * (lo + hi);
    (walk(curve, arc, segments, mid, nullptr) < L ? lo : hi) = mid;
  }
  std::vector<Eigen::Vector3d> chain;
  walk(curve, arc, segments, lo, &chain);
  if (static_cast<int>(chain.size()) != segments + 1)
  {
    return Status::Error("segmentsAlongCurve: no chain of equal segments follows this curve.");
  }
  // The last node lands on the curve's end, but for a curve that comes back near itself:
  // there a slightly longer d makes a node jump to a later stretch of the curve, and no d puts
  // the last node exactly at the end. The chain then ends short of it, its segments still
  // equal, the gap counted in the fit's error.
  if ((chain.back() - curve.back()).norm() <= 1e-9 * lo)
  {
    chain.back() = curve.back();
  }
  fitError = std::max(distanceToChain(curve, chain), (chain.back() - curve.back()).norm());
  nodes = std::move(chain);
  return Status::Ok();
}

Status projectiveSagFree(ProjectiveStrands& sim, int s, const SagFreeOptions& o,
                         ProjectiveSagFree& result)
{
  if (s < 0 || s >= sim.numberOfStrands())
  {
    return Status::Error("projectiveSagFree: no strand " + std::to_string(s));
  }
  const double kappa = sim.hingeStiffness(s);
  const std::vector<Eigen::Vector2d> shape = sim.angles(s);
  const std::vector<Eigen::Vector3d> shapeNodes = sim.nodes(s);
  auto smallest = [&](const Eigen::MatrixXd& H, Eigen::VectorXd* vector)
  {
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(H);
    if (vector)
    {
      *vector = eig.eigenvectors().col(0);
    }
    return eig.eigenvalues()(0) / kappa;
  };
  auto balanced = [&](const std::vector<Eigen::Vector2d>& q, const std::vector<Eigen::Vector2d>& Q)
  {
    std::vector<Eigen::Vector2d> rest(q.size());
    for (std::size_t i = 0; i < q.size(); ++i)
    {
      rest[i] = q[i] - Q[i] / kappa;
    }
    return rest;
  };

  // The hinges' prestress κ (q − q⁰) bends the fibre by |q − q⁰| / d: at its surface the
  // strain |q − q⁰| r / d may not pass hair's elastic range (options.elasticStrain).
  const double radius = 0.5 * sim.material(s).dragDiameter;
  const double limit = radius > 0 ? o.elasticStrain * sim.segmentLength(s) / radius
                                  : std::numeric_limits<double>::infinity(); // on |Δq|
  auto withinLimit =
      [&](const std::vector<Eigen::Vector2d>& q, const std::vector<Eigen::Vector2d>& rest)
  {
    std::vector<Eigen::Vector2d> out = rest;
    for (std::size_t i = 0; i < q.size(); ++i)
    {
      const Eigen::Vector2d d = q[i] - rest[i];
      if (d.norm() > limit)
      {
        out[i] = q[i] - (limit / d.norm()) * d;
      }
    }
    return out;
  };

  ProjectiveSagFree r;
  Eigen::MatrixXd H;
  std::vector<Eigen::Vector2d> Q;
  hessian(sim, s, shape, H, Q);
  r.rest = balanced(shape, Q);
  r.start = shape;
  Eigen::VectorXd mode;
  r.report.stability = smallest(H, &mode);
  r.report.outcome = RestOutcome::Held;
  int tightest = -1;
  double tightness = 0;
  for (std::size_t i = 0; i < shape.size(); ++i)
  {
    const double d = (shape[i] - r.rest[i]).norm();
    if (d > limit && d > tightness)
    {
      tightest = static_cast<int>(i);
      tightness = d;
    }
  }
  if (tightest >= 0 || !(r.report.stability > o.stabilityMargin))
  {
    std::ostringstream why;
    std::vector<std::vector<Eigen::Vector2d>> starts;
    std::vector<Eigen::Vector2d> rest = r.rest;
    if (tightest >= 0)
    {
      r.report.outcome = RestOutcome::BeyondBending;
      why << "holding this shape strains the fibre by " << 100 * o.elasticStrain * tightness / limit
          << " % at its surface at segment " << tightest << ", beyond hair's elastic range ("
          << 100 * o.elasticStrain << " %): its stiffness cannot carry its weight there";
      rest = withinLimit(shape, rest);
      starts.push_back(shape);
    }
    else
    {
      r.report.outcome = RestOutcome::Unstable;
      why << "this shape is balanced by rest angles but not stable (the Hessian's smallest "
             "eigenvalue is "
          << r.report.stability
          << " of the hinge stiffness: a push makes it fall away, as a strand standing up or "
             "held out beyond what its hinges carry does)";
      const double turn = mode.cwiseAbs().maxCoeff();
      for (double sign : {1.0, -1.0})
      {
        std::vector<Eigen::Vector2d> from = shape;
        for (std::size_t i = 0; i < from.size(); ++i)
        {
          from[i] += sign * (1e-4 / std::max(turn, 1e-300)) * mode.segment<2>(2 * i);
        }
        starts.push_back(from);
      }
    }
    double best = std::numeric_limits<double>::infinity();
    bool settled = false;
    std::string failure;
    for (const std::vector<Eigen::Vector2d>& from : starts)
    {
      std::vector<Eigen::Vector2d> end;
      std::string fail;
      const bool ok = settle(sim, s, rest, from, o, end, fail);
      const std::vector<Eigen::Vector3d> nodes = chainOf(sim, s, end);
      double d = 0;
      for (std::size_t i = 0; i < nodes.size(); ++i)
      {
        d = std::max(d, (nodes[i] - shapeNodes[i]).norm());
      }
      if (d < best)
      {
        best = d;
        r.start = end;
        settled = ok;
        failure = fail;
      }
    }
    hessian(sim, s, r.start, H, Q);
    r.rest = balanced(r.start, Q);
    // Within the elastic range whatever the outcome (a strand that had not settled is not
    // balanced where it stopped).
    r.rest = withinLimit(r.start, r.rest);
    const double settledStability = smallest(H, nullptr);
    r.report.deviation = best;
    why << "; the closest stable shape, " << best << " m from it at most, is used";
    if (!settled)
    {
      why << " (" << failure << ")";
    }
    if (!(settledStability > o.stabilityMargin))
    {
      why << "; it is not stable either (" << settledStability << ")";
    }
    r.report.reason = why.str();
  }
  const std::vector<Eigen::Vector2d> zero(shape.size(), Eigen::Vector2d::Zero());
  if (Status st = sim.setState(s, r.start, zero); !st)
  {
    return st;
  }
  if (Status st = sim.setRestAngles(s, r.rest); !st)
  {
    return st;
  }
  sim.restMoments(s, Q);
  std::vector<Eigen::Vector2d> gap(Q.size());
  for (std::size_t i = 0; i < Q.size(); ++i)
  {
    gap[i] = kappa * (r.start[i] - r.rest[i]) - Q[i];
  }
  const double qn = norm(Q);
  r.imbalance = qn > 0 ? norm(gap) / qn : 0.0;
  result = std::move(r);
  return Status::Ok();
}

} // namespace hair
