// sagFree: the balance 𝕂 (q − q_rest) = f(q) solved for q_rest with the step's own
// generalized force (SuperHelix::assemble) and the contacts' forces summed through the
// Jacobian at the same quadrature samples; the stability of the result from H's smallest
// eigenvalue; the closest stable shape by settling the strand with raised damping.
#include "superhelix/SagFree.h"

#include "superhelix/CurveFit.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace hair
{

namespace
{

/// The strand `spec` held still at its root's pose at t = 0, no wind: what the balance and
/// the settling are computed on.
StrandSpec stillSpec(const StrandSpec& spec)
{
  StrandSpec s = spec;
  RootState r = spec.root ? spec.root(0.0) : RootState{};
  RootState still;
  still.position = r.position;
  still.orientation = r.orientation;
  s.root = [still](double) { return still; };
  s.wind.setZero();
  s.windField = nullptr;
  return s;
}

/// f(q) of the strand at rest in `q` (gravity, tip force, contacts) and, when asked, the
/// contacts' stiffness Σ w Jᵀ K J.
void restForce(SuperHelix& h, const Eigen::VectorXd& q, const ContactForces& contacts,
               Eigen::VectorXd& f, Eigen::MatrixXd* contactStiffness)
{
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(q.size());
  h.setState(q, zero);
  h.assemble();
  f = h.generalizedForce();
  if (contactStiffness)
  {
    contactStiffness->setZero(q.size(), q.size());
  }
  if (!contacts)
  {
    return;
  }
  const std::vector<StrandSample>& samples = h.samples();
  std::vector<ContactResponse> response(samples.size());
  contacts(h.spec().id, h.time(), samples, response);
  for (std::size_t i = 0; i < samples.size() && i < response.size(); ++i)
  {
    const ContactResponse& c = response[i];
    const bool force = !c.force.isZero(0), stiff = contactStiffness && !c.stiffness.isZero(0);
    if (!force && !stiff)
    {
      continue;
    }
    const Eigen::Matrix3Xd J = h.jacobian(samples[i].s);
    if (force)
    {
      f.noalias() += samples[i].weight * (J.transpose() * c.force);
    }
    if (stiff)
    {
      *contactStiffness += samples[i].weight * (J.transpose() * c.stiffness * J);
    }
  }
}

/// H = 𝕂 + K_contact − ∂f_gravity/∂q (symmetrized) at q.
void hessian(SuperHelix& h, const Eigen::VectorXd& q, const ContactForces& contacts,
             Eigen::MatrixXd& H, Eigen::VectorXd& f)
{
  const int m = static_cast<int>(q.size());
  Eigen::MatrixXd Kc;
  restForce(h, q, contacts, f, &Kc);
  Eigen::MatrixXd G(m, m);
  Eigen::VectorXd fp, fm;
  for (int j = 0; j < m; ++j)
  {
    // A turn of 1e-5 rad over the element: truncation (1e-10 relative) and round-off
    // (1e-11 of |f| ℓ) both far below 𝕂's entries.
    const double eps = 1e-5 / h.spec().elementLengths[j / 3];
    Eigen::VectorXd qp = q, qm = q;
    qp(j) += eps;
    qm(j) -= eps;
    restForce(h, qp, ContactForces(), fp, nullptr);
    restForce(h, qm, ContactForces(), fm, nullptr);
    G.col(j) = -(fp - fm) / (2 * eps);
  }
  H = 0.5 * (G + G.transpose()) + Kc;
  H.diagonal() += h.stiffnessDiagonal();
  h.setState(q, Eigen::VectorXd::Zero(m));
}

/// Largest distance between two shapes of the same strand, at 8 points per element.
double shapeDistance(const SuperHelix& h, const Eigen::VectorXd& a, const Eigen::VectorXd& b)
{
  const RootState r = h.rootState(0.0);
  const int n = h.elementCount();
  std::vector<double> s;
  for (int i = 0; i <= 8 * n; ++i)
  {
    s.push_back(h.length() * i / (8.0 * n));
  }
  std::vector<Eigen::Vector3d> pa, pb;
  superHelixPoints(a, r.orientation, r.position, h.length(), s, pa);
  superHelixPoints(b, r.orientation, r.position, h.length(), s, pb);
  double d = 0;
  for (std::size_t i = 0; i < pa.size(); ++i)
  {
    d = std::max(d, (pa[i] - pb[i]).norm());
  }
  return d;
}

/// The strand settled from `from` with rest shape `rest` (steps with raised drag until no
/// element turns faster than the settled rate). Returns whether it settled.
bool settle(const StrandSpec& still, const Eigen::VectorXd& rest, const Eigen::VectorXd& from,
            const ContactForces& contacts, const SagFreeOptions& o, Eigen::VectorXd& out,
            std::string& failure)
{
  StrandSpec s = still;
  s.restCurvature.assign(rest.data(), rest.data() + rest.size());
  s.hair.airFriction = o.relaxDamping * s.hair.linearDensity();
  SuperHelix h;
  if (Status st = h.initialize(s, 0.0); !st)
  {
    failure = st.message();
    out = from;
    return false;
  }
  h.setContactForces(contacts);
  h.setState(from, Eigen::VectorXd::Zero(from.size()));
  const int steps = static_cast<int>(std::ceil(o.relaxTime / o.relaxStep));
  int quiet = 0;
  for (int i = 0; i < steps; ++i)
  {
    if (Status st = h.step(o.relaxStep); !st)
    {
      failure = st.message();
      out = h.q();
      return false;
    }
    double fastest = 0;
    for (int e = 0; e < h.elementCount(); ++e)
    {
      fastest = std::max(fastest, h.qdot().segment<3>(3 * e).norm() * s.elementLengths[e]);
    }
    quiet = fastest < o.settledRate ? quiet + 1 : 0;
    if (quiet >= 5)
    {
      out = h.q();
      return true;
    }
  }
  out = h.q();
  std::ostringstream m;
  m << "it had not settled after " << o.relaxTime << " s";
  failure = m.str();
  return false;
}

} // namespace

Status restHessian(const StrandSpec& spec, const Eigen::VectorXd& shape,
                   const ContactForces& contacts, Eigen::MatrixXd& H, Eigen::VectorXd& f)
{
  SuperHelix h;
  if (Status s = h.initialize(stillSpec(spec), 0.0); !s)
  {
    return s;
  }
  if (shape.size() != 3 * h.elementCount() || !shape.allFinite())
  {
    return Status::Error("strand '" + spec.name + "': the shape needs 3N finite values.");
  }
  hessian(h, shape, contacts, H, f);
  return Status::Ok();
}

Status sagFree(const StrandSpec& spec, const Eigen::VectorXd& shape, const ContactForces& contacts,
               const SagFreeOptions& o, SagFreeResult& result)
{
  const StrandSpec still = stillSpec(spec);
  SuperHelix h;
  if (Status s = h.initialize(still, 0.0); !s)
  {
    return s;
  }
  const int m = 3 * h.elementCount();
  if (shape.size() != m || !shape.allFinite())
  {
    return Status::Error("strand '" + spec.name + "': the shape needs 3N finite values.");
  }
  const Eigen::VectorXd& K = h.stiffnessDiagonal();
  const double kMax = K.maxCoeff();
  const double limit = 1.0 / spec.hair.radius;
  Eigen::MatrixXd H;
  Eigen::VectorXd f;
  auto smallest = [&](const Eigen::MatrixXd& A, Eigen::VectorXd* vector)
  {
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(A);
    if (vector)
    {
      *vector = eig.eigenvectors().col(0);
    }
    return eig.eigenvalues()(0) / kMax;
  };

  SagFreeResult r;
  hessian(h, shape, contacts, H, f);
  r.rest = shape - (f.array() / K.array()).matrix();
  r.start = shape;
  Eigen::VectorXd mode;
  r.stability = smallest(H, &mode);
  int tightest = -1;
  double tightness = 0;
  for (int e = 0; e < h.elementCount(); ++e)
  {
    const double k = r.rest.segment<3>(3 * e).norm();
    if (k > limit && k > tightness)
    {
      tightest = e;
      tightness = k;
    }
  }
  const bool stable = r.stability > o.stabilityMargin;
  if (stable && tightest < 0)
  {
    r.outcome = RestOutcome::Held;
  }
  else
  {
    std::ostringstream why;
    Eigen::VectorXd rest = r.rest;
    std::vector<Eigen::VectorXd> starts;
    if (tightest >= 0)
    {
      r.outcome = RestOutcome::BeyondBending;
      why << "holding this shape needs a natural curvature of " << tightness << " 1/m in element "
          << tightest << ", tighter than 1/radius = " << limit
          << " 1/m (its stiffness cannot carry its weight there)";
      for (int e = 0; e < h.elementCount(); ++e)
      {
        const double k = rest.segment<3>(3 * e).norm();
        if (k > limit)
        {
          rest.segment<3>(3 * e) *= (1 - 1e-9) * limit / k;
        }
      }
      starts.push_back(shape);
    }
    else
    {
      r.outcome = RestOutcome::Unstable;
      why << "this shape is balanced by a natural shape but not stable (the Hessian's smallest "
             "eigenvalue is "
          << r.stability
          << " of the largest stiffness: a push makes it buckle away, as a strand held out too "
             "far twists over or a standing one falls)";
      // A push of 1e-4 rad along the unstable mode, either way.
      double turn = 0;
      for (int e = 0; e < h.elementCount(); ++e)
      {
        turn = std::max(turn, mode.segment<3>(3 * e).norm() * spec.elementLengths[e]);
      }
      const Eigen::VectorXd push = (1e-4 / std::max(turn, 1e-300)) * mode;
      starts.push_back(shape + push);
      starts.push_back(shape - push);
    }
    // The closest stable shape: where the strand settles from the given one with this rest
    // shape, the nearer of the two pushes.
    double best = std::numeric_limits<double>::infinity();
    std::string failure;
    bool settled = false;
    for (const Eigen::VectorXd& from : starts)
    {
      Eigen::VectorXd end;
      std::string fail;
      const bool ok = settle(still, rest, from, contacts, o, end, fail);
      const double d = shapeDistance(h, shape, end);
      if (d < best)
      {
        best = d;
        r.start = end;
        settled = ok;
        failure = fail;
      }
    }
    // Its rest shape exactly balanced there (it was only nearly: settling stops at a rate).
    hessian(h, r.start, contacts, H, f);
    r.rest = r.start - (f.array() / K.array()).matrix();
    if (r.outcome == RestOutcome::BeyondBending)
    {
      for (int e = 0; e < h.elementCount(); ++e)
      {
        const double k = r.rest.segment<3>(3 * e).norm();
        if (k > limit)
        {
          r.rest.segment<3>(3 * e) *= (1 - 1e-9) * limit / k;
        }
      }
    }
    r.stability = smallest(H, nullptr);
    r.deviation = best;
    why << "; the closest stable shape, " << best << " m from it at most, is used";
    if (!settled)
    {
      why << " (" << failure << ")";
    }
    if (!(r.stability > o.stabilityMargin))
    {
      why << "; it is not stable either (" << r.stability << ")";
    }
    r.reason = why.str();
  }
  restForce(h, r.start, contacts, f, nullptr);
  const double fn = f.norm();
  r.imbalance = fn > 0 ? ((K.array() * (r.start - r.rest).array()).matrix() - f).norm() / fn : 0.0;
  result = std::move(r);
  return Status::Ok();
}

} // namespace hair
