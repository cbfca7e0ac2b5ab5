#include "helix/HelixFunctions.h"

#include <cmath>
#include <cstring>

namespace hair
{

namespace
{
// Below HelixSeriesLimit (1.5) the series is used; above it the closed forms lose at most
// ~1e-13 to cancellation.

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

// The closed forms for x >= HelixSeriesLimit from s = sin x and c = cos x.
[[gnu::always_inline]] inline HelixCoefficients closedForm(double x, double s, double c)
{
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

// helixCoefficients, forced inline into helixPoint and helixBilinear (GCC does not inline it
// by itself, and the call spilled their registers around it: ~14 instructions per call).
[[gnu::always_inline]] inline HelixCoefficients coefficients(double x)
{
  x = std::abs(x);
  if (x < HelixSeriesLimit)
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
  sinCos(x, s, c);
  return closedForm(x, s, c);
}
} // namespace

HelixCoefficients helixCoefficients(double x)
{
  return coefficients(x);
}

HelixCoefficients helixCoefficients(double x, double s, double c)
{
  if (x < HelixSeriesLimit)
    return coefficients(x);
  return closedForm(x, s, c);
}

void helixPoint(const Eigen::Vector3d& k, const Eigen::Vector3d& kd, double u, HelixPoint& out,
                HelixCoefficients* coefficients)
{
  // Written out in scalars, sharing the products (Eigen's 3-vector expressions do not).
  const double k0 = k.x(), k1 = k.y(), k2 = k.z();
  const double v0 = kd.x(), v1 = kd.y(), v2 = kd.z();
  const double om2 = k.squaredNorm();
  const HelixCoefficients h = hair::coefficients(std::sqrt(om2) * u);
  if (coefficients)
    *coefficients = h;
  // helixFunctionValues' list, written out: through the array it cost +0.2 % (smooth) to
  // +0.4 % (fuzzy) of a step's instructions here (callgrind), for the same values.
  const double u2 = u * u, u3 = u2 * u, u4 = u2 * u2, u5 = u4 * u, u6 = u3 * u3, u7 = u6 * u;
  const double a = u2 * h.phi1, b = u3 * h.phi2;
  const double da = u4 * h.psi1, db = u5 * h.psi2; // (da/dΩ)/Ω, (db/dΩ)/Ω
  helixGValues(k, u, a, b, out.g);
  helixJacobianValues(k, a, b, da, db, out.dg);
  const double w0 = -(k1 * k1 + k2 * k2);
  const double b2 = 2 * b;
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

void helixBasis(const Eigen::Vector3d& k, const Eigen::Vector3d& kd, HelixBasis& out)
{
  helixGValues(k, 1, 0, 0, out.g[0]);
  helixGValues(k, 0, 1, 0, out.g[1]);
  helixGValues(k, 0, 0, 1, out.g[2]);
  helixJacobianValues(k, 1, 0, 0, 0, out.dg[0]);
  helixJacobianValues(k, 0, 1, 0, 0, out.dg[1]);
  helixJacobianValues(k, 0, 0, 1, 0, out.dg[2]);
  helixJacobianValues(k, 0, 0, 0, 1, out.dg[3]);
  // helixPoint's D²g[v, v] (v = kd, p = k·v) taken apart by function: b = f2, da = f3,
  // db = f4, u⁶χ1 = f5, u⁷χ2 = f6 (dda = f5 p² + f3 |v|², ddb = f6 p² + f4 |v|²).
  const double k0 = k.x(), k1 = k.y(), k2 = k.z();
  const double v0 = kd.x(), v1 = kd.y(), v2 = kd.z();
  const double w0 = -(k1 * k1 + k2 * k2);
  const double kv12 = k1 * v1 + k2 * v2, vv12 = v1 * v1 + v2 * v2;
  const double p = k0 * v0 + kv12, vv = v0 * v0 + vv12, pp = p * p;
  out.d2g[0] = Eigen::Vector3d(-2 * vv12, 2 * v0 * v1, 2 * v0 * v2);
  out.d2g[1] = Eigen::Vector3d(0, vv * k2 + 2 * p * v2, -(vv * k1 + 2 * p * v1));
  const double m1 = vv * k0 + 2 * p * v0, m2 = 2 * p * k0;
  out.d2g[2] = Eigen::Vector3d(vv * w0 - 4 * p * kv12, k1 * m1 + v1 * m2, k2 * m1 + v2 * m2);
  out.d2g[3] = Eigen::Vector3d(0, pp * k2, -pp * k1);
  out.d2g[4] = Eigen::Vector3d(pp * w0, pp * k0 * k1, pp * k0 * k2);
}

void helixBilinearBasis(const Eigen::Vector3d& k, const Eigen::Vector3d& kd,
                        const Eigen::Matrix3d& F, Eigen::Matrix3d (&out)[5])
{
  // helixBilinearValues with one function at a time (v = kd, p = k·v, w = k × (k × e0)):
  //   c3 = u³φ2:  −2 e0 vᵀ + v0 I + v e0ᵀ
  //   c1 = u⁴ψ1:  (v × e0) kᵀ + (k × e0) vᵀ + p (e1 e2ᵀ − e2 e1ᵀ)
  //   c2 = u⁵ψ2:  a kᵀ + w vᵀ + p k0 I + p k e0ᵀ,
  //               a = (−2 (k1 v1 + k2 v2 + p), k1 v0 + k0 v1, k2 v0 + k0 v2)
  //   e6 = u⁶χ1:  p (k × e0) kᵀ
  //   e7 = u⁷χ2:  p w kᵀ
  // and F times each, with F e0, F e1, F e2 the columns of F.
  const double k0 = k.x(), k1 = k.y(), k2 = k.z();
  const double v0 = kd.x(), v1 = kd.y(), v2 = kd.z();
  const double kv12 = k1 * v1 + k2 * v2, p = k0 * v0 + kv12, w0 = -(k1 * k1 + k2 * k2);
  const Eigen::Vector3d f0 = F.col(0), f1 = F.col(1), f2 = F.col(2);
  const Eigen::Vector3d Fv = F * kd, Fk = F * k;
  const Eigen::Vector3d Fkx = k2 * f1 - k1 * f2; // F (k × e0)
  const Eigen::Vector3d Fvx = v2 * f1 - v1 * f2; // F (v × e0)
  const Eigen::Vector3d Fw = w0 * f0 + (k0 * k1) * f1 + (k0 * k2) * f2;
  const Eigen::Vector3d Fa =
      (-2 * (kv12 + p)) * f0 + (k1 * v0 + k0 * v1) * f1 + (k2 * v0 + k0 * v2) * f2;
  out[0].noalias() = (-2 * f0) * kd.transpose();
  out[0] += v0 * F;
  out[0].col(0) += Fv;
  out[1].noalias() = Fvx * k.transpose();
  out[1].noalias() += Fkx * kd.transpose();
  out[1].col(2) += p * f1;
  out[1].col(1) -= p * f2;
  out[2].noalias() = Fa * k.transpose();
  out[2].noalias() += Fw * kd.transpose();
  out[2] += (p * k0) * F;
  out[2].col(0) += p * Fk;
  out[3].noalias() = (p * Fkx) * k.transpose();
  out[4].noalias() = (p * Fw) * k.transpose();
}

void helixEnd(const Eigen::Vector3d& k, const Eigen::Vector3d& kd, double u, HelixEnd& out)
{
  HelixCoefficients h;
  helixPoint(k, kd, u, out, &h);
  helixEndRotation(k, kd, u, h, out);
}

void helixEndRotation(const Eigen::Vector3d& k, const Eigen::Vector3d& kd, double u,
                      const HelixCoefficients& h, HelixEnd& out)
{
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
  const HelixCoefficients h =
      coefficients ? *coefficients : hair::coefficients(std::sqrt(k.squaredNorm()) * u);
  double f[7];
  helixFunctionValues(u, h, f);
  helixBilinearValues(k, v, f[2], f[3], f[4], f[5], f[6], d2gW, dGkW);
}
} // namespace hair
