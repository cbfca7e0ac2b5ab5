// sagFree: the balance 𝕂 (q − q_rest) = f(q) solved for q_rest with the step's own
// generalized force (SuperHelix::assemble) and the contacts' forces summed through the
// Jacobian at the same quadrature samples; the stability of the result from H's smallest
// eigenvalue; the closest stable shape by settling the strand with raised damping.
#include "groom/SagFree.h"

#include "groom/CurveFit.h"

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

/// f(q) of the strand at rest in `q`: gravity and the tip force, and the contacts' forces
/// summed through the Jacobian at the quadrature samples. With `columns`, the contacts are
/// left out of f and given instead as one column w Jᵀ n per sample in contact (n the unit
/// direction of its force) with the force's magnitude in `magnitudes`.
void restForce(SuperHelix& h, const Eigen::VectorXd& q, const ContactForces& contacts,
               Eigen::VectorXd& f, Eigen::MatrixXd* columns = nullptr,
               Eigen::VectorXd* magnitudes = nullptr)
{
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(q.size());
  h.setState(q, zero);
  h.assemble();
  f = h.generalizedForce();
  if (columns)
  {
    columns->resize(q.size(), 0);
    magnitudes->resize(0);
  }
  if (!contacts)
  {
    return;
  }
  const std::vector<StrandSample>& samples = h.samples();
  std::vector<ContactResponse> response(samples.size());
  contacts(h.spec().id, h.time(), samples, response);
  std::vector<Eigen::VectorXd> cols;
  std::vector<double> mags;
  for (std::size_t i = 0; i < samples.size() && i < response.size(); ++i)
  {
    const Eigen::Vector3d& c = response[i].force;
    if (c.isZero(0))
    {
      continue;
    }
    const Eigen::Matrix3Xd J = h.jacobian(samples[i].s);
    if (columns)
    {
      cols.push_back(samples[i].weight * (J.transpose() * c.normalized()));
      mags.push_back(c.norm());
    }
    else
    {
      f.noalias() += samples[i].weight * (J.transpose() * c);
    }
  }
  if (columns)
  {
    columns->resize(q.size(), static_cast<Eigen::Index>(cols.size()));
    magnitudes->resize(static_cast<Eigen::Index>(mags.size()));
    for (std::size_t i = 0; i < cols.size(); ++i)
    {
      columns->col(static_cast<Eigen::Index>(i)) = cols[i];
      (*magnitudes)(static_cast<Eigen::Index>(i)) = mags[i];
    }
  }
}

/// The contact forces the body carries the strand with: λ in [0, λmax] per sample in contact
/// (λmax the penalty's force at the given shape) minimizing the prestress the rest shape must
/// hold, ½ |f_g + C λ|²_{𝕂⁻¹} (C the columns w Jᵀ n): where the strand rests on the body,
/// the body carries its weight, not its stiffness. Coordinate descent on the box-constrained
/// convex quadratic (each step exact in its coordinate), until no force changes by more than
/// 1e-12 of the largest bound.
Eigen::VectorXd carriedContacts(const Eigen::VectorXd& fg, const Eigen::MatrixXd& C,
                                const Eigen::VectorXd& lambdaMax, const Eigen::VectorXd& K)
{
  const Eigen::Index n = C.cols();
  Eigen::VectorXd lambda = lambdaMax; // the penalty's own forces: the exact balance at the shape
  if (n == 0)
  {
    return lambda;
  }
  const Eigen::VectorXd Kinv = K.cwiseInverse();
  Eigen::VectorXd r = fg + C * lambda; // f(λ)
  Eigen::VectorXd a(n);
  for (Eigen::Index i = 0; i < n; ++i)
  {
    a(i) = C.col(i).cwiseProduct(Kinv).dot(C.col(i));
  }
  const double tol = 1e-12 * lambdaMax.maxCoeff();
  for (int sweep = 0; sweep < 2000; ++sweep)
  {
    double change = 0;
    for (Eigen::Index i = 0; i < n; ++i)
    {
      if (!(a(i) > 0))
      {
        continue;
      }
      const double g = C.col(i).cwiseProduct(Kinv).dot(r);
      const double next = std::clamp(lambda(i) - g / a(i), 0.0, lambdaMax(i));
      const double d = next - lambda(i);
      if (d != 0)
      {
        r.noalias() += d * C.col(i);
        lambda(i) = next;
        change = std::max(change, std::abs(d));
      }
    }
    if (change <= tol)
    {
      break;
    }
  }
  return lambda;
}

/// H = 𝕂 − ∂f_g/∂q (symmetrized; gravity and the tip force by central differences) + the
/// contacts' stiffness Σ w Jᵀ K J as their response gives it, at q; f the rest force with the
/// contacts. The turning of the contacts' normals over the body (λ ∂n/∂x, of relative size
/// λ / (k R) ~ 1e-4 against the normal stiffness for a resting strand on the head) is left
/// out: differences across the table's cells and the edge of the contact layer would swamp it.
void hessian(SuperHelix& h, const Eigen::VectorXd& q, const ContactForces& contacts,
             Eigen::MatrixXd& H, Eigen::VectorXd& f)
{
  const int m = static_cast<int>(q.size());
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
    restForce(h, qp, ContactForces(), fp);
    restForce(h, qm, ContactForces(), fm);
    G.col(j) = -(fp - fm) / (2 * eps);
  }
  H = 0.5 * (G + G.transpose());
  H.diagonal() += h.stiffnessDiagonal();
  restForce(h, q, contacts, f);
  if (!contacts)
  {
    return;
  }
  const std::vector<StrandSample>& samples = h.samples();
  std::vector<ContactResponse> response(samples.size());
  contacts(h.spec().id, h.time(), samples, response);
  for (std::size_t i = 0; i < samples.size() && i < response.size(); ++i)
  {
    if (!response[i].stiffness.isZero(0))
    {
      const Eigen::Matrix3Xd J = h.jacobian(samples[i].s);
      const Eigen::Matrix3d S = 0.5 * (response[i].stiffness + response[i].stiffness.transpose());
      H.noalias() += samples[i].weight * (J.transpose() * S * J);
    }
  }
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

/// How far the strand moves from `shape` in `time` s of steps of `dt`, started pushed by
/// 1e-9 rad along `mode` with its own damping: the simulator's own verdict on an equilibrium
/// the Hessian calls stable, which also sees what the Hessian leaves out (the contacts hold
/// only against being pushed in and their normals turn over the body; friction holds nothing
/// at rest). `end` receives where it is then.
double drift(const StrandSpec& still, const Eigen::VectorXd& rest, const Eigen::VectorXd& shape,
             const Eigen::VectorXd& mode, const ContactForces& contacts, double time, double dt,
             Eigen::VectorXd& end)
{
  StrandSpec s = still;
  s.restCurvature.assign(rest.data(), rest.data() + rest.size());
  SuperHelix h;
  end = shape;
  if (!h.initialize(s, 0.0).ok())
  {
    return std::numeric_limits<double>::infinity();
  }
  h.setContactForces(contacts);
  double turn = 0;
  for (int e = 0; e < h.elementCount(); ++e)
  {
    turn = std::max(turn, mode.segment<3>(3 * e).norm() * s.elementLengths[e]);
  }
  h.setState(shape + (1e-9 / std::max(turn, 1e-300)) * mode, Eigen::VectorXd::Zero(shape.size()));
  std::vector<Eigen::Vector3d> start, now;
  h.polyline(8, start);
  double moved = 0;
  const int steps = static_cast<int>(std::ceil(time / dt));
  for (int i = 0; i < steps; ++i)
  {
    if (!h.step(dt).ok())
    {
      return std::numeric_limits<double>::infinity();
    }
    h.polyline(8, now);
    for (std::size_t j = 0; j < now.size(); ++j)
    {
      moved = std::max(moved, (now[j] - start[j]).norm());
    }
  }
  end = h.q();
  return moved;
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
  // The prestress q − q_rest bends (and twists) the fibre: its strain at the surface, |Δk| a
  // (a the larger semi-axis), may not pass hair's elastic range (options.elasticStrain).
  const double limit =
      o.elasticStrain / (spec.hair.radius * std::sqrt(spec.hair.ellipticity)); // on |Δk|
  auto smallest = [&](const Eigen::MatrixXd& A, Eigen::VectorXd* vector)
  {
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(A);
    if (vector)
    {
      *vector = eig.eigenvectors().col(0);
    }
    return eig.eigenvalues()(0) / kMax;
  };
  auto balanced = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& f)
  { return Eigen::VectorXd(q - (f.array() / K.array()).matrix()); };
  // The element whose prestress strains the fibre most beyond the limit (−1: none), and the
  // rest shape with every prestress cut back to the limit.
  auto tightestElement =
      [&](const Eigen::VectorXd& q, const Eigen::VectorXd& rest, double& tightness)
  {
    int tightest = -1;
    tightness = 0;
    for (int e = 0; e < h.elementCount(); ++e)
    {
      const double k = (q - rest).segment<3>(3 * e).norm();
      if (k > limit && k > tightness)
      {
        tightest = e;
        tightness = k;
      }
    }
    return tightest;
  };
  auto withinLimit = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& rest)
  {
    Eigen::VectorXd out = rest;
    for (int e = 0; e < h.elementCount(); ++e)
    {
      const Eigen::Vector3d d = (q - rest).segment<3>(3 * e);
      if (d.norm() > limit)
      {
        out.segment<3>(3 * e) = q.segment<3>(3 * e) - (limit / d.norm()) * d;
      }
    }
    return out;
  };

  // The balance at the shape with the contacts' forces as the body gives them there: exact,
  // so the shape itself is the equilibrium.
  SagFreeResult r;
  Eigen::MatrixXd H;
  Eigen::VectorXd f;
  hessian(h, shape, contacts, H, f);
  r.rest = balanced(shape, f);
  r.start = shape;
  Eigen::VectorXd mode;
  r.stability = smallest(H, &mode);
  double tightness = 0;
  int tightest = tightestElement(shape, r.rest, tightness);
  // A shape pressed into the body deeper than its load needs (a groom taken from motion) gets
  // more from the penalty than it should carry; when that would strain the fibre past its
  // range, the body carries only what leaves the least prestress (carriedContacts) and the
  // strand settles onto it, a little off the shape.
  bool pressed = false;
  if (tightest >= 0 && contacts)
  {
    Eigen::VectorXd fg, lambdaMax;
    Eigen::MatrixXd C;
    restForce(h, shape, contacts, fg, &C, &lambdaMax);
    const Eigen::VectorXd lambda = carriedContacts(fg, C, lambdaMax, K);
    const Eigen::VectorXd carried = balanced(shape, fg + C * lambda);
    double t2 = 0;
    if (tightestElement(shape, carried, t2) < 0)
    {
      r.rest = carried;
      tightest = -1;
      pressed = true;
    }
  }
  const bool stable = r.stability > o.stabilityMargin;
  // A shape the Hessian calls stable is held if the simulator keeps it: pushed by 1e-9 rad,
  // it must stay within 0.1 mm over the settling time (an instability the run would show
  // within ~20 s from round-off grows past that from the push). Those that drift away are
  // unstable after all, and settle on from where they got to.
  Eigen::VectorXd drifted;
  bool slides = false;
  if (stable && tightest < 0 && !pressed)
  {
    const double moved =
        drift(still, r.rest, shape, mode, contacts, o.relaxTime, o.relaxStep, drifted);
    slides = !(moved <= 1e-4);
  }
  if (stable && tightest < 0 && !pressed && !slides)
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
      why << "holding this shape strains the fibre by " << 100 * tightness / limit * o.elasticStrain
          << " % at its surface in element " << tightest << ", beyond hair's elastic range ("
          << 100 * o.elasticStrain << " %): its stiffness cannot carry its weight there";
      rest = withinLimit(shape, rest);
      starts.push_back(shape);
    }
    else if (slides)
    {
      r.outcome = RestOutcome::Unstable;
      why << "this shape is balanced by a natural shape and its Hessian is positive, but the "
             "strand does not stay: pushed by 1e-9 rad it leaves it by more than 0.1 mm within "
          << o.relaxTime
          << " s (what the Hessian leaves out: the body holds it only against being pushed in, "
             "and friction holds nothing at rest)";
      starts.push_back(drifted);
    }
    else if (!stable)
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
    else
    {
      r.outcome = RestOutcome::Held; // held, resting on the body instead of in it
      starts.push_back(shape);
    }
    // Where the strand settles from the shape with this rest shape (the nearer of the two
    // pushes): the closest stable equilibrium.
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
    // Its rest shape exactly balanced there (settling stops at a rate, not at zero).
    hessian(h, r.start, contacts, H, f);
    r.rest = balanced(r.start, f);
    // Within the elastic range whatever the outcome: a strand that had not settled is not
    // balanced where it stopped, and balancing it exactly there can ask for any prestress.
    r.rest = withinLimit(r.start, r.rest);
    const double settledStability = smallest(H, nullptr);
    r.deviation = best;
    if (r.outcome != RestOutcome::Held)
    {
      why << "; the closest stable shape, " << best << " m from it at most, is used";
    }
    else
    {
      why << "resting on the body rather than pressed into it, " << best << " m from the shape";
    }
    if (!settled)
    {
      why << " (" << failure << ")";
    }
    if (!(settledStability > o.stabilityMargin))
    {
      why << "; it is not stable either (" << settledStability << ")";
    }
    r.reason = why.str();
  }
  restForce(h, r.start, contacts, f);
  const double fn = f.norm();
  r.imbalance = fn > 0 ? ((K.array() * (r.start - r.rest).array()).matrix() - f).norm() / fn : 0.0;
  result = std::move(r);
  return Status::Ok();
}

} // namespace hair
