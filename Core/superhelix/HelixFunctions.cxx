#include "superhelix/HelixFunctions.h"

#include <cmath>
#include <cstring>

namespace hair
{

namespace
{
// Below this |x| the series is used; above it the closed forms lose at most ~1e-13 to
// cancellation.
constexpr double SeriesLimit = 1.5;

// Taylor coefficients in y = x² of the seven functions, in the order of HelixCoefficients;
// row m holds the coefficients of y^m, lane 7 is zero padding so that a row is four SSE2
// pairs and the seven Horner recurrences run as one vectorized loop.
constexpr int MaxTerms = 11;
constexpr int Lanes = 8;

struct SeriesTable
{
  alignas(64) double c[MaxTerms][Lanes];
};

constexpr double factorial(int n)
{
  double f = 1;
  for (int i = 2; i <= n; ++i)
    f *= i;
  return f;
}

constexpr SeriesTable makeTable()
{
  SeriesTable t{};
  for (int m = 0; m < MaxTerms; ++m)
  {
    const double sg = (m % 2 == 0) ? 1.0 : -1.0;
    t.c[m][0] = sg / factorial(2 * m + 1);                             // phi0
    t.c[m][1] = sg / factorial(2 * m + 2);                             // phi1
    t.c[m][2] = sg / factorial(2 * m + 3);                             // phi2
    t.c[m][3] = -sg * (2 * m + 2) / factorial(2 * m + 4);              // psi1
    t.c[m][4] = -sg * (2 * m + 2) / factorial(2 * m + 5);              // psi2
    t.c[m][5] = sg * (2 * m + 4) * (2 * m + 2) / factorial(2 * m + 6); // chi1
    t.c[m][6] = sg * (2 * m + 4) * (2 * m + 2) / factorial(2 * m + 7); // chi2
    t.c[m][7] = 0;
  }
  return t;
}

constexpr SeriesTable Table = makeTable();

// The first N terms of the seven series, by Horner's rule in y, all seven at once (Eigen's
// packets: four SSE2 pairs per step instead of seven scalar chains).
using SeriesRow = Eigen::Array<double, Lanes, 1>;
static_assert(sizeof(HelixCoefficients) == 7 * sizeof(double), "HelixCoefficients layout");

template <int N>
inline HelixCoefficients series(double y)
{
  static_assert(N >= 1 && N <= MaxTerms, "series length");
  using Row = Eigen::Map<const SeriesRow, Eigen::Aligned16>;
  SeriesRow r = Row(Table.c[N - 1]);
  for (int m = N - 2; m >= 0; --m)
    r = r * y + Row(Table.c[m]);
  HelixCoefficients h;
  std::memcpy(&h, r.data(), sizeof h);
  return h;
}

// helixCoefficients, forced inline into helixPoint and helixBilinear (GCC does not inline it
// by itself, and the call spilled their registers around it: ~14 instructions per call).
[[gnu::always_inline]] inline HelixCoefficients coefficients(double x)
{
  x = std::abs(x);
  if (x < SeriesLimit)
  {
    // Every series alternates with terms decreasing in magnitude for y = x² < 2.25, so the
    // truncation error is below the first omitted term. Relative to the function's value
    // (the seven functions have no zero for x < 1.5), the worst of the seven first omitted
    // terms is, for N terms: x < 0.5, N = 8: 4.5e-20; x < 1, N = 10: 2.3e-20;
    // x < 1.5, N = 11: 4.4e-19 — all below 1/200 of the double precision's 1.1e-16, so each
    // band gives the full series to round-off (and the switches between bands jump by
    // round-off only). One term fewer would leave up to 4.9e-17, 9.8e-18 and 9.8e-17.
    const double y = x * x;
    if (x < 0.5)
      return series<8>(y);
    if (x < 1.0)
      return series<10>(y);
    return series<11>(y);
  }
  double s, c;
#if defined(__GLIBC__)
  ::sincos(x, &s, &c); // one call for both; glibc's sin and cos give the same values
#else
  s = std::sin(x);
  c = std::cos(x);
#endif
  // (One reciprocal and multiplications instead of the seven divisions: no fewer
  // instructions, no measurable time next to sincos, and ~1 ulp less accurate.)
  const double x2 = x * x, x3 = x2 * x, x4 = x2 * x2;
  HelixCoefficients h;
  h.phi0 = s / x;
  h.phi1 = (1 - c) / x2;
  h.phi2 = (x - s) / x3;
  h.psi1 = (x * s - 2 + 2 * c) / x4;
  h.psi2 = (3 * s - 2 * x - x * c) / (x4 * x);
  h.chi1 = (x2 * c - 5 * x * s + 8 - 8 * c) / (x4 * x2);
  h.chi2 = (8 * x + 7 * x * c + x2 * s - 15 * s) / (x4 * x3);
  return h;
}
} // namespace

HelixCoefficients helixCoefficients(double x)
{
  return coefficients(x);
}

void helixPoint(const Eigen::Vector3d& k, const Eigen::Vector3d& kd, double u, HelixPoint& out,
                HelixCoefficients* coefficients)
{
  // Written out in scalars, sharing the products (Eigen's 3-vector expressions did not).
  const double k0 = k.x(), k1 = k.y(), k2 = k.z();
  const double v0 = kd.x(), v1 = kd.y(), v2 = kd.z();
  const double om2 = k.squaredNorm();
  const HelixCoefficients h = hair::coefficients(std::sqrt(om2) * u);
  if (coefficients)
    *coefficients = h;
  const double u2 = u * u, u3 = u2 * u, u4 = u2 * u2, u5 = u4 * u, u6 = u3 * u3, u7 = u6 * u;
  const double a = u2 * h.phi1, b = u3 * h.phi2;
  const double da = u4 * h.psi1, db = u5 * h.psi2; // (da/dΩ)/Ω, (db/dΩ)/Ω
  // k × e0 = (0, k2, −k1); w = k × (k × e0) = k k0 − Ω² e0, with w0 = −(k1² + k2²) summed
  // directly (no cancellation when k is nearly along e0).
  const double w0 = -(k1 * k1 + k2 * k2), w1 = k1 * k0, w2 = k2 * k0;
  // g = u e0 + a k×e0 + b w.
  out.g = Eigen::Vector3d(u + b * w0, a * k2 + b * w1, b * w2 - a * k1);
  // ∂g/∂k_i = k_i (da k×e0 + db w) + a e_i×e0 + b (k0 e_i − 2 k_i e0 + δ_i0 k)
  // (e0×e0 = 0, e1×e0 = −e2, e2×e0 = e1).
  const double z0 = db * w0, z1 = da * k2 + db * w1, z2 = db * w2 - da * k1;
  const double bk0 = b * k0, b2 = 2 * b;
  Eigen::Matrix3d& dg = out.dg;
  dg(0, 0) = k0 * z0;
  dg(1, 0) = k0 * z1 + b * k1;
  dg(2, 0) = k0 * z2 + b * k2;
  dg(0, 1) = k1 * z0 - b2 * k1;
  dg(1, 1) = k1 * z1 + bk0;
  dg(2, 1) = k1 * z2 - a;
  dg(0, 2) = k2 * z0 - b2 * k2;
  dg(1, 2) = k2 * z1 + a;
  dg(2, 2) = k2 * z2 + bk0;
  // Second derivative along v = kd, with p = k·v:
  //   D²g[v, v] = dda k×e0 + 2 da p v×e0 + ddb w + 2 db p (v k0 + k v0 − 2 p e0)
  //               + b (2 v0 v − 2 |v|² e0),
  // dda = u⁶ χ1 p² + da |v|², ddb = u⁷ χ2 p² + db |v|². Components 1, 2 grouped as
  //   k_i (ddb k0 + 2 db p v0) + v_i (2 db p k0 + 2 b v0) + (dda k×e0 + 2 da p v×e0)_i,
  // component 0 with v0 k0 − p = −(k1 v1 + k2 v2) and v0² − |v|² = −(v1² + v2²).
  const double kv12 = k1 * v1 + k2 * v2, vv12 = v1 * v1 + v2 * v2;
  const double p = k0 * v0 + kv12, vv = v0 * v0 + vv12;
  const double dda = u6 * h.chi1 * p * p + da * vv;
  const double ddb = u7 * h.chi2 * p * p + db * vv;
  const double da2 = 2 * (da * p), db2 = 2 * (db * p);
  const double m1 = ddb * k0 + db2 * v0, m2 = db2 * k0 + b2 * v0;
  out.d2g = Eigen::Vector3d(ddb * w0 - 2 * (db2 * kv12 + b * vv12),
                            k1 * m1 + v1 * m2 + (dda * k2 + da2 * v2),
                            k2 * m1 + v2 * m2 - (dda * k1 + da2 * v1));
}

void helixEnd(const Eigen::Vector3d& k, const Eigen::Vector3d& kd, double u, HelixEnd& out)
{
  HelixCoefficients h;
  helixPoint(k, kd, u, out, &h);
  const double k0 = k.x(), k1 = k.y(), k2 = k.z();
  const double u2 = u * u, u3 = u2 * u;
  // E = I + A K + B K², G = u I + B K + C K², with K = [k]×, K² = k kᵀ − Ω² I (its diagonal
  // −Ω² + k_i² summed over the other two components).
  const double A = u * h.phi0, B = u2 * h.phi1, C = u3 * h.phi2;
  const double s0 = k0 * k0, s1 = k1 * k1, s2 = k2 * k2;
  const double q00 = -(s1 + s2), q11 = -(s2 + s0), q22 = -(s0 + s1);
  const double q01 = k0 * k1, q02 = k0 * k2, q12 = k1 * k2;
  Eigen::Matrix3d& E = out.E;
  E(0, 0) = 1 + B * q00;
  E(1, 1) = 1 + B * q11;
  E(2, 2) = 1 + B * q22;
  E(0, 1) = B * q01 - A * k2;
  E(1, 0) = B * q01 + A * k2;
  E(0, 2) = B * q02 + A * k1;
  E(2, 0) = B * q02 - A * k1;
  E(1, 2) = B * q12 - A * k0;
  E(2, 1) = B * q12 + A * k0;
  Eigen::Matrix3d& G = out.G;
  G(0, 0) = u + C * q00;
  G(1, 1) = u + C * q11;
  G(2, 2) = u + C * q22;
  G(0, 1) = C * q01 - B * k2;
  G(1, 0) = C * q01 + B * k2;
  G(0, 2) = C * q02 + B * k1;
  G(2, 0) = C * q02 - B * k1;
  G(1, 2) = C * q12 - B * k0;
  G(2, 1) = C * q12 + B * k0;
  // D(G v)[v] = da p (k × v) + db p k × (k × v) + b v × (k × v), with v = kd, b = C,
  //           = da p (k × v) + (db p k + b v) × (k × v).
  const double p = k.dot(kd);
  const double c1 = u2 * u2 * h.psi1 * p, c2 = u3 * u2 * h.psi2 * p;
  const Eigen::Vector3d kxv = k.cross(kd);
  out.dGk = c1 * kxv + (c2 * k + C * kd).cross(kxv);
}

} // namespace hair

namespace hair
{
void helixBilinear(const Eigen::Vector3d& k, const Eigen::Vector3d& v, double u,
                   Eigen::Matrix3d& d2gW, Eigen::Matrix3d* dGkW,
                   const HelixCoefficients* coefficients)
{
  // Polarization of the quadratic forms in helixPoint / helixEnd, written out in scalars.
  const double k0 = k.x(), k1 = k.y(), k2 = k.z();
  const double v0 = v.x(), v1 = v.y(), v2 = v.z();
  const HelixCoefficients h =
      coefficients ? *coefficients : hair::coefficients(std::sqrt(k.squaredNorm()) * u);
  const double u2 = u * u, u3 = u2 * u, u4 = u2 * u2, u5 = u4 * u, u6 = u3 * u3, u7 = u6 * u;
  // Partial sums over the other two components (k·v − k_i v_i, |k|² − k_i²).
  const double kv12 = k1 * v1 + k2 * v2, kk12 = k1 * k1 + k2 * k2;
  const double pv = k0 * v0 + kv12;
  const double c1 = u4 * h.psi1, c2 = u5 * h.psi2, c3 = u3 * h.phi2;
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
  const double al = u6 * h.chi1 * pv, be = u7 * h.chi2 * pv;
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
