// The time step: solve() (the step's linear system from M, C, K_T and the contact terms,
// for either integrator, factorized by the unblocked LU of DenseLu.h or, for large N,
// Eigen's), step(), singleStep() (one step of the semi-implicit or the midpoint scheme, its
// checks, the energy flows over the step, its error estimate and the commit), advance()
// (sub-steps controlled by that estimate), and setState().
#include "superhelix/SubstepControl.h"
#include "superhelix/SuperHelix.h"

#include "helix/DenseLu.h"
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

namespace
{
// The second-order step is declined when it would create more energy than this fraction of
// the energy the step moves (the kinetic energy at both ends and the flows' magnitudes).
// Measured on the released frictionless strand (docs/super-helix.md, "The second-order
// step"): with 0 about two thirds of its steps fell back at every dt from 1/30 to 1/240 s
// (midpoint steps err either way by O(h³)), so the scheme was first order; with 0.1 a step
// gaining 10 % at a time let the strand's energy grow fivefold at 1/240 s; 0.01 declined
// 9, 11, 9, 7 steps (1/30 … 1/240 s) and none from 1/1920 s on.
// BDF2 takes the same guard: its one linearization about an extrapolated prediction can
// create energy in a whip (the released frictionless strand at 1/240 s grew a millionfold
// without it). A looser guard for BDF2 was measured and not kept: with 0.05 the demo scene
// (200 guides, 2 s, tolerance 0.05 m/s) took 4 % of its sub-steps first order instead of
// 16 % and closed its energy to 0.7 % instead of 6.3 %, but a smooth strand shaken at 3 Hz
// at 1/30 s gained energy step by step past the stability bound (0.02 failed it too).
constexpr double EnergyGuard = 0.01;
} // namespace
using detail::UnblockedLuMax;

Status SuperHelix::solve(double h, Eigen::VectorXd& qdotNext)
{
  // Semi-implicit ([B06] §3.4, docs/super-helix.md):
  // (M + hΓ + h²(𝕂 + K_T) + h D_air − ½ h C) q̇ⁿ⁺¹ = M q̇ⁿ + h (f − 𝕂 (qⁿ − q_rest) − ½ C q̇ⁿ)
  // D_air = ν ∫ JᵀJ, taken as (ν / ρS) M for a uniform strand (M's rotary-inertia share,
  // < 1e-5 of it, gets the same factor). f is quadratic in q̇, f = f₀ + L q̇ + Q(q̇, q̇),
  // C = ∂f/∂q̇ = L + 2 Q(q̇ⁿ, ·), so f − ½ C q̇ⁿ + ½ C q̇ⁿ⁺¹ = f₀ + L (q̇ⁿ + q̇ⁿ⁺¹)/2 +
  // Q(q̇ⁿ, q̇ⁿ⁺¹): the linear (gyroscopic) terms at the midpoint, one factor of the quadratic
  // ones at the new velocity.
  // Midpoint (while attemptStep takes one): the current state is the predicted midpoint
  // q̃ = qⁿ + h/2 q̇ⁿ, t + h/2, with velocity q̇ⁿ, and the midpoint rule
  // M (q̇ⁿ⁺¹ − q̇ⁿ) = h Φ(q_m, q̇_m), q_m = qⁿ + h/4 (q̇ⁿ + q̇ⁿ⁺¹), q̇_m = (q̇ⁿ + q̇ⁿ⁺¹)/2, is
  // linearized about it with the same M, C, K_T: q_m − q̃ = h/4 (q̇ⁿ⁺¹ − q̇ⁿ),
  // q̇_m − q̇ⁿ = ½ (q̇ⁿ⁺¹ − q̇ⁿ):
  // (M + ½hΓ + ¼h²(𝕂 + K_T) + ½h D_air − ½ h C) q̇ⁿ⁺¹
  //   = (M − ½h D_air − ½ h C + ¼h² K_T) q̇ⁿ + h (f − 𝕂 (q̃ − q_rest)) + (¼h² 𝕂 − ½hΓ) q̇ⁿ.
  // BDF2 (while attemptStep takes one; h here is its weight β = hₙ (1 + ω)/(1 + 2ω)): the
  // current state is the prediction (q*, q̇*) of the step's end, q* = q̂ + β q̇*, and the step
  // qⁿ⁺¹ = q̂ + β q̇ⁿ⁺¹, M (q̇ⁿ⁺¹ − q̇̂) = β Φ(qⁿ⁺¹, q̇ⁿ⁺¹, tⁿ⁺¹) (q̂, q̇̂ from the history) is
  // linearized about it with qⁿ⁺¹ − q* = β (q̇ⁿ⁺¹ − q̇*) and the whole C (a Newton step):
  // (M + βΓ + β²(𝕂 + K_T) + β D_air − β C) q̇ⁿ⁺¹
  //   = M q̇̂ + (β² K_T − β C) q̇* + β (f − 𝕂 (q* − q_rest)) + β² 𝕂 q̇*.
  const bool midpoint = StepScheme == Scheme::Midpoint;
  const bool bdf = StepScheme == Scheme::Bdf2;
  const double hv = midpoint ? 0.5 * h : h;          // weight of the velocity terms
  const double hk = midpoint ? 0.25 * h * h : h * h; // weight of the stiffness terms
  const double nu = Spec.hair.airFriction;
  detail::StepWorkspace& ws = detail::stepWorkspace();
  const Eigen::MatrixXd &M = ws.M, &C = ws.C, &Kt = ws.Kt;
  Eigen::MatrixXd& Lhs = ws.Lhs;
  Eigen::VectorXd& Rhs = ws.Rhs;
  const int m = static_cast<int>(M.rows());
  Lhs.resize(m, m);
  Rhs = h * (F - (Kdiag.array() * (Q - Qrest).array()).matrix());
  // The mass matrix's vector of the midpoint step's right-hand side, (1 − h/2 ν/ρS) q̇ⁿ.
  thread_local Eigen::VectorXd u;
  if (midpoint)
  {
    Rhs.array() += (hk * Kdiag.array() - hv * Gdiag.array()) * Qdot.array();
    u = (1 - hv * nu / RhoS) * Qdot;
  }
  else if (bdf)
  {
    Rhs.array() += hk * Kdiag.array() * Qdot.array();
    u = BdfHat;
  }
  // (The semi-implicit step's factor in the order it always had: the same bits.)
  const double airScale = midpoint ? 1 + hv * nu / RhoS : 1 + h * nu / RhoS;
  const bool withVector = midpoint || bdf;
  // Lhs and the right-hand side's (M − ½ h C) q̇ⁿ (semi-implicit) or
  // M u + (¼h² K_T − ½ h C) q̇ⁿ (midpoint) in one pass over M, C and K_T.
  if (!formStepSystem(Lhs.data(), Rhs.data(), M.data(), C.data(), Kt.data(), Qdot.data(), m,
                      airScale, bdf ? h : 0.5 * h, hk, withVector ? u.data() : nullptr, hk))
    return Status::Error("the step's matrix (mass matrix, velocity Jacobian or tension "
                         "stiffness) is not finite. Check the root motion and forces");
  Lhs.diagonal() += hv * Gdiag + hk * Kdiag;
  if (ContactsSet) // else no sample has a contact stiffness or damping: skip the pass
    addContactJacobians(h, bdf);
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

Status SuperHelix::singleStep(double h, double acceptLimit, bool& rejected)
{
  LastSubsteps = 1;
  LastRejected = 0;
  LastFirstOrder = 0;
  rejected = false;
  Status st = checkStep(h);
  if (!st)
    return st;
  Outcome outcome = Outcome::Committed;
  // BDF2 from the second step on, while the step ratio keeps it zero-stable (ω < 1 + √2);
  // declined (it would create energy, a failed solve or a blow-up), the semi-implicit step is
  // taken instead. Unlike the midpoint step's, its attempts do not back off after a declined
  // one: measured (BM_IntegratorSideBySide, the 3 Hz shake) the back-off saved 3–11 % of the
  // time but took 7–13 % more of the steps first order, and on the demo's head (tolerance
  // 0.05 m/s) it moved the first-order share from 0.16 to 0.22 for the same error and a wall
  // time within the noise.
  if (Spec.integrator == Integrator::Bdf2 && HasPrevious && h <= MaxBdfRatio * PreviousStep)
  {
    st = attemptStep(h, Scheme::Bdf2, acceptLimit, outcome);
    if (!st)
      return st;
    if (outcome != Outcome::Declined)
    {
      rejected = outcome == Outcome::Rejected;
      return st;
    }
  }
  else if (Spec.integrator == Integrator::Midpoint)
  {
    // The second-order step, unless recent attempts were declined (then the next few steps
    // are semi-implicit without trying: each attempt costs the predicted midpoint's
    // kinematics and, when declined for energy or a blow-up, a whole solve).
    if (MidpointSkip > 0)
      --MidpointSkip;
    else
    {
      st = attemptStep(h, Scheme::Midpoint, acceptLimit, outcome);
      if (!st)
        return st;
      if (outcome != Outcome::Declined)
      {
        if (outcome == Outcome::Committed)
          MidpointBackoff = 0;
        rejected = outcome == Outcome::Rejected;
        return st;
      }
      MidpointBackoff = std::min(8, 2 * MidpointBackoff + 1);
      MidpointSkip = MidpointBackoff - 1;
    }
  }
  st = attemptStep(h, Scheme::SemiImplicit, acceptLimit, outcome);
  rejected = outcome == Outcome::Rejected;
  if (st && outcome == Outcome::Committed)
    LastFirstOrder = 1;
  return st;
}

Status SuperHelix::prepareStep(double h, double t0, Scheme scheme, Eigen::VectorXd& qdN,
                               bool& declined, bool& solveFailed)
{
  declined = solveFailed = false;
  const bool midpoint = scheme == Scheme::Midpoint;
  // The weight of the step's implicit terms: h, or BDF2's β.
  const double weight = scheme == Scheme::Bdf2 ? BdfWeight : h;
  const double t1 = t0 + h;
  Status st = evaluateForces(Cur, Time);
  if (!st)
    return Status::Error(where(t0, t1) + st.message());
  // The penalty contacts are stiff (√(k/ρS) ≈ 1000 rad/s, 33/dt at 1/30 s): the midpoint
  // rule leaves such a mode ringing (amplification −0.99 per step) where backward Euler
  // damps it; a strand touching anything takes the semi-implicit step.
  if (midpoint && ContactsSet)
    for (const Node& nd : Cur.nodes)
      if (nd.hasF || nd.hasK || nd.hasD || nd.hasField)
      {
        declined = true;
        return Status::Ok();
      }
  FoldStep = midpoint ? 0 : weight; // the far field's drag and spring into M (assemble())
  assemble();
  FoldStep = 0;
  assembleVelocityJacobian();
  assembleTensionStiffness(weight);
  if (!F.allFinite())
    return Status::Error(where(t0, t1) +
                         "the generalized forces are not finite; the previous state is kept. "
                         "Check the root motion and forces.");
  st = solve(midpoint ? h : weight, qdN);
  solveFailed = !st;
  if (!st)
    return Status::Error(where(t0, t1) + st.message() + "; the previous state is kept.");
  return Status::Ok();
}

Status SuperHelix::attemptStep(double h, Scheme scheme, double acceptLimit, Outcome& outcome,
                               const Eigen::VectorXd* coupled)
{
  outcome = Outcome::Committed;
  const bool midpoint = scheme == Scheme::Midpoint, bdf = scheme == Scheme::Bdf2;
  const double t0 = Time, t1 = Time + h;
  if (!CurValid)
    reconstruct();
  // The contact response in the step workspace is this strand's only until the step ends,
  // and solve() forms this step's system.
  struct EndOfStep
  {
    bool& contactsSet;
    Scheme& scheme;
    const std::vector<StrandSample>*& hookSamples;
    ~EndOfStep()
    {
      contactsSet = false;
      scheme = Scheme::SemiImplicit;
      hookSamples = nullptr;
    }
  } endOfStep{ContactsSet, StepScheme, HookSamples};
  StepScheme = scheme;
  // Where the step is evaluated: the semi-implicit step at the start (Cur); the midpoint
  // step at the predicted midpoint q̃ = qⁿ + h/2 q̇ⁿ, t + h/2, with the velocity q̇ⁿ, which
  // becomes the current state (Q, Time, Cur) while the step is assembled and solved; the
  // start's kinematics wait in `start` and come back if the step is not committed.
  // BDF2 at its prediction of the step's end, tⁿ⁺¹: with ω = hₙ / hₙ₋₁ and the history
  // q̂ = qⁿ + a (qⁿ − qⁿ⁻¹), q̇̂ likewise (a = ω²/(1 + 2ω)), the velocity extrapolated,
  // q̇* = q̇ⁿ + ω (q̇ⁿ − q̇ⁿ⁻¹), and q* = q̂ + β q̇*; its error is O(h³), so the step's
  // linearization about it keeps the second order whatever the approximations in K_T.
  thread_local Kinematics start;
  thread_local Eigen::VectorXd q0, qd0, qHat;
  q0 = Q;
  qd0 = Qdot;
  double tEval = t0;
  if (midpoint)
  {
    std::swap(Cur, start);
    Q.noalias() = q0 + (0.5 * h) * Qdot;
    tEval = t0 + 0.5 * h;
    Time = tEval;
    kinematics(Q, Qdot, rootState(tEval), tEval, Cur);
    newCurId();
    WindsValid = false;
  }
  else if (bdf)
  {
    const double omega = h / PreviousStep;
    const double a = omega * omega / (1 + 2 * omega);
    BdfWeight = h * (1 + omega) / (1 + 2 * omega);
    qHat = q0 + a * (q0 - PreviousQ);
    BdfHat = qd0 + a * (qd0 - PreviousQdot);
    // The prediction's kinematics, then where its samples' material points are now (the
    // contact hook's samples); then the prediction becomes the current state.
    thread_local Kinematics predicted;
    thread_local Eigen::VectorXd qStar, qdStar;
    thread_local std::vector<double> arcs;
    thread_local std::vector<StrandSample> atStart;
    qdStar = qd0 + omega * (qd0 - PreviousQdot);
    qStar = qHat + BdfWeight * qdStar;
    kinematics(qStar, qdStar, rootState(t1), t1, predicted);
    if (Contacts)
    {
      arcs.resize(predicted.nodes.size());
      for (size_t j = 0; j < arcs.size(); ++j)
        arcs[j] = Starts[predicted.nodes[j].element] + predicted.nodes[j].u;
      materialPoints(arcs, false, atStart);
      for (size_t j = 0; j < arcs.size(); ++j)
        atStart[j].weight = predicted.nodes[j].w;
      HookSamples = &atStart;
      HookTime = t0;
    }
    std::swap(Cur, start);
    std::swap(Cur, predicted);
    Qdot = qdStar;
    Q = qStar;
    tEval = t1;
    Time = tEval;
    newCurId();
    WindsValid = false;
  }
  // The midpoint and BDF2 steps are evaluated away from the start, which comes back if the
  // step is not committed.
  const bool awayFromStart = midpoint || bdf;
  // Every return before the commit goes through here.
  auto keep = [&](Status s, Outcome o)
  {
    outcome = o;
    if (awayFromStart)
    {
      Q = q0;
      Qdot = qd0;
      Time = t0;
      std::swap(Cur, start);
      newCurId();
      WindsValid = false;
    }
    return s;
  };
  // A midpoint step that fails for any reason but the input is declined: the semi-implicit
  // step is taken instead (and reports its own error if it fails too).
  auto fail = [&](const std::string& message)
  {
    return awayFromStart ? keep(Status::Ok(), Outcome::Declined)
                         : keep(Status::Error(message), Outcome::Committed);
  };
  // The step's velocities: solved here, or by a coupled step (endStep) from the forces,
  // assembly and solve of its beginStep.
  Eigen::VectorXd qdN;
  Status st;
  if (coupled)
    qdN = *coupled;
  else
  {
    bool declined = false, solveFailed = false;
    st = prepareStep(h, t0, scheme, qdN, declined, solveFailed);
    if (declined)
      return keep(Status::Ok(), Outcome::Declined);
    if (solveFailed)
      return fail(st.message());
    if (!st)
      return keep(st, Outcome::Committed);
  }
  // The velocity of the step: qⁿ⁺¹ = qⁿ + h q̇_step (semi-implicit: q̇ⁿ⁺¹; midpoint:
  // (q̇ⁿ + q̇ⁿ⁺¹)/2); BDF2: qⁿ⁺¹ = q̂ + β q̇ⁿ⁺¹, its flows taken with q̇ⁿ⁺¹.
  const Eigen::VectorXd qdStep = midpoint ? Eigen::VectorXd(0.5 * (Qdot + qdN)) : qdN;
  const Eigen::VectorXd qN = bdf ? Eigen::VectorXd(qHat + BdfWeight * qdN) : q0 + h * qdStep;
  if (!qN.allFinite() || !qdN.allFinite())
    return fail(where(t0, t1) +
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
      return fail(s.str());
    }
  }
  const RootState rootN = rootState(t1);
  st = rootN.validate();
  if (!st)
    return keep(Status::Error(where(t0, t1) + st.message()), Outcome::Committed);

  // Energy flows over the step, at the configuration where the step was evaluated (Cur) with
  // the velocity of the step ṽ = v0 + J q̇_step. The semi-implicit step: at tⁿ, with the
  // acceleration r̈ = a0 + J q̈, q̈ = (q̇ⁿ⁺¹ − q̇ⁿ)/h. The midpoint step: at the predicted
  // midpoint, a midpoint quadrature of each flow's power (second order, like the step); its
  // root work is written without a0, which the midpoint velocity would need (below).
  // BDF2: at its prediction of tⁿ⁺¹ with q̇ⁿ⁺¹ and q̈ = (q̇ⁿ⁺¹ − q̇̂)/β, the contacts' force
  // linearized about the prediction (the rectangle rule: its error over a run is h/2 times
  // the change of each flow's power, not a sum over the steps).
  // The error estimate: the element ends' displacement by δq = h/2 (q̇ⁿ⁺¹ − q̇ⁿ), the first-
  // minus the second-order position update, through the tail Jacobians (J_P(s) = A_P × r(s)
  // + W_P past element P). BDF2: its local error, −(qⁿ⁺¹ − q*)/3 = −β/3 (q̇ⁿ⁺¹ − q̇*) for every
  // step ratio (the prediction's error is −2 times the step's, both O(h³) q⃛).
  EnergyTerms flow;
  double error = 0;
  {
    const Eigen::VectorXd qdd =
        bdf ? Eigen::VectorXd((qdN - BdfHat) / BdfWeight) : Eigen::VectorXd((qdN - Qdot) / h);
    const double nu = Spec.hair.airFriction;
    const Eigen::Vector3d* const winds = Spec.windField ? Winds.data() : nullptr;
    const ContactResponse* const contacts =
        ContactsSet ? detail::stepWorkspace().ContactBuffer.data() : nullptr;
    const RootState& root = Cur.root;
    // The midpoint's root work: ∫ ρS r̈ · v₀ ds = d/dt ∫ ρS ṙ · v₀ ds − ∫ ρS ṙ · v̇₀ ds, and
    // following a material point v̇₀ = a_c + α_c × (r − r_c) + ω_c × (ṙ − v_c), of which
    // ṙ · (ω_c × ṙ) = 0: the first term is the change of Kinematics::carried over the step,
    // the second a midpoint quadrature.
    const Eigen::Vector3d carriedAcc =
        root.acceleration - root.angularVelocity.cross(root.velocity);
    Eigen::Vector3d pa = Eigen::Vector3d::Zero(), pw = Eigen::Vector3d::Zero();
    Eigen::Vector3d sa = Eigen::Vector3d::Zero(), sw = Eigen::Vector3d::Zero();
    Eigen::Vector3d da = Eigen::Vector3d::Zero(), dw = Eigen::Vector3d::Zero();
    for (int e = 0; e < elementCount(); ++e)
    {
      const Element& el = Cur.elements[e];
      const Eigen::Vector3d x = qdStep.segment<3>(3 * e), y = qdd.segment<3>(3 * e);
      for (int j = el.first; j < el.first + el.count; ++j)
      {
        const Node& nd = Cur.nodes[j];
        const Eigen::Vector3d vt = nd.v0 + pa.cross(nd.r) + pw + nd.J * x;
        const Eigen::Vector3d& wind = winds ? winds[j] : Spec.wind;
        const Eigen::Vector3d rel = vt - wind;
        flow.airDissipated += h * nd.w * nu * rel.squaredNorm();
        flow.windWork -= h * nd.w * nu * rel.dot(wind);
        // The contact force that acted: its implicit linearization (see ContactResponse).
        // (A midpoint step has none: a strand in contact takes the semi-implicit step.)
        Eigen::Vector3d fc = Eigen::Vector3d::Zero();
        if (contacts)
        {
          if (nd.hasF)
            fc = contacts[j].force;
          if (nd.hasK)
            fc -= bdf ? Eigen::Vector3d(BdfWeight * (contacts[j].stiffness * (vt - nd.v)))
                      : Eigen::Vector3d(h * (contacts[j].stiffness * vt));
          if (nd.hasD)
            fc -= contacts[j].damping * (vt - nd.v);
          if (nd.hasField)
          {
            // drag (medium − ṽ) + push − spring h ṽ (BDF2: spring β (ṽ − v*)), as assemble()
            // folded it into the step.
            const ContactResponse& c = contacts[j];
            const Eigen::Vector3d slip = vt - c.medium;
            const Eigen::Vector3d ff = c.push - c.drag * slip -
                                       (bdf ? Eigen::Vector3d((BdfWeight * c.spring) * (vt - nd.v))
                                            : Eigen::Vector3d((h * c.spring) * vt));
            flow.fieldWork += h * nd.w * ff.dot(vt);
            flow.fieldDissipated += h * nd.w * c.drag * slip.squaredNorm();
            fc += ff;
          }
        }
        flow.contactWork += h * nd.w * fc.dot(vt);
        const Eigen::Vector3d f = RhoS * Spec.gravity - nu * rel + fc;
        if (midpoint)
        {
          const Eigen::Vector3d vdot0 =
              carriedAcc + root.angularAcceleration.cross(nd.r - root.position);
          flow.rootWork -= h * nd.w * (RhoS * vt.dot(vdot0) + f.dot(nd.v0));
        }
        else
        {
          const Eigen::Vector3d rdd = nd.a0 + sa.cross(nd.r) + sw + nd.J * y;
          flow.rootWork += h * nd.w * (RhoS * rdd - f).dot(nd.v0);
        }
      }
      pa += el.A * x;
      pw += el.W * x;
      sa += el.A * y;
      sw += el.W * y;
      const Eigen::Vector3d dq =
          (bdf ? BdfWeight / 3 : 0.5 * h) * (qdN.segment<3>(3 * e) - Qdot.segment<3>(3 * e));
      da += el.A * dq;
      dw += el.W * dq;
      const Eigen::Vector3d& end = e + 1 < elementCount() ? Cur.elements[e + 1].r0 : Cur.tip.r0;
      error = std::max(error, (da.cross(end) + dw).norm());
    }
    if (!Spec.tipForce.isZero(0))
    {
      const Eigen::Vector3d& rt = Cur.tip.r0;
      const Eigen::Vector3d v0t =
          Cur.root.velocity + Cur.root.angularVelocity.cross(rt - Cur.root.position);
      flow.loadWork += h * Spec.tipForce.dot(v0t + pa.cross(rt) + pw);
      flow.rootWork -= h * Spec.tipForce.dot(v0t);
    }
    flow.frictionDissipated = h * (Gdiag.array() * qdStep.array().square()).sum();
  }
  LastError = error;
  LastErrorPower = bdf ? 3 : 2;
  if (error > acceptLimit)
    return keep(Status::Ok(), Outcome::Rejected);

  // The new state's kinematics go to a per-thread buffer that is swapped with Cur on
  // commit, so each strand keeps one set of samples (not two): with hundreds of strands
  // stepped in turn, the strand's data streamed through the caches is what a step costs.
  thread_local Kinematics next;
  kinematics(qN, qdN, rootN, t1, next);
  if (midpoint) // the change of ∫ ρS ṙ · v₀ over the step (see above)
    flow.rootWork += next.carried - start.carried;
  const double elastic = elasticEnergy(qN);
  const double e0 = Energy.mechanical();
  const double e1 = next.kinetic + elastic + next.gravitational;
  if (!std::isfinite(e1))
    return fail(where(t0, t1) + "the energy is not finite; the previous state is kept.");
  flow.residual = e1 - e0 - flow.rootWork - flow.windWork - flow.contactWork - flow.loadWork +
                  flow.frictionDissipated + flow.airDissipated;
  // The energy guard of the second-order steps (EnergyGuard): the midpoint rule is not
  // dissipative, and where the step does not resolve the motion (a whip, the 3 Hz shake at
  // 1/30 s) its linearization can create energy without bound; BDF2 damps what it does not
  // resolve when the system is linear, but its one linearization about an extrapolated
  // prediction can create energy in a whip. Such a step is declined.
  if (awayFromStart)
  {
    const double moved = Energy.kinetic + next.kinetic + std::abs(flow.rootWork) +
                         std::abs(flow.windWork) + std::abs(flow.contactWork) +
                         std::abs(flow.loadWork) + flow.frictionDissipated + flow.airDissipated;
    if (flow.residual > EnergyGuard * moved)
      return keep(Status::Ok(), Outcome::Declined);
  }

  // Commit; the step left becomes the history of the next.
  PreviousQ = q0;
  PreviousQdot = qd0;
  PreviousStep = h;
  HasPrevious = true;
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
  Energy.total.fieldWork += flow.fieldWork;
  Energy.total.fieldDissipated += flow.fieldDissipated;
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
  MidpointSkip = MidpointBackoff = 0;
  HasPrevious = false;
  reconstruct();
  Energy.time = Time;
  Energy.kinetic = Cur.kinetic;
  Energy.gravitational = Cur.gravitational;
  Energy.elastic = elasticEnergy(Q);
  return Status::Ok();
}

namespace
{
// The scalars of a strand's continuation, before q, q̇, BDF2's history and the energy report.
constexpr std::size_t ContinuationScalars = 11;
constexpr std::size_t EnergyReportValues = sizeof(EnergyReport) / sizeof(double);
static_assert(sizeof(EnergyReport) == 22 * sizeof(double),
              "EnergyReport is saved as its doubles: a new member must be a double");
} // namespace

std::size_t SuperHelix::continuationSize(int elements)
{
  return ContinuationScalars + 4 * 3 * std::size_t(elements) + EnergyReportValues;
}

void SuperHelix::saveContinuation(std::vector<double>& out) const
{
  const int n = 3 * elementCount();
  const double scalars[ContinuationScalars] = {
      Time,        double(LastSubsteps),   double(LastRejected),   double(LastFirstOrder),
      LastError,   double(LastErrorPower), double(MidpointSkip),   double(MidpointBackoff),
      NextSubstep, PreviousStep,           HasPrevious ? 1.0 : 0.0};
  out.insert(out.end(), scalars, scalars + ContinuationScalars);
  auto append = [&](const Eigen::VectorXd& v)
  {
    if (v.size() == n)
    {
      out.insert(out.end(), v.data(), v.data() + n);
    }
    else
    {
      out.insert(out.end(), std::size_t(n), 0.0); // no history yet
    }
  };
  append(Q);
  append(Qdot);
  append(PreviousQ);
  append(PreviousQdot);
  const double* e = reinterpret_cast<const double*>(&Energy);
  out.insert(out.end(), e, e + EnergyReportValues);
}

Status SuperHelix::restoreContinuation(const double* values, std::size_t count, std::size_t& used)
{
  used = 0;
  const int n = 3 * elementCount();
  const std::size_t need = continuationSize(elementCount());
  if (!Initialized || count < need)
  {
    return Status::Error("strand '" + Spec.name + "': its continuation has " +
                         std::to_string(count) + " numbers, a strand of " +
                         std::to_string(elementCount()) + " elements needs " +
                         std::to_string(need) + ".");
  }
  for (std::size_t i = 0; i < need; ++i)
  {
    if (!std::isfinite(values[i]))
    {
      return Status::Error("strand '" + Spec.name +
                           "': its continuation has a non-finite number (" + std::to_string(i) +
                           ").");
    }
  }
  const double* v = values;
  Time = v[0];
  LastSubsteps = int(v[1]);
  LastRejected = int(v[2]);
  LastFirstOrder = int(v[3]);
  LastError = v[4];
  LastErrorPower = int(v[5]);
  MidpointSkip = int(v[6]);
  MidpointBackoff = int(v[7]);
  NextSubstep = v[8];
  PreviousStep = v[9];
  HasPrevious = v[10] != 0;
  v += ContinuationScalars;
  Q = Eigen::Map<const Eigen::VectorXd>(v, n);
  Qdot = Eigen::Map<const Eigen::VectorXd>(v + n, n);
  PreviousQ = Eigen::Map<const Eigen::VectorXd>(v + 2 * n, n);
  PreviousQdot = Eigen::Map<const Eigen::VectorXd>(v + 3 * n, n);
  if (!HasPrevious)
  {
    PreviousQ.resize(0);
    PreviousQdot.resize(0);
  }
  v += 4 * n;
  std::copy(v, v + EnergyReportValues, reinterpret_cast<double*>(&Energy));
  Pending = PendingStep();
  ContactsSet = false;
  reconstruct();
  used = need;
  return Status::Ok();
}

Status SuperHelix::advance(double dt, double tolerance)
{
  if (!(tolerance > 0))
    return step(dt);
  Status st = checkStep(dt);
  if (!st)
    return st;
  // Sub-steps h controlled by the step's embedded error estimate e(h) (lastErrorEstimate):
  // accepted when e <= tolerance · h / dt, so that the accepted estimates add up to at most
  // `tolerance` over dt. e is the first-order update's local error, O(h²), so the ratio
  // r = e / (tolerance · h / dt) is O(h) and the next sub-step is h · 0.9 / r (at most
  // doubled, at least a fifth); BDF2's estimate is its own local error, O(h³), and the next
  // sub-step h · 0.9 / √r (superhelix/SubstepControl.h). The sub-step carries over to the next
  // advance(); with BDF2 it is at most MaxBdfRatio times the one before.
  const Eigen::VectorXd q0 = Q, qd0 = Qdot;
  const double t0 = Time;
  const EnergyReport en0 = Energy;
  const double hMin = dt / MaxSubsteps;
  double h = NextSubstep > 0 ? std::min(NextSubstep, dt) : dt;
  double remaining = dt, errorSum = 0;
  int accepted = 0, rejectedCount = 0, firstOrder = 0;
  EnergyTerms sum;
  while (remaining > 1e-12 * dt)
  {
    // The last sub-steps of the interval: one that reaches its end, or two equal ones
    // rather than a long one followed by a sliver.
    double hs = std::max(h, hMin);
    if (Spec.integrator == Integrator::Bdf2 && HasPrevious)
      hs = std::max(hMin, std::min(hs, MaxBdfRatio * PreviousStep));
    hs = substeps::land(hs, remaining);
    // At the smallest sub-step (or when the sub-steps would run out) accept whatever the
    // estimate: the sum reported says how far it is from the tolerance.
    const bool last = hs <= hMin * (1 + 1e-9) || accepted + rejectedCount >= 4 * MaxSubsteps;
    const double allowed = tolerance * hs / dt;
    bool rejected = false;
    st = singleStep(hs, last ? std::numeric_limits<double>::infinity() : allowed, rejected);
    if (!st)
    {
      Q = q0;
      Qdot = qd0;
      Time = t0;
      Energy = en0;
      reconstruct();
      return st;
    }
    const double grow = substeps::factor(LastError / allowed, LastErrorPower);
    if (rejected)
    {
      ++rejectedCount;
      h = substeps::afterRejected(hs, grow);
      continue;
    }
    ++accepted;
    firstOrder += LastFirstOrder;
    errorSum += LastError;
    remaining -= hs;
    const EnergyTerms& l = Energy.lastStep;
    sum.frictionDissipated += l.frictionDissipated;
    sum.airDissipated += l.airDissipated;
    sum.rootWork += l.rootWork;
    sum.windWork += l.windWork;
    sum.contactWork += l.contactWork;
    sum.loadWork += l.loadWork;
    sum.residual += l.residual;
    sum.fieldWork += l.fieldWork;
    sum.fieldDissipated += l.fieldDissipated;
    // The next sub-step from this one's ratio; one shortened only to land on the interval's
    // end does not hold back the next (at most twice the longer of the two).
    h = substeps::afterAccepted(hs, grow, h);
  }
  NextSubstep = std::min(h, dt);
  Energy.lastStep = sum;
  LastSubsteps = accepted;
  LastRejected = rejectedCount;
  LastFirstOrder = firstOrder;
  LastError = errorSum;
  return Status::Ok();
}

} // namespace hair
