#pragma once
// The one contact-response type of Core: what a contact (with the body, with other hair)
// gives a strand at the points where its forces act, linearized so that the step can treat
// the stiffness and damping implicitly.
#include <Eigen/Core>

#include <functional>
#include <vector>

namespace hair
{

/// A point of a strand where distributed forces act (a Super-Helix quadrature sample).
struct StrandSample
{
  int element = 0;
  double s = 0;      ///< arc length from the root [m]
  double weight = 0; ///< quadrature weight [m]: ∫ f ds ≈ Σ weight · f(sample)
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
};

/// The contact response at one sample, linearized about the sample's position x and
/// velocity v at the start of the step: force per unit length f [N/m] and its derivatives
/// K = −∂f/∂x [N/m²] and D = −∂f/∂v [N·s/m²]. The step treats K and D implicitly
/// (backward Euler on the linearization), so a stiff penalty keeps dt = 1/30 s stable; the
/// force that acts over the step, and whose work is reported, is
///   f − K (x⁽ⁿ⁺¹⁾ − xⁿ) − D (v⁽ⁿ⁺¹⁾ − vⁿ),  x⁽ⁿ⁺¹⁾ − xⁿ ≈ h v⁽ⁿ⁺¹⁾.
/// Leave K and D zero for an explicit force.
struct ContactResponse
{
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  Eigen::Matrix3d stiffness = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d damping = Eigen::Matrix3d::Zero();
  /// The far field of hair–hair interaction (contact/HairGrid), kept apart from the terms
  /// above: a drag `drag` [N·s/m²] towards the velocity of the hair around, `medium` [m/s],
  /// and a push `push` [N/m] with an isotropic stiffness `spring` [N/m²]. Over a step the
  /// force per unit length is
  ///   drag (medium − v⁽ⁿ⁺¹⁾) + push − spring (x⁽ⁿ⁺¹⁾ − xⁿ),
  /// implicit in drag and spring like `damping` and `stiffness`. Both are multiples of the
  /// identity, so a model whose mass matrix is ∫ ρS Jᵀ J ds can treat them at no cost (the
  /// Super-Helix scales its mass weights: docs/hair-hair-interaction.md), and their work is
  /// reported apart from the body's.
  double drag = 0;
  double spring = 0;
  Eigen::Vector3d medium = Eigen::Vector3d::Zero();
  Eigen::Vector3d push = Eigen::Vector3d::Zero();
  bool hasField() const { return drag != 0 || spring != 0 || !push.isZero(0); }
};

/// How the end-of-step velocities of some samples of a strand respond to point forces at
/// those samples, within one implicit step that has been solved without them (the strand's
/// own forces, body contacts included, are in it): with forces F_l [N] at the coupling
/// samples l, the strand's coordinate velocities change by Δ = Σ_l Y_l F_l and sample k's
/// velocity is v_k = freeVelocity_k + J_k Δ. Y_l = h A⁻¹ J_lᵀ for the step's matrix A, so
/// J_k Y_l is the compliance the step gives between the two samples. Filled by the strand
/// model (SuperHelix::compliance) for the contacts between strands to be solved together
/// (contact/HairHairContacts).
struct StrandCompliance
{
  std::vector<int> samples;                  ///< the coupling samples (indices), increasing
  std::vector<Eigen::Vector3d> freeVelocity; ///< [m/s], one per coupling sample
  std::vector<int> columns; ///< per coupling sample: its J_k is 0 past this many coordinates
  Eigen::MatrixXd Jt;       ///< the coordinates × 3 columns per coupling sample: J_kᵀ
  Eigen::MatrixXd Y;        ///< the coordinates × 3 columns per coupling sample: Y_k
  /// J_k Y_l for every pair of coupling samples (3 × 3 blocks), when it comes without Jt and
  /// Y (another process's strand); empty: a solver forms it from Jt and Y.
  Eigen::MatrixXd G;
};

/// Contact hook: given the samples at the start of a (sub-)step, write the response of each
/// sample (the vector arrives sized and zeroed). Called once per step (and sub-step) of the
/// strand, from the thread that steps it.
using ContactForces =
    std::function<void(int strandId, double time, const std::vector<StrandSample>& samples,
                       std::vector<ContactResponse>& response)>;

} // namespace hair
