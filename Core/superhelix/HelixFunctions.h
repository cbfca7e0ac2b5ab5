#pragma once
// Closed-form kinematics of one helical element (Super-Helices paper, appendix A) and its
// exact derivatives with respect to the element's (τ, κ1, κ2). Every coefficient is an
// even function of x = Ω u that is evaluated by its Taylor series near x = 0, so the
// straight and nearly straight cases are exact and smooth.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace hair
{

/// With x = Ω u:
///   phi0 = sin x / x, phi1 = (1 − cos x)/x², phi2 = (x − sin x)/x³,
///   psi_i = phi_i'(x)/x, chi_i = psi_i'(x)/x.
struct HelixCoefficients
{
  double phi0, phi1, phi2, psi1, psi2, chi1, chi2;
};

HelixCoefficients helixCoefficients(double x);

/// A point at distance u from the start of an element of curvature k (in the element's
/// start frame), moving with curvature rate kd (k̈ = 0).
struct HelixPoint
{
  Eigen::Vector3d g;   ///< G(u) e0: position relative to the element's start
  Eigen::Matrix3d dg;  ///< ∂g/∂k (column i: derivative with respect to k_i)
  Eigen::Vector3d d2g; ///< D²g[kd, kd]
};

/// HelixPoint plus what the end of an element passes on to the next one.
struct HelixEnd : HelixPoint
{
  Eigen::Matrix3d E;   ///< exp(u [k]×): the frame rotation over the element
  Eigen::Matrix3d G;   ///< ∫0^u E: columns integrate n0, n1, n2
  Eigen::Vector3d dGk; ///< D(G kd)[kd]: the k̇-dependent part of the angular acceleration
};

/// `coefficients`, when given, receives helixCoefficients(|k| u) for reuse.
void helixPoint(const Eigen::Vector3d& k, const Eigen::Vector3d& kd, double u, HelixPoint& out,
                HelixCoefficients* coefficients = nullptr);
void helixEnd(const Eigen::Vector3d& k, const Eigen::Vector3d& kd, double u, HelixEnd& out);

inline Eigen::Matrix3d skew(const Eigen::Vector3d& v)
{
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

} // namespace hair

namespace hair
{
/// Symmetric bilinear forms behind HelixPoint::d2g and HelixEnd::dGk, with w = e0, e1, e2:
/// column i of d2gW is D²g[kd, e_i], column i of dGkW is ½ ∂/∂kd_i of D(G kd)[kd], so that
/// the derivative of d2g (and dGk) with respect to kd is 2 d2gW (and 2 dGkW).
/// `coefficients`: helixCoefficients(|k| u) if already known, else null.
void helixBilinear(const Eigen::Vector3d& k, const Eigen::Vector3d& kd, double u,
                   Eigen::Matrix3d& d2gW, Eigen::Matrix3d* dGkW,
                   const HelixCoefficients* coefficients = nullptr);
} // namespace hair
