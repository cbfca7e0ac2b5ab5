#pragma once
// Hair–body contact for Super-Helix strands: penalty, normal damping and anisotropic,
// regularized Coulomb friction at the strand's quadrature samples against moving body parts
// (collision tables, Kurihara et al. 1993). The response is the force per unit length with
// its stiffness K = −∂f/∂x and damping D that SuperHelix::setContactForces expects; the
// step treats K and D implicitly. The equations and the defaults are in
// docs/superhelix-contacts.md.
#include "collision/PosedPart.h"
#include "common/Status.h"
#include "contact/ContactResponse.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <vector>

namespace hair
{

/// Contact parameters (SI units). Defaults and why: docs/superhelix-contacts.md.
struct BodyContactParameters
{
  bool enabled = true;
  /// k_n: normal force per unit length per metre of penetration [N/m²]. A resting strand
  /// of weight ρS g per unit length sinks by ρS g / k_n: 5 µm (wavy) to 10 µm (smooth).
  double stiffness = 10.0;
  /// ζ: normal damping as a fraction of the critical damping of one sample on the penalty
  /// spring, c_n = 2 ζ √(k_n ρS) [N·s/m²] (1: no bounce).
  double dampingRatio = 1.0;
  /// μ: Coulomb friction coefficient (averaged over the sliding directions).
  double friction = 0.3;
  /// μ_s: static friction coefficient; 0 (the default): none, the regularized Coulomb law
  /// alone, under which a strand held by friction creeps at ~ε. > 0 (at least μ): a sample
  /// that touches a part is anchored where it touched (in the part's own coordinates, so the
  /// anchor moves with it); while the tangential force that holds it there (a spring of the
  /// contact's stiffness and a damper of its damping, to the anchor) stays within μ_s λ it
  /// sticks, beyond that it slides under the kinetic law (μ, anisotropic) and its anchor
  /// trails it by the kinetic force's stretch. Needs the anchors' state: respond()'s
  /// `anchors`, kept by the model per strand and sample.
  double staticFriction = 0;
  /// a ∈ [0, 1): anisotropy of the friction (cuticle scales). μ_eff = μ (1 + a cos ψ),
  /// ψ the angle between the fibre's tangent (root → tip) and its sliding velocity relative
  /// to the body: tip-first sliding (the body rubbing the fibre tip → root, against the
  /// scales) has μ (1 + a), root-first μ (1 − a).
  double anisotropy = 0.2;
  /// A guide stands for a clump of hair: it touches at this distance from the surface [m].
  double thickness = 1e-3;
  /// ε: regularization speed of the Coulomb law [m/s]; below it, friction is viscous
  /// (μ λ / ε per unit speed) and a strand held by friction creeps at most at ~ε.
  double slipVelocity = 1e-3;
  /// The step size [s] (set it to the simulation's). The response is linearized at the start
  /// of a step, so a sample that is outside then gets no force during it however fast it
  /// comes in: a sample that would reach the clump's layer within `lookAhead` at its
  /// current normal speed is treated as in contact already (see docs/superhelix-contacts.md).
  double lookAhead = 1.0 / 30;

  /// Names the first parameter out of range, what is wrong and what to do.
  Status validate() const;
};

/// Checks a Coulomb friction law with the body (either model's): μ ≥ 0, μ_s 0 (none) or
/// ≥ μ, anisotropy in [0, 1); the message names the coefficient and what to give.
Status validateFriction(double friction, double staticFriction, double anisotropy);

/// Where a sample stuck to a part (static friction): its anchor in the part's rest
/// coordinates, or none.
struct BodyAnchor
{
  /// Steps in a row a sample may be drawn past the cone's edge while slower than the slip
  /// velocity before it slides (a transient of the load passes within them).
  static constexpr int MaxFlows = 3;
  bool set = false;
  Eigen::Vector3d rest = Eigen::Vector3d::Zero();
  int flows = 0;        ///< steps in a row its anchor was drawn after it
  bool sliding = false; ///< sliding (kinetic) until it slows below half the slip velocity
};

/// What one call found (for statistics; optional).
struct ContactSummary
{
  int samplesInContact = 0; ///< samples closer than `thickness` to a surface
  double deepest = 0;       ///< largest penetration into the table surface itself [m]
};

/// Stateless apart from its parameters and the parts' reach (culling): `respond` is const
/// and allocates nothing, so strands may be answered from several threads at once.
class BodyContacts
{
public:
  /// Validates the parameters; on error *this is unchanged.
  Status setParameters(const BodyContactParameters& parameters);
  const BodyContactParameters& parameters() const { return Parameters; }

  /// Adds to `response[i]` the contact response of sample i of one strand against every
  /// body in `bodies` (overlapping bodies, e.g. head and trunk at the neck, add up: the
  /// sum is continuous where a "deepest body" choice would jump). Samples
  /// must be in order of arc length (as SuperHelix::samples() gives them): the fibre
  /// tangent for the anisotropy is taken from the neighbouring samples. `linearDensity`
  /// is the strand's ρS [kg/m] (for the critical damping). `response` must have one entry
  /// per sample.
  /// With static friction on, `anchors` holds the strand's anchors, samples × bodyCount
  /// (sample i, body k at i · bodyCount + k; resized, and reset, when its size differs), read
  /// and updated here: a sample's anchor is set when it touches and cleared when it leaves.
  /// Null: kinetic friction alone.
  void respond(const std::vector<StrandSample>& samples, double linearDensity,
               const PosedPart* bodies, int bodyCount, std::vector<ContactResponse>& response,
               ContactSummary* summary = nullptr, std::vector<BodyAnchor>* anchors = nullptr) const;

  /// The response of one sample (exposed for tests): position x, velocity v, fibre tangent
  /// t (unit, root → tip) against one body. Returns false (and leaves `out` alone) when the
  /// sample is farther than `thickness` from the surface or the table does not cover it.
  /// `depth` receives the table's penetration (Q − P)·N (> 0 inside).
  /// `anchor`: the sample's anchor on this body (static friction), or null.
  bool respondOne(const Eigen::Vector3d& x, const Eigen::Vector3d& v, const Eigen::Vector3d& t,
                  double linearDensity, const PosedPart& body, ContactResponse& out, double& depth,
                  BodyAnchor* anchor = nullptr) const;

private:
  BodyContactParameters Parameters;
};

} // namespace hair
