// The time step: solve() (the step's linear system from M, C, K_T and the contact terms,
// factorized by the unblocked LU of DenseLu.h or, for large N, Eigen's), step(),
// singleStep() (one step of the semi-implicit scheme, its checks, the energy flows over the
// step and the commit), advance() and stepCount() (step doubling to a tolerance), and
// setState().
#include "superhelix/SuperHelix.h"

#include "superhelix/DenseLu.h"
#include "superhelix/StepKernels.h"
#include "superhelix/SuperHelixInternal.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace hair
{

using detail::formStepSystem;
using detail::UnblockedLuMax;

Status SuperHelix::solve(double h, Eigen::VectorXd& qdotNext)
{
  // (M + hΓ + h²(𝕂 + K_T) + h D_air − ½ h C) q̇ⁿ⁺¹ = M q̇ⁿ + h (f − 𝕂 (qⁿ − q_rest) − ½ C q̇ⁿ)
  // (docs/super-helix.md). D_air = ν ∫ JᵀJ, taken as (ν / ρS) M for a uniform strand (M's
  // rotary-inertia share, < 1e-5 of it, gets the same factor). f is quadratic in q̇,
  // f = f₀ + L q̇ + Q(q̇, q̇), C = ∂f/∂q̇ = L + 2 Q(q̇ⁿ, ·), so f − ½ C q̇ⁿ + ½ C q̇ⁿ⁺¹ =
  // f₀ + L (q̇ⁿ + q̇ⁿ⁺¹)/2 + Q(q̇ⁿ, q̇ⁿ⁺¹): the linear (gyroscopic) terms at the midpoint,
  // one factor of the quadratic ones at the new velocity.
  const double airScale = 1 + h * Spec.hair.airFriction / RhoS;
  detail::StepWorkspace& ws = detail::stepWorkspace();
  const Eigen::MatrixXd &M = ws.M, &C = ws.C, &Kt = ws.Kt;
  Eigen::MatrixXd& Lhs = ws.Lhs;
  Eigen::VectorXd& Rhs = ws.Rhs;
  const int m = static_cast<int>(M.rows());
  Lhs.resize(m, m);
  Rhs = h * (F - (Kdiag.array() * (Q - Qrest).array()).matrix());
  // Lhs and M q̇ − ½ h C q̇ in one pass over M, C and K_T.
  if (!formStepSystem(Lhs.data(), Rhs.data(), M.data(), C.data(), Kt.data(), Qdot.data(), m,
                      airScale, 0.5 * h, h * h))
    return Status::Error("the step's matrix (mass matrix, velocity Jacobian or tension "
                         "stiffness) is not finite. Check the root motion and forces");
  Lhs.diagonal() += h * Gdiag + h * h * Kdiag;
  if (ContactsSet) // else no sample has a contact stiffness or damping: skip the pass
    addContactJacobians(h);
  const double scale = Lhs.diagonal().cwiseAbs().maxCoeff();
  if (m > UnblockedLuMax)
  {
    // Large systems: Eigen's blocked LU (its cache blocking pays off past 3N = 360).
    Eigen::PartialPivLU<Eigen::MatrixXd>& Lu = ws.Lu;
    Lu.compute(Lhs);
    const double pivotL = Lu.matrixLU().diagonal().cwiseAbs().minCoeff();
    if (!(pivotL > 1e-30 * scale))
      return Status::Error("the step's matrix is singular (smallest pivot " +
                           std::to_string(pivotL) + ")");
    qdotNext = Lu.solve(Rhs);
    return Status::Ok();
  }
  // Small systems: LU with partial pivoting (row interchanges, as LAPACK getrf / Eigen's
  // PartialPivLU) in panels of four columns, without packing: at 3N = 30 Eigen's blocked
  // kernel spends most of its time in packing and dispatch.
  std::vector<int>& Pivots = ws.Pivots;
  Pivots.resize(static_cast<size_t>(m));
  const double pivot = luSolveInPlace(Lhs.data(), Rhs.data(), m, Pivots.data());
  if (!(pivot > 1e-30 * scale))
    return Status::Error("the step's matrix is singular (smallest pivot " + std::to_string(pivot) +
                         ")");
  qdotNext = Rhs;
  return Status::Ok();
}

Status SuperHelix::step(double dt)
{
  Status st = checkStep(dt);
  if (!st)
    return st;
  st = singleStep(dt);
  if (!st)
    reconstruct(); // singleStep keeps q, q̇, time and energies; refresh the kinematics
  return st;
}

Status SuperHelix::checkStep(double dt) const
{
  if (!Initialized)
    return Status::Error("SuperHelix::step: the strand is not initialized; call initialize().");
  if (!(std::isfinite(dt) && dt > 0))
  {
    std::ostringstream s;
    s << "strand '" << Spec.name << "' (id " << Spec.id << ") at t = " << Time << " s: dt = " << dt
      << " is invalid; the time step must be finite and > 0 seconds "
      << "(1/30 is stable for every preset).";
    return Status::Error(s.str());
  }
  return Status::Ok();
}

Status SuperHelix::stepCount(double dt, int count)
{
  if (count == 1)
    return singleStep(dt);
  const Eigen::VectorXd q0 = Q, qd0 = Qdot;
  const double t0 = Time;
  const EnergyReport e0 = Energy;
  EnergyTerms sum;
  for (int i = 0; i < count; ++i)
  {
    const Status st = singleStep(dt / count);
    if (!st)
    {
      Q = q0;
      Qdot = qd0;
      Time = t0;
      Energy = e0;
      reconstruct();
      return st;
    }
    const EnergyTerms& l = Energy.lastStep;
    sum.frictionDissipated += l.frictionDissipated;
    sum.airDissipated += l.airDissipated;
    sum.rootWork += l.rootWork;
    sum.windWork += l.windWork;
    sum.contactWork += l.contactWork;
    sum.loadWork += l.loadWork;
    sum.residual += l.residual;
  }
  Energy.lastStep = sum;
  LastSubsteps = count;
  return Status::Ok();
}

Status SuperHelix::singleStep(double h)
{
  LastSubsteps = 1;
  if (!Initialized)
    return Status::Error("SuperHelix::step: the strand is not initialized; call initialize().");
  if (!(std::isfinite(h) && h > 0))
  {
    std::ostringstream s;
    s << "strand '" << Spec.name << "' (id " << Spec.id << ") at t = " << Time << " s: dt = " << h
      << " is invalid; the time step must be finite and > 0 seconds "
      << "(1/30 is stable for every preset).";
    return Status::Error(s.str());
  }
  if (!CurValid)
    reconstruct();
  // The contact response in the step workspace is this strand's only until the step ends.
  struct EndOfStep
  {
    bool& contactsSet;
    ~EndOfStep() { contactsSet = false; }
  } endOfStep{ContactsSet};
  Eigen::VectorXd qdN;
  if (Status st = prepareStep(h, qdN); !st)
    return st;
  return commitStep(h, qdN);
}

Status SuperHelix::prepareStep(double h, Eigen::VectorXd& qdN)
{
  const double t0 = Time, t1 = Time + h;
  Status st = evaluateForces(Cur, t0);
  if (!st)
    return Status::Error(where(t0, t1) + st.message());
  assemble();
  assembleVelocityJacobian();
  assembleTensionStiffness(h);
  if (!F.allFinite())
    return Status::Error(where(t0, t1) +
                         "the generalized forces are not finite; the previous state is kept. "
                         "Check the root motion and forces.");
  st = solve(h, qdN);
  if (!st)
    return Status::Error(where(t0, t1) + st.message() + "; the previous state is kept.");
  return Status::Ok();
}

Status SuperHelix::commitStep(double h, const Eigen::VectorXd& qdN)
{
  const double t0 = Time, t1 = Time + h;
  const Eigen::VectorXd qN = Q + h * qdN;
  if (!qN.allFinite() || !qdN.allFinite())
    return Status::Error(
        where(t0, t1) +
        "the step blew up (non-finite curvature); the previous state is kept. Reduce dt or "
        "check the forces.");
  // A fibre cannot bend tighter than its own radius: past that the model is meaningless.
  const double limit = 1.0 / Spec.hair.radius;
  for (int e = 0; e < elementCount(); ++e)
  {
    const double om = qN.segment<3>(3 * e).norm();
    if (om > limit)
    {
      std::ostringstream s;
      s << where(t0, t1) << "the step blew up: element " << e << " reached curvature " << om
        << " 1/m, tighter than 1/radius = " << limit
        << " 1/m; the previous state is kept. Reduce dt or check the forces.";
      return Status::Error(s.str());
    }
  }
  const RootState rootN = rootState(t1);
  Status st = rootN.validate();
  if (!st)
    return Status::Error(where(t0, t1) + st.message());

  // Energy flows over the step, at the configuration of tⁿ with the velocity of the step
  // ṽ = v0 + J q̇ⁿ⁺¹ and the acceleration r̈ = a0 + J q̈, q̈ = (q̇ⁿ⁺¹ − q̇ⁿ)/h.
  EnergyTerms flow;
  {
    const Eigen::VectorXd qdd = (qdN - Qdot) / h;
    const double nu = Spec.hair.airFriction;
    const Eigen::Vector3d* const winds = Spec.windField ? Winds.data() : nullptr;
    const ContactResponse* const contacts =
        ContactsSet ? detail::stepWorkspace().ContactBuffer.data() : nullptr;
    Eigen::Vector3d pa = Eigen::Vector3d::Zero(), pw = Eigen::Vector3d::Zero();
    Eigen::Vector3d sa = Eigen::Vector3d::Zero(), sw = Eigen::Vector3d::Zero();
    for (int e = 0; e < elementCount(); ++e)
    {
      const Element& el = Cur.elements[e];
      const Eigen::Vector3d x = qdN.segment<3>(3 * e), y = qdd.segment<3>(3 * e);
      for (int j = el.first; j < el.first + el.count; ++j)
      {
        const Node& nd = Cur.nodes[j];
        const Eigen::Vector3d vt = nd.v0 + pa.cross(nd.r) + pw + nd.J * x;
        const Eigen::Vector3d rdd = nd.a0 + sa.cross(nd.r) + sw + nd.J * y;
        const Eigen::Vector3d& wind = winds ? winds[j] : Spec.wind;
        const Eigen::Vector3d rel = vt - wind;
        flow.airDissipated += h * nd.w * nu * rel.squaredNorm();
        flow.windWork -= h * nd.w * nu * rel.dot(wind);
        // The contact force that acted: its implicit linearization (see ContactResponse).
        Eigen::Vector3d fc = Eigen::Vector3d::Zero();
        if (contacts)
        {
          if (nd.hasF)
            fc = contacts[j].force;
          if (nd.hasK)
            fc -= h * (contacts[j].stiffness * vt);
          if (nd.hasD)
            fc -= contacts[j].damping * (vt - nd.v);
        }
        flow.contactWork += h * nd.w * fc.dot(vt);
        const Eigen::Vector3d f = RhoS * Spec.gravity - nu * rel + fc;
        flow.rootWork += h * nd.w * (RhoS * rdd - f).dot(nd.v0);
      }
      pa += el.A * x;
      pw += el.W * x;
      sa += el.A * y;
      sw += el.W * y;
    }
    if (!Spec.tipForce.isZero(0))
    {
      const Eigen::Vector3d& rt = Cur.tip.r0;
      const Eigen::Vector3d v0t =
          Cur.root.velocity + Cur.root.angularVelocity.cross(rt - Cur.root.position);
      flow.loadWork += h * Spec.tipForce.dot(v0t + pa.cross(rt) + pw);
      flow.rootWork -= h * Spec.tipForce.dot(v0t);
    }
    flow.frictionDissipated = h * (Gdiag.array() * qdN.array().square()).sum();
  }

  // The new state's kinematics go to a per-thread buffer that is swapped with Cur on
  // commit, so each strand keeps one set of samples (not two): with hundreds of strands
  // stepped in turn, the strand's data streamed through the caches is what a step costs.
  thread_local Kinematics next;
  kinematics(qN, qdN, rootN, t1, next);
  const double elastic = elasticEnergy(qN);
  const double e0 = Energy.mechanical();
  const double e1 = next.kinetic + elastic + next.gravitational;
  if (!std::isfinite(e1))
    return Status::Error(where(t0, t1) + "the energy is not finite; the previous state is kept.");
  flow.residual = e1 - e0 - flow.rootWork - flow.windWork - flow.contactWork - flow.loadWork +
                  flow.frictionDissipated + flow.airDissipated;

  // Commit.
  Q = qN;
  Qdot = qdN;
  Time = t1;
  std::swap(Cur, next);
  newCurId();
  CurValid = true;
  WindsValid = false; // the wind field at the new samples is evaluated when needed
  Energy.time = t1;
  Energy.kinetic = Cur.kinetic;
  Energy.gravitational = Cur.gravitational;
  Energy.elastic = elastic;
  Energy.lastStep = flow;
  Energy.total.frictionDissipated += flow.frictionDissipated;
  Energy.total.airDissipated += flow.airDissipated;
  Energy.total.rootWork += flow.rootWork;
  Energy.total.windWork += flow.windWork;
  Energy.total.contactWork += flow.contactWork;
  Energy.total.loadWork += flow.loadWork;
  Energy.total.residual += flow.residual;
  return Status::Ok();
}

Status SuperHelix::setState(const Eigen::VectorXd& q, const Eigen::VectorXd& qdot)
{
  if (!Initialized)
    return Status::Error("SuperHelix::setState: the strand is not initialized.");
  const int n = 3 * elementCount();
  if (q.size() != n || qdot.size() != n)
    return Status::Error("strand '" + Spec.name +
                         "': setState needs q and qdot of size 3N = " + std::to_string(n) + ".");
  if (!q.allFinite() || !qdot.allFinite())
    return Status::Error("strand '" + Spec.name + "': setState got non-finite q or qdot.");
  Q = q;
  Qdot = qdot;
  reconstruct();
  Energy.time = Time;
  Energy.kinetic = Cur.kinetic;
  Energy.gravitational = Cur.gravitational;
  Energy.elastic = elasticEnergy(Q);
  return Status::Ok();
}

Status SuperHelix::advance(double dt, double tolerance, int maxDepth)
{
  if (!(tolerance > 0))
    return step(dt);
  Status st = checkStep(dt);
  if (!st)
    return st;
  // Step doubling: n sub-steps against 2n, on every element end, doubling n until they
  // agree within `tolerance`; the finer result is kept.
  int n = 1;
  const Eigen::VectorXd q0 = Q, qd0 = Qdot;
  const double t0 = Time;
  const EnergyReport en0 = Energy;
  auto restore = [&]()
  {
    Q = q0;
    Qdot = qd0;
    Time = t0;
    Energy = en0;
    reconstruct();
  };
  auto ends = [&]()
  {
    std::vector<Eigen::Vector3d> e;
    for (const Element& el : Cur.elements)
      e.push_back(el.r0);
    e.push_back(Cur.tip.r0);
    return e;
  };
  Status prev = stepCount(dt, n);
  std::vector<Eigen::Vector3d> prevEnds;
  if (prev)
    prevEnds = ends();
  for (int depth = 0; depth < maxDepth && 2 * n <= MaxSubsteps; ++depth)
  {
    restore();
    n *= 2;
    st = stepCount(dt, n);
    if (st && prev)
    {
      const std::vector<Eigen::Vector3d> e = ends();
      double err = 0;
      for (size_t i = 0; i < e.size(); ++i)
        err = std::max(err, (e[i] - prevEnds[i]).norm());
      if (err <= tolerance)
        return Status::Ok();
      prevEnds = e;
    }
    else if (st)
      prevEnds = ends();
    prev = st;
  }
  if (!st)
    restore();
  return st;
}

} // namespace hair
