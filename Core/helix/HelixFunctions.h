#pragma once
// Closed-form kinematics of one helical element (Super-Helices paper, appendix A) and its
// exact derivatives with respect to the element's (τ, κ1, κ2). Every coefficient is an
// even function of x = Ω u that is evaluated by its Taylor series near x = 0, so the
// straight and nearly straight cases are exact and smooth.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>

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

/// Below this x the coefficients are Taylor series; from it on, closed forms in sin x, cos x.
constexpr double HelixSeriesLimit = 1.5;

/// helixCoefficients(x) for x >= 0 whose s = sin x and c = cos x are known (e.g. from an
/// angle difference): the same closed forms. Below HelixSeriesLimit the series is used and
/// s, c are not read.
HelixCoefficients helixCoefficients(double x, double s, double c);

/// sin x and cos x in one call where the C library has one (glibc's sincos gives the same
/// values as sin and cos).
inline void sinCos(double x, double& s, double& c)
{
#if defined(__GLIBC__)
  ::sincos(x, &s, &c);
#else
  s = std::sin(x);
  c = std::cos(x);
#endif
}

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
/// Only HelixEnd's own fields (E, G, dGk), from the coefficients h = helixCoefficients(|k| u).
void helixEndRotation(const Eigen::Vector3d& k, const Eigen::Vector3d& kd, double u,
                      const HelixCoefficients& h, HelixEnd& out);

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

/// The element functions at u that helixPoint and helixBilinear are linear in, from the
/// coefficients c of Ω u: f = (u, u²φ1, u³φ2, u⁴ψ1, u⁵ψ2, u⁶χ1, u⁷χ2) (a, b, da, db of the
/// kernels below are f[1] … f[4]).
[[gnu::always_inline]] inline void helixFunctionValues(double u, const HelixCoefficients& c,
                                                       double (&f)[7])
{
  const double u2 = u * u, u3 = u2 * u, u4 = u2 * u2, u5 = u4 * u, u6 = u3 * u3, u7 = u6 * u;
  f[0] = u;
  f[1] = u2 * c.phi1;
  f[2] = u3 * c.phi2;
  f[3] = u4 * c.psi1;
  f[4] = u5 * c.psi2;
  f[5] = u6 * c.chi1;
  f[6] = u7 * c.chi2;
}

/// The frame's rotation and its integral at u as polynomials in K = [k]× (coefficients c of
/// Ω u): E(u) = e0 I + e1 K + e2 K² and G(u) = ∫0^u E = g0 I + g1 K + g2 K², with
/// e = (1, uφ0, u²φ1) and g = (u, u²φ1, u³φ2).
[[gnu::always_inline]] inline void helixFrameCoefficients(double u, const HelixCoefficients& c,
                                                          double (&e)[3], double (&g)[3])
{
  const double u2 = u * u;
  e[0] = 1;
  e[1] = u * c.phi0;
  e[2] = u2 * c.phi1;
  g[0] = u;
  g[1] = e[2];
  g[2] = u2 * u * c.phi2;
}

/// The parts of helixPoint that are linear in the element functions' values at u (with
/// x = Ω u: a = u²φ1(x), b = u³φ2(x), da = u⁴ψ1(x), db = u⁵ψ2(x)), in the element's start frame:
///   g = u e0 + a k×e0 + b k×(k×e0),
///   ∂g/∂k_i = k_i (da k×e0 + db k×(k×e0)) + a e_i×e0 + b (k0 e_i − 2 k_i e0 + δ_i0 k).
/// Called with other values they give the sums Σ c_f (coefficient of f), e.g. with Gram
/// matrix rows (SuperHelix's FunctionGram).
[[gnu::always_inline]] inline void helixGValues(const Eigen::Vector3d& k, double u, double a,
                                                double b, Eigen::Vector3d& g)
{
  const double k0 = k.x(), k1 = k.y(), k2 = k.z();
  // k × e0 = (0, k2, −k1); w = k × (k × e0) = k k0 − Ω² e0, with w0 = −(k1² + k2²) summed
  // directly (no cancellation when k is nearly along e0).
  g = Eigen::Vector3d(u - b * (k1 * k1 + k2 * k2), a * k2 + b * (k1 * k0), b * (k2 * k0) - a * k1);
}

[[gnu::always_inline]] inline void helixJacobianValues(const Eigen::Vector3d& k, double a, double b,
                                                       double da, double db, Eigen::Matrix3d& dg)
{
  const double k0 = k.x(), k1 = k.y(), k2 = k.z();
  const double w0 = -(k1 * k1 + k2 * k2), w1 = k1 * k0, w2 = k2 * k0;
  // (e0×e0 = 0, e1×e0 = −e2, e2×e0 = e1).
  const double z0 = db * w0, z1 = da * k2 + db * w1, z2 = db * w2 - da * k1;
  const double bk0 = b * k0, b2 = 2 * b;
  dg(0, 0) = k0 * z0;
  dg(1, 0) = k0 * z1 + b * k1;
  dg(2, 0) = k0 * z2 + b * k2;
  dg(0, 1) = k1 * z0 - b2 * k1;
  dg(1, 1) = k1 * z1 + bk0;
  dg(2, 1) = k1 * z2 - a;
  dg(0, 2) = k2 * z0 - b2 * k2;
  dg(1, 2) = k2 * z1 + a;
  dg(2, 2) = k2 * z2 + bk0;
}

/// helixPoint's g, ∂g/∂k and D²g[kd, kd] are linear in the element functions f =
/// helixFunctionValues(u, ·) with coefficients that are constant on the element:
///   g = Σ_{i<3} f_i g_i,  ∂g/∂k = Σ_{i=1..4} f_i dg_{i−1},  D²g[kd, kd] = Σ_{i=2..6} f_i
///   d2g_{i−2}.
/// Computed once per element, they turn a sample's reconstruction into a few sums instead
/// of helixPoint's kernels.
struct HelixBasis
{
  Eigen::Vector3d g[3];
  Eigen::Matrix3d dg[4];
  Eigen::Vector3d d2g[5];
};
void helixBasis(const Eigen::Vector3d& k, const Eigen::Vector3d& kd, HelixBasis& out);

/// helixBilinear's d2gW (columns D²g[kd, e_j]) is linear in the element functions f2 … f6
/// as well: F d2gW = Σ_{i=2..6} f_i out[i − 2] for any matrix F (the element's start frame),
/// with out formed here once per element from closed forms (outer products of F's columns
/// and of k, kd).
void helixBilinearBasis(const Eigen::Vector3d& k, const Eigen::Vector3d& kd,
                        const Eigen::Matrix3d& F, Eigen::Matrix3d (&out)[5]);

/// helixBilinear from the values at u of the functions it is linear in: c3 = u³φ2,
/// c1 = u⁴ψ1, c2 = u⁵ψ2, e6 = u⁶χ1, e7 = u⁷χ2 (φ, ψ, χ of Ω u); like helixJacobianValues,
/// other values give sums of the coefficient matrices.
[[gnu::always_inline]] inline void helixBilinearValues(const Eigen::Vector3d& k,
                                                       const Eigen::Vector3d& v, double c3,
                                                       double c1, double c2, double e6, double e7,
                                                       Eigen::Matrix3d& d2gW,
                                                       Eigen::Matrix3d* dGkW = nullptr)
{
  // Polarization of the quadratic forms in helixPoint / helixEnd, written out in scalars.
  const double k0 = k.x(), k1 = k.y(), k2 = k.z();
  const double v0 = v.x(), v1 = v.y(), v2 = v.z();
  // Partial sums over the other two components (k·v − k_i v_i, |k|² − k_i²).
  const double kv12 = k1 * v1 + k2 * v2, kk12 = k1 * k1 + k2 * k2;
  const double pv = k0 * v0 + kv12;
  // Column j of d2gW is D²g[v, e_j] (k·e_j = k_j, v·e_j = v_j):
  //   (u6 χ1 pv k_j + c1 v_j) k×e0 + c1 (pv e_j×e0 + k_j v×e0)
  //   + (u7 χ2 pv k_j + c2 v_j) wk + c2 (pv (k0 e_j + δ_j0 k − 2 k_j e0) + k_j t)
  //   + c3 (δ_j0 v + v0 e_j − 2 v_j e0),
  // with k×e0 = (0, k2, −k1), wk = k k0 − Ω² e0, v×e0 = (0, v2, −v1), t = v k0 + k v0 − 2 pv e0.
  // Collected: d2gW = α kᵀ + β vᵀ + (c2 pv k + c3 v) e0ᵀ + (c2 pv k0 + c3 v0) I
  //                   + c1 pv (e1 e2ᵀ − e2 e1ᵀ), with Q0 = u7 χ2 pv k0 + c2 v0, n = c2 k0,
  //   α = (u7 χ2 pv wk0 − 2 c2 (kv12 + pv), u6 χ1 pv k2 + c1 v2 + k1 Q0 + n v1,
  //        k2 Q0 + n v2 − u6 χ1 pv k1 − c1 v1),
  //   β = (c2 wk0 − 2 c3, c1 k2 + n k1, n k2 − c1 k1),
  // where wk0 = −(k1² + k2²) and v0 k0 − 2 pv = −(kv12 + pv).
  const double al = e6 * pv, be = e7 * pv;
  const double w0 = -kk12;
  const double Q0 = be * k0 + c2 * v0, n = c2 * k0;
  const double c2pv = c2 * pv, c1pv = c1 * pv;
  const double A0 = be * w0 - 2 * c2 * (kv12 + pv), B0 = c2 * w0 - 2 * c3;
  const double A1 = al * k2 + c1 * v2 + (k1 * Q0 + n * v1), B1 = c1 * k2 + n * k1;
  const double A2 = k2 * Q0 + n * v2 - (al * k1 + c1 * v1), B2 = n * k2 - c1 * k1;
  const double dI = c2pv * k0 + c3 * v0;
  d2gW(0, 0) = A0 * k0 + B0 * v0 + 2 * dI;
  d2gW(1, 0) = A1 * k0 + B1 * v0 + (c2pv * k1 + c3 * v1);
  d2gW(2, 0) = A2 * k0 + B2 * v0 + (c2pv * k2 + c3 * v2);
  d2gW(0, 1) = A0 * k1 + B0 * v1;
  d2gW(1, 1) = A1 * k1 + B1 * v1 + dI;
  d2gW(2, 1) = A2 * k1 + B2 * v1 - c1pv;
  d2gW(0, 2) = A0 * k2 + B0 * v2;
  d2gW(1, 2) = A1 * k2 + B1 * v2 + c1pv;
  d2gW(2, 2) = A2 * k2 + B2 * v2 + dI;
  if (!dGkW)
    return;
  // Column i of dGkW, w = e_i (K = [k]×, so k×e_i = K e_i, k×(k×e_i) = K² e_i):
  //   ½ (c1 (k_i k×v + pv K e_i) + c2 (k_i k×(k×v) + pv K² e_i) + c3 (e_i×(k×v) + v×(K e_i)))
  // = k_i q + z_i k + [s]× e_i off the diagonal, with q = ½ (c1 k×v + c2 k×(k×v)),
  //   z = ½ (c2 pv k + c3 v), s = ½ (c1 pv k − c3 k×v), since K² = k kᵀ − Ω² I,
  //   v×(k×e_i) = k v_i − (k·v) e_i and e_i×a = −[a]× e_i.
  // The diagonal's −Ω² and −(k·v) parts are summed over the other two components, as the
  // cross products give them (no cancellation when one component of k dominates).
  Eigen::Matrix3d& D = *dGkW;
  const double h1 = 0.5 * c1, h2 = 0.5 * c2, h3 = 0.5 * c3;
  const double x0 = k1 * v2 - k2 * v1, x1 = k2 * v0 - k0 * v2, x2 = k0 * v1 - k1 * v0; // k×v
  const double y0 = k1 * x2 - k2 * x1, y1 = k2 * x0 - k0 * x2, y2 = k0 * x1 - k1 * x0; // k×(k×v)
  const double q0 = h1 * x0 + h2 * y0, q1 = h1 * x1 + h2 * y1, q2 = h1 * x2 + h2 * y2;
  const double h2pv = h2 * pv, h1pv = h1 * pv;
  const double z0 = h2pv * k0 + h3 * v0, z1 = h2pv * k1 + h3 * v1, z2 = h2pv * k2 + h3 * v2;
  const double s0 = h1pv * k0 - h3 * x0, s1 = h1pv * k1 - h3 * x1, s2 = h1pv * k2 - h3 * x2;
  D(0, 0) = q0 * k0 - h2pv * kk12 - h3 * kv12;
  D(1, 1) = q1 * k1 - h2pv * (k2 * k2 + k0 * k0) - h3 * (v2 * k2 + v0 * k0);
  D(2, 2) = q2 * k2 - h2pv * (k0 * k0 + k1 * k1) - h3 * (v0 * k0 + v1 * k1);
  D(0, 1) = q0 * k1 + k0 * z1 - s2;
  D(1, 0) = q1 * k0 + k1 * z0 + s2;
  D(0, 2) = q0 * k2 + k0 * z2 + s1;
  D(2, 0) = q2 * k0 + k2 * z0 - s1;
  D(1, 2) = q1 * k2 + k1 * z2 - s0;
  D(2, 1) = q2 * k1 + k2 * z1 + s0;
}
} // namespace hair
