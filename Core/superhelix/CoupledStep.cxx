// The step split around a solve that couples strands (hair–hair contacts): beginStep (the
// step without the coupling forces; its factorized matrix kept, the samples' velocities at
// its end), compliance (the coupling samples' answer to point forces, from the kept
// factors) and endStep (the forces added, the step committed).
#include "superhelix/SuperHelix.h"

#include "superhelix/SuperHelixInternal.h"

#include <limits>
#include <sstream>

namespace hair
{

Status SuperHelix::beginStep(double h)
{
  Pending.active = false;
  if (Status st = checkStep(h); !st)
    return st;
  LastSubsteps = 1;
  if (!CurValid)
    reconstruct();
  struct EndOfStep
  {
    bool& contactsSet;
    ~EndOfStep() { contactsSet = false; }
  } endOfStep{ContactsSet};
  // The semi-implicit step, whatever the integrator: the coupling solve needs its
  // linearization (a strand that ends up carrying no coupling force may take its own step
  // instead, endStep).
  Eigen::VectorXd qd;
  bool declined = false, solveFailed = false;
  if (Status st = prepareStep(h, Time, Scheme::SemiImplicit, qd, declined, solveFailed); !st)
    return st;
  endVelocities(qd, Pending.free);
  detail::StepWorkspace& ws = detail::stepWorkspace();
  const int m = static_cast<int>(Q.size());
  if (m > detail::UnblockedLuMax)
    Pending.largeLu = ws.Lu;
  else
  {
    Pending.lu = ws.Lhs;
    Pending.pivots.assign(ws.Pivots.begin(), ws.Pivots.begin() + m);
  }
  Pending.h = h;
  Pending.qdot = std::move(qd);
  Pending.contactsSet = ContactsSet;
  if (ContactsSet)
    Pending.contacts = ws.ContactBuffer;
  Pending.active = true;
  return Status::Ok();
}

void SuperHelix::endVelocities(const Eigen::VectorXd& qd, std::vector<StrandSample>& out) const
{
  // The samples' velocities at the end of the step, v0 + Σ_{p<e} ((A_p q̇_p) × r + W_p q̇_p)
  // + J q̇_e (as the energy flows and the kinematics take them), at their current places.
  out = samples();
  thread_local std::vector<Eigen::Vector3d> velocities;
  sampleVelocities(qd, true, velocities);
  for (size_t j = 0; j < out.size(); ++j)
    out[j].velocity = velocities[j];
}

void SuperHelix::predictedSamples(const Eigen::VectorXd& response,
                                  std::vector<StrandSample>& out) const
{
  if (!Pending.active)
  {
    out = samples();
    return;
  }
  if (response.size() != Pending.qdot.size())
  {
    out = Pending.free;
    return;
  }
  endVelocities(Pending.qdot + response, out);
}

Status SuperHelix::compliance(const std::vector<int>& samples, StrandCompliance& out) const
{
  if (!Pending.active)
    return Status::Error("strand '" + Spec.name +
                         "': compliance() needs a step begun by beginStep().");
  const int nodes = static_cast<int>(Cur.nodes.size());
  for (size_t k = 0; k < samples.size(); ++k)
    if (samples[k] < 0 || samples[k] >= nodes || (k > 0 && samples[k] <= samples[k - 1]))
    {
      std::ostringstream s;
      s << "strand '" << Spec.name << "' (id " << Spec.id << "): coupling sample " << samples[k]
        << " is not an increasing index below the strand's " << nodes << " samples.";
      return Status::Error(s.str());
    }
  // J_kᵀ: the columns of v_k = v0_k + J_k q̇; Y = h A⁻¹ Jᵀ from the kept factors.
  const int m = static_cast<int>(Q.size()), count = static_cast<int>(samples.size());
  out.samples = samples;
  out.freeVelocity.resize(count);
  out.columns.resize(count);
  out.Jt.setZero(m, 3 * count);
  for (int k = 0; k < count; ++k)
  {
    const Node& nd = Cur.nodes[samples[k]];
    auto Jk = out.Jt.middleCols<3>(3 * k);
    for (int p = 0; p < nd.element; ++p)
    {
      const Element& el = Cur.elements[p];
      Jk.middleRows<3>(3 * p) = (el.W - detail::crossCols(nd.r, el.A)).transpose();
    }
    Jk.middleRows<3>(3 * nd.element) = nd.J.transpose();
    out.columns[k] = 3 * (nd.element + 1);
    out.freeVelocity[k] = Pending.free[samples[k]].velocity;
  }
  out.Y = Pending.h * out.Jt;
  solvePending(out.Y);
  return Status::Ok();
}

void SuperHelix::solvePending(Eigen::MatrixXd& Y) const
{
  const int m = static_cast<int>(Q.size());
  if (m > detail::UnblockedLuMax)
  {
    Y = Pending.largeLu.solve(Y);
    return;
  }
  // The interchanges, then the two triangular solves (blocked).
  for (int c = 0; c < m; ++c)
    if (Pending.pivots[c] != c)
      Y.row(c).swap(Y.row(Pending.pivots[c]));
  Pending.lu.triangularView<Eigen::UnitLower>().solveInPlace(Y);
  Pending.lu.triangularView<Eigen::Upper>().solveInPlace(Y);
}

void SuperHelix::materialPoints(const std::vector<double>& s, bool free,
                                std::vector<StrandSample>& out) const
{
  // v(s) = el.v0 + ω0 × Fg + F0 ∂g/∂k q̇_e at the current q̇; the free step's adds J(s) δ,
  // δ = q̇_free − q̇ⁿ: Σ_{p<e} ((A_p δ_p) × r + W_p δ_p) + F0 ∂g/∂k δ_e.
  const bool withFree = free && Pending.active;
  out.resize(s.size());
  Eigen::Vector3d pa = Eigen::Vector3d::Zero(), pw = Eigen::Vector3d::Zero();
  int e = 0;
  HelixPoint hp;
  for (std::size_t k = 0; k < s.size(); ++k)
  {
    double u;
    const int at = locate(s[k], u);
    for (; e < at; ++e)
      if (withFree)
      {
        const Eigen::Vector3d d = Pending.qdot.segment<3>(3 * e) - Qdot.segment<3>(3 * e);
        pa += Cur.elements[e].A * d;
        pw += Cur.elements[e].W * d;
      }
    const Element& el = Cur.elements[at];
    const Eigen::Vector3d kd = Qdot.segment<3>(3 * at);
    helixPoint(Q.segment<3>(3 * at), kd, u, hp);
    const Eigen::Vector3d Fg = el.F0 * hp.g;
    StrandSample& o = out[k];
    o.element = at;
    o.s = s[k];
    o.weight = 0;
    o.position = el.r0 + Fg;
    o.velocity = el.v0 + el.omega0.cross(Fg) + el.F0 * (hp.dg * kd);
    if (withFree)
      o.velocity +=
          pa.cross(o.position) + pw + el.F0 * (hp.dg * (Pending.qdot.segment<3>(3 * at) - kd));
  }
}

Status SuperHelix::loadCompliance(const std::vector<std::array<double, 2>>& s,
                                  const std::vector<std::array<double, 2>>& weight,
                                  const std::vector<Eigen::Vector3d>& direction, Eigen::MatrixXd& D,
                                  Eigen::MatrixXd& Y) const
{
  if (!Pending.active)
    return Status::Error("strand '" + Spec.name +
                         "': loadCompliance() needs a step begun by beginStep().");
  const int count = static_cast<int>(s.size());
  if (static_cast<int>(weight.size()) != count || static_cast<int>(direction.size()) != count)
    return Status::Error("strand '" + Spec.name + "': loadCompliance() got " +
                         std::to_string(count) + " loads with " + std::to_string(weight.size()) +
                         " weights and " + std::to_string(direction.size()) + " directions.");
  for (int l = 0; l < count; ++l)
    for (int e = 0; e < 2; ++e)
      if (!(s[l][e] >= 0 && s[l][e] <= Length) || !std::isfinite(weight[l][e]) ||
          !direction[l].allFinite())
        return Status::Error("strand '" + Spec.name + "': load " + std::to_string(l) + " at s = " +
                             std::to_string(s[l][e]) + " m is not on the strand, or not finite.");
  // j_l = Σ_e w_e J(s_e)ᵀ d_l: for an element p before the point's element e,
  // J_p(s)ᵀ d = (W_p − [r]× A_p)ᵀ d = W_pᵀ d + A_pᵀ (r × d); its own element's block
  // (F0 ∂g/∂k)ᵀ d.
  const int m = static_cast<int>(Q.size());
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(m, count);
  HelixPoint hp;
  for (int l = 0; l < count; ++l)
    for (int e = 0; e < 2; ++e)
    {
      if (weight[l][e] == 0)
        continue;
      double u;
      const int at = locate(s[l][e], u);
      helixPoint(Q.segment<3>(3 * at), Qdot.segment<3>(3 * at), u, hp);
      const Element& own = Cur.elements[at];
      const Eigen::Vector3d r = own.r0 + own.F0 * hp.g;
      const Eigen::Vector3d d = weight[l][e] * direction[l];
      const Eigen::Vector3d rd = r.cross(d);
      for (int p = 0; p < at; ++p)
      {
        const Element& el = Cur.elements[p];
        J.col(l).segment<3>(3 * p) += el.W.transpose() * d + el.A.transpose() * rd;
      }
      J.col(l).segment<3>(3 * at) += (own.F0 * hp.dg).transpose() * d;
    }
  Y = Pending.h * J;
  solvePending(Y);
  D.noalias() = J.transpose() * Y;
  return Status::Ok();
}

Status SuperHelix::endStep(const std::vector<int>& samples,
                           const std::vector<Eigen::Vector3d>& forces,
                           const Eigen::VectorXd& response)
{
  if (!Pending.active)
    return Status::Error("strand '" + Spec.name +
                         "': endStep without beginStep; begin the coupled step first.");
  Pending.active = false;
  const bool none = samples.empty() && forces.empty() && response.size() == 0;
  // A strand without coupling forces takes the step its integrator asks for: with
  // Integrator::Midpoint the second-order one (itself semi-implicit where the strand touches
  // the body), with Integrator::Bdf2 BDF2; the semi-implicit step begun is what it would
  // commit otherwise. (Its pairs were searched along the semi-implicit step's motion; the
  // detection's margin covers the difference, docs/hair-hair-contacts.md.)
  if (none && Spec.integrator != Integrator::SemiImplicit)
    return singleStep(Pending.h);
  if (!none && (forces.size() != samples.size() || response.size() != Q.size()))
    return Status::Error(
        "strand '" + Spec.name + "': endStep got " + std::to_string(forces.size()) +
        " forces for " + std::to_string(samples.size()) + " coupling samples and " +
        std::to_string(response.size()) + " coordinates for " + std::to_string(Q.size()) + ".");
  for (size_t k = 0; k < samples.size(); ++k)
    if (!forces[k].allFinite() || samples[k] < 0 ||
        samples[k] >= static_cast<int>(Cur.nodes.size()))
      return Status::Error("strand '" + Spec.name +
                           "': a coupling force is not finite or not at a sample.");
  // The commit's energy flows read the contact response from the step workspace: the hook's,
  // plus the coupling forces per unit length at their samples.
  detail::StepWorkspace& ws = detail::stepWorkspace();
  if (Pending.contactsSet)
    ws.ContactBuffer = Pending.contacts;
  else
  {
    ws.ContactBuffer.assign(Cur.nodes.size(), ContactResponse());
    for (Node& nd : Cur.nodes) // without a hook the flags were not set by this step
      nd.hasF = nd.hasK = nd.hasD = nd.hasField = false;
  }
  for (size_t k = 0; k < forces.size(); ++k)
  {
    Node& nd = Cur.nodes[samples[k]];
    ws.ContactBuffer[samples[k]].force += forces[k] / nd.w;
    nd.hasF = nd.hasF || !forces[k].isZero(0);
  }
  ContactsSet = true; // attemptStep clears it when it ends
  LastSubsteps = 1;
  LastRejected = 0;
  LastFirstOrder = 1; // the semi-implicit step
  Outcome outcome = Outcome::Committed;
  const Eigen::VectorXd qd = none ? Pending.qdot : Eigen::VectorXd(Pending.qdot + response);
  return attemptStep(Pending.h, Scheme::SemiImplicit, std::numeric_limits<double>::infinity(),
                     outcome, &qd);
}

} // namespace hair
