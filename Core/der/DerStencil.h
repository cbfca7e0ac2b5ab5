#pragma once
// The bending and twisting energy of one interior node of a Discrete Elastic Rod (Bergou,
// Wardetzky, Robinson, Audoly, Grinspun, "Discrete Elastic Rods", SIGGRAPH 2008), with the
// time-parallel reference frame of Bergou, Audoly, Vouga, Wardetzky, Grinspun, "Discrete
// Viscous Threads", SIGGRAPH 2010: a smooth function of the stencil's 11 unknowns
//   u = (x_{i−1}, θ_{i−1}, x_i, θ_i, x_{i+1})   [m, rad]
// given the reference frames at the start of the step, so that its gradient and Hessian
// include the frames' dependence on the positions. They are exact, by second-order forward
// automatic differentiation. The equations are in docs/discrete-elastic-rods.md.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace hair
{

using Vector11d = Eigen::Matrix<double, 11, 1>;
using Matrix11d = Eigen::Matrix<double, 11, 11>;

/// The space-parallel transport of d from the unit tangent a to the unit tangent b: the
/// rotation about a × b that takes a to b (the identity when a = b; undefined for b = −a).
Eigen::Vector3d parallelTransport(const Eigen::Vector3d& d, const Eigen::Vector3d& a,
                                  const Eigen::Vector3d& b);

/// What the energy of interior node i depends on besides its unknowns.
struct StencilData
{
  /// Unit tangents t_{i−1}, t_i and reference directors d1_{i−1}, d1_i (unit, ⟂ tangent) at
  /// the start of the step. Within the step the reference director of an edge is d1
  /// parallel-transported from its old tangent to its current one (time-parallel).
  Eigen::Vector3d tangentA = Eigen::Vector3d::UnitX(), tangentB = Eigen::Vector3d::UnitX();
  Eigen::Vector3d directorA = Eigen::Vector3d::UnitY(), directorB = Eigen::Vector3d::UnitY();
  /// The reference twist m_ref_i at the start of the step [rad], accumulated (not wrapped):
  /// the current one is taken on the branch nearest to it.
  double referenceTwist = 0;
  double restLength = 1; ///< l̄_i = (|ē_{i−1}| + |ē_i|)/2 [m]
  /// (m̄, κ̄1, κ̄2): the rest twist and material curvatures, integrated over l̄_i [rad].
  Eigen::Vector3d rest = Eigen::Vector3d::Zero();
  Eigen::Vector3d stiffness = Eigen::Vector3d::Zero(); ///< (GJ, EI1, EI2) [N·m²]
  /// (m, κ1, κ2) at the start of the step, and the weight γ/h [N·m²] of the viscous
  /// (Rayleigh) term ½ (γ/h) |strains − previous|² / l̄_i (0: none).
  Eigen::Vector3d previous = Eigen::Vector3d::Zero();
  double viscosity = 0;
};

/// The discrete strains of the stencil at u: (m_i, κ_i1, κ_i2) [rad], and the reference twist
/// m_ref_i (on the branch nearest StencilData::referenceTwist).
struct StencilStrains
{
  Eigen::Vector3d strains = Eigen::Vector3d::Zero();
  double referenceTwist = 0;
};
StencilStrains stencilStrains(const Vector11d& u, const StencilData& data);

/// The stencil's energy [J] in parts: bending ½ (κ − κ̄)ᵀ diag(EI1, EI2) (κ − κ̄)/l̄, twisting
/// ½ GJ (m − m̄)²/l̄, and the viscous term.
struct StencilEnergy
{
  double bending = 0, twisting = 0, viscous = 0;
  double total() const { return bending + twisting + viscous; }
};
StencilEnergy stencilEnergy(const Vector11d& u, const StencilData& data);

/// The total energy of stencilEnergy with its exact gradient [J/m, J/rad] and Hessian.
double stencilEnergy(const Vector11d& u, const StencilData& data, Vector11d& gradient,
                     Matrix11d& hessian);

} // namespace hair
