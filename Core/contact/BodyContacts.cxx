#include "contact/BodyContacts.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace hair
{

namespace
{
Status bad(const char* name, double value, const char* want)
{
  std::ostringstream s;
  s << "the contact " << name << " is " << value << "; " << want << ".";
  return Status::Error(s.str());
}
/// The stick–slip law of static friction. A sample at world position `x`, tangential
/// velocity `ut` relative to `body`, anchored by `anchor` (set here on first touch), is held
/// by a tangential spring of stiffness `k` towards its anchor; `tangential` is I − n nᵀ,
/// `limit` μ_s λ, `kinetic` μ λ. Returns true when it sticks: `stretch` is then the
/// tangential offset x − anchor the spring acts on (drawn back to the cone's edge when the
/// anchor flows after a transient). False: it slides under the kinetic law, its anchor moved
/// to trail it at the stretch where the spring pulls with `kinetic`.
bool stickOrSlide(BodyAnchor& anchor, const PosedPart& body, const Eigen::Vector3d& x,
                  const Eigen::Vector3d& ut, const Eigen::Matrix3d& tangential, double k,
                  double limit, double kinetic, double slipVelocity, Eigen::Vector3d& stretch)
{
  if (!anchor.set)
  {
    // A new touch: anchored where it touched, sticking (whatever the last touch left).
    anchor = BodyAnchor();
    anchor.set = true;
    anchor.rest = body.toRest(x);
  }
  // The sample sticks while the spring's stretch alone stays within the cone (the damper's
  // share would let a suddenly loaded contact break away on its transient); the caller keeps
  // the force, damper included, within μ_s λ.
  stretch = tangential * (x - body.pose * anchor.rest);
  const double speed = ut.norm();
  double sn = stretch.norm();
  // A sliding sample slides on (kinetic) until it slows below half the slip velocity.
  const bool slides = anchor.sliding && speed >= 0.5 * slipVelocity;
  anchor.sliding = slides;
  if (!slides)
  {
    if (k * sn > limit && speed < slipVelocity && anchor.flows < BodyAnchor::MaxFlows)
    {
      // Stretched past the cone while hardly moving (a transient of the load, the rod's own
      // vibration): the anchor is drawn after the sample to the cone's edge and the contact
      // holds from there. A load that has passed leaves the sample stuck at its new anchor;
      // one that stays beyond μ_s λ draws it on step after step, and after MaxFlows steps
      // the sample slides (held by the spring, it would creep at (load − μ_s λ)/(k h)
      // instead; yielding at once, a 3 % transient at 90 % of the cone unzipped a strand).
      stretch *= limit / (k * sn);
      sn = limit / k;
      anchor.rest = body.toRest(x - stretch);
      ++anchor.flows;
    }
    else if (k * sn <= limit)
    {
      anchor.flows = 0;
    }
    if (k * sn <= limit * (1 + 1e-9))
    {
      return true;
    }
  }
  anchor.flows = 0;
  anchor.sliding = true;
  // Sliding: the anchor trails the sample by the stretch at which the spring would pull
  // with the kinetic force, so that a slowing sample is caught without a jump.
  const Eigen::Vector3d away =
      sn > 0 ? Eigen::Vector3d(stretch / sn)
             : Eigen::Vector3d(speed > 0 ? Eigen::Vector3d(ut / speed) : Eigen::Vector3d::Zero());
  anchor.rest = body.toRest(x - (kinetic / k) * away);
  return false;
}

} // namespace

Status validateFriction(double friction, double staticFriction, double anisotropy)
{
  if (!std::isfinite(friction) || friction < 0)
  {
    return bad("friction coefficient", friction,
               "give a finite value >= 0 (0: frictionless; hair on skin or hair is a few "
               "tenths, default 0.3)");
  }
  if (!std::isfinite(staticFriction) || staticFriction < 0 ||
      (staticFriction > 0 && staticFriction < friction))
  {
    return bad("static friction coefficient", staticFriction,
               "give 0 (no sticking) or a finite value at least the kinetic coefficient (a "
               "contact that holds needs at least the force that keeps it sliding)");
  }
  if (!std::isfinite(anisotropy) || anisotropy < 0 || anisotropy >= 1)
  {
    return bad("friction anisotropy", anisotropy,
               "give a value in [0, 1): the friction against the scales is μ (1 + a), with "
               "them μ (1 − a) (default 0.2)");
  }
  return Status::Ok();
}

Status BodyContactParameters::validate() const
{
  if (!std::isfinite(stiffness) || !(stiffness > 0))
  {
    return bad("stiffness", stiffness,
               "give a positive finite value in N/m² (default 10: a resting strand sinks "
               "by ρS g / k ≈ 5–10 µm)");
  }
  if (!std::isfinite(dampingRatio) || dampingRatio < 0)
  {
    return bad("damping ratio", dampingRatio,
               "give a finite value >= 0 (a fraction of the critical damping; default 1)");
  }
  if (Status s = validateFriction(friction, staticFriction, anisotropy); !s)
  {
    return s;
  }
  if (!std::isfinite(thickness) || thickness < 0)
  {
    return bad("thickness", thickness,
               "give a distance >= 0 in metres (default 1e-3: a guide stands for a clump)");
  }
  if (!std::isfinite(lookAhead) || lookAhead < 0)
  {
    return bad("look-ahead time", lookAhead,
               "give a time >= 0 in seconds, normally the simulation's time step");
  }
  if (!std::isfinite(slipVelocity) || !(slipVelocity > 0))
  {
    return bad("slip velocity", slipVelocity,
               "give a positive speed in m/s (the regularization of Coulomb friction; "
               "default 1e-3)");
  }
  return Status::Ok();
}

Status BodyContacts::setParameters(const BodyContactParameters& parameters)
{
  if (Status s = parameters.validate(); !s)
  {
    return s;
  }
  Parameters = parameters;
  return Status::Ok();
}

bool BodyContacts::respondOne(const Eigen::Vector3d& x, const Eigen::Vector3d& v,
                              const Eigen::Vector3d& t, double linearDensity, const PosedPart& body,
                              ContactResponse& out, double& depth, BodyAnchor* anchor) const
{
  const BodyContactParameters& p = Parameters;
  depth = 0;
  if (!body.table)
  {
    return false;
  }
  // The table's query at the part's rest coordinates; the normal back to world ones.
  const TableQuery q = body.table->query(body.toRest(x));
  if (!q.covered)
  {
    return false;
  }
  // The table's inside test is authoritative; the depth along N follows it in sign (where
  // the interpolated normal disagrees with the inside test near an edge of the table).
  depth = q.inside ? std::max(q.depth, 0.0) : std::min(q.depth, 0.0);
  const double d = depth + p.thickness; // penetration of the clump's outer layer
  const Eigen::Vector3d n = body.pose.linear() * q.normal;
  const Eigen::Vector3d vb = body.velocityAt(x); // the surface's
  const Eigen::Vector3d u = v - vb;              // relative
  const double un = n.dot(u);
  // The normal force per unit length λ n, never pulling (λ > 0: a sample leaving fast is let
  // go), continuous in the sample's state so that a step converges at its order through
  // contact (docs/superhelix-contacts.md). The surface moves too: over the look-ahead h it
  // advances by h (v_b·n) into the strand, d̃ = d + h n·v_b.
  //  - In the layer (d̃ > 0): penalty and damping, λ = k d̃ − c u_n.
  //  - Arriving (d̃ ≤ 0, reaching the layer within h at the approach speed u_n < 0): the
  //    damping, ramped from nothing where the sample is h |u_n| away to all of it at the
  //    layer, λ = (c/h) d̃ − c u_n = c (d̃ − h u_n)/h, implicit, which stops the approach
  //    (c h / ρS = 2 ζ h √(k/ρS) ≫ 1). Its stiffness c/h is 2ζ/(h √(k/ρS)) of k: 6 % at the
  //    defaults.
  // Both give −c u_n at d̃ = 0 and the arriving force is 0 at its edge. K carries the −n·Δx
  // part of the penetration at the end of the step.
  const double k = p.stiffness;
  const double c = 2 * p.dampingRatio * std::sqrt(k * linearDensity);
  const double dm = d + p.lookAhead * n.dot(vb);
  double lambda = 0, normalStiffness = 0;
  if (dm > 0)
  {
    lambda = k * dm - c * un;
    normalStiffness = k;
  }
  else if (p.lookAhead > 0 && un < 0 && dm - p.lookAhead * un > 0)
  {
    lambda = (c / p.lookAhead) * dm - c * un;
    normalStiffness = c / p.lookAhead;
  }
  if (!(lambda > 0))
  {
    return false;
  }
  const Eigen::Matrix3d nn = n * n.transpose();
  out.force += lambda * n;
  out.stiffness += normalStiffness * nn;
  out.damping += c * nn;

  // Friction: regularized Coulomb, f_t = −μ (1 + a t·u_t / s) λ u_t / s, s = √(|u_t|² + ε²),
  // with whatever normal force the sample has (arriving ones too: friction then grows with
  // it from nothing).
  // Its linearization is the secant η P (η = μ_eff λ / s, P = I − n nᵀ): with it, the force
  // over the step is −η u_tⁿ⁺¹, which opposes the new sliding velocity and cannot reverse
  // it (the tangent would overshoot stick by up to h μ g per step at dt = 1/30 s).
  const Eigen::Vector3d ut = u - un * n;
  const Eigen::Matrix3d tangential = Eigen::Matrix3d::Identity() - nn;
  // Static friction: stick to the anchor by a spring–damper in the tangent plane (implicit,
  // as the normal penalty: its stiffness k and damping c).
  if (anchor && p.staticFriction > 0)
  {
    Eigen::Vector3d stretch;
    const double limit = p.staticFriction * lambda;
    if (stickOrSlide(*anchor, body, x, ut, tangential, k, limit, p.friction * lambda,
                     p.slipVelocity, stretch))
    {
      const Eigen::Vector3d hold = -k * stretch - c * ut;
      const double h = hold.norm();
      const double scale = h > limit ? limit / h : 1.0;
      out.force += scale * hold;
      out.stiffness += scale * k * tangential;
      out.damping += scale * c * tangential;
      return true;
    }
  }
  if (p.friction > 0)
  {
    const double s = std::sqrt(ut.squaredNorm() + p.slipVelocity * p.slipVelocity);
    const double g = 1 + p.anisotropy * t.dot(ut) / s;
    const double eta = p.friction * g * lambda / s;
    out.force -= eta * ut;
    out.damping += eta * tangential;
  }
  return true;
}

void BodyContacts::respond(const std::vector<StrandSample>& samples, double linearDensity,
                           const PosedPart* bodies, int bodyCount,
                           std::vector<ContactResponse>& response, ContactSummary* summary,
                           std::vector<BodyAnchor>* anchors) const
{
  if (!Parameters.enabled || bodyCount <= 0)
  {
    return;
  }
  const std::size_t n = std::min(samples.size(), response.size());
  const bool sticking = anchors && Parameters.staticFriction > 0;
  if (sticking && anchors->size() != samples.size() * std::size_t(bodyCount))
  {
    anchors->assign(samples.size() * std::size_t(bodyCount), BodyAnchor());
  }
  for (std::size_t i = 0; i < n; ++i)
  {
    // Fibre tangent (root → tip) from the neighbouring samples: central where there are two.
    const std::size_t a = i > 0 ? i - 1 : i, b = i + 1 < samples.size() ? i + 1 : i;
    Eigen::Vector3d t = samples[b].position - samples[a].position;
    const double tn = t.norm();
    t = tn > 0 ? Eigen::Vector3d(t / tn) : Eigen::Vector3d::Zero();
    bool touching = false;
    for (int k = 0; k < bodyCount; ++k)
    {
      double depth = 0;
      ContactResponse r;
      BodyAnchor* anchor = sticking ? &(*anchors)[i * std::size_t(bodyCount) + k] : nullptr;
      const bool touches = respondOne(samples[i].position, samples[i].velocity, t, linearDensity,
                                      bodies[k], r, depth, anchor);
      if (anchor && !touches)
      {
        anchor->set = false; // left the part: a new touch anchors anew, sticking (stickOrSlide)
      }
      if (touches)
      {
        touching = true;
        response[i].force += r.force;
        response[i].stiffness += r.stiffness;
        response[i].damping += r.damping;
      }
      if (summary)
      {
        summary->deepest = std::max(summary->deepest, depth);
      }
    }
    if (summary && touching)
    {
      ++summary->samplesInContact;
    }
  }
}

} // namespace hair
