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
  if (Status st = prepareStep(h, Time, false, qd, declined, solveFailed); !st)
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
  Eigen::Vector3d pa = Eigen::Vector3d::Zero(), pw = Eigen::Vector3d::Zero();
  for (int e = 0; e < elementCount(); ++e)
  {
    const Element& el = Cur.elements[e];
    const Eigen::Vector3d x = qd.segment<3>(3 * e);
    for (int j = el.first; j < el.first + el.count; ++j)
    {
      const Node& nd = Cur.nodes[j];
      out[j].velocity = nd.v0 + pa.cross(nd.r) + pw + nd.J * x;
    }
    pa += el.A * x;
    pw += el.W * x;
  }
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
  if (m > detail::UnblockedLuMax)
    out.Y = Pending.largeLu.solve(out.Y);
  else
  {
    // All columns at once: the interchanges, then the two triangular solves (blocked).
    for (int c = 0; c < m; ++c)
      if (Pending.pivots[c] != c)
        out.Y.row(c).swap(out.Y.row(Pending.pivots[c]));
    Pending.lu.triangularView<Eigen::UnitLower>().solveInPlace(out.Y);
    Pending.lu.triangularView<Eigen::Upper>().solveInPlace(out.Y);
  }
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
  // the body); the semi-implicit step begun is what it would commit otherwise. (Its pairs were
  // searched along the semi-implicit step's motion; the detection's margin covers the
  // difference, docs/hair-hair-contacts.md.)
  if (none && Spec.integrator == Integrator::Midpoint)
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
      nd.hasF = nd.hasK = nd.hasD = false;
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
  return attemptStep(Pending.h, false, std::numeric_limits<double>::infinity(), outcome, &qd);
}

} // namespace hair
