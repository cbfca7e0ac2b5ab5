// Reconstruction, Jacobian, velocity-dependent terms and mass matrix of the Super-Helix
// model, each checked against an independent computation: finite differences of the
// reconstruction (allowed in tests only), brute-force quadrature, and the analytic helix.
#include "HeadShake.h"
#include "helix/HelixFunctions.h"
#include "superhelix/SuperHelix.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

using namespace hair;

namespace
{
HairParameters plainHair()
{
  HairParameters p = HairParameters::preset(HairType::Smooth);
  p.curvatureVariation = 0;
  return p;
}

// A curled strand with a moving root: every term of the kinematics is exercised.
struct Curled
{
  StrandSpec spec;
  Eigen::VectorXd q, qd;
  Curled()
  {
    spec = StrandSpec::uniform(0.1, 4, plainHair());
    spec.elementLengths = {0.02, 0.035, 0.025, 0.02}; // unequal lengths
    HeadShake shake;
    shake.axis = Eigen::Vector3d(0.3, 1, 0.2);
    shake.frequency = 1.3;
    shake.amplitude = 0.4;
    spec.root = shake;
    std::mt19937 g(7);
    std::uniform_real_distribution<double> d(-1, 1);
    q.resize(12);
    qd.resize(12);
    for (int i = 0; i < 12; ++i)
    {
      q[i] = 40 * d(g); // up to 40 1/m: about 1 rad per element, curved branch
      qd[i] = 20 * d(g);
    }
    q[3] = 1e-7; // a nearly straight element: the series branch
    q[4] = -2e-7;
    q[5] = 0;
  }
  SuperHelix make(double t, const Eigen::VectorXd& qq) const
  {
    SuperHelix h;
    EXPECT_TRUE(h.initialize(spec, t).ok());
    EXPECT_TRUE(h.setState(qq, qd).ok());
    return h;
  }
};

// K_T of an initialized strand in its current state, for a step of h: the phases in the
// order the step runs them (kinematics, then M and f, which K_T's tension needs).
Eigen::MatrixXd tensionStiffnessOf(SuperHelix& h, double step)
{
  h.reconstruct();
  h.assemble();
  h.assembleTensionStiffness(step);
  return h.tensionStiffness();
}
} // namespace

TEST(SuperHelixKinematics, SeriesAndClosedFormsAgreeAtTheSwitch)
{
  // The series (x < 1.5) and the closed forms must be the same function: compare both
  // sides of the switch, 2e-12 apart (slopes are < 0.1, so that moves values by < 2e-13).
  // 1e-12 is the closed forms' cancellation error there (~1e-16 · 15 / (χ2 x⁷)); a wrong
  // series coefficient would jump by far more than 1e-6.
  const double eps = 1e-12;
  const HelixCoefficients a = helixCoefficients(1.5 - eps), b = helixCoefficients(1.5 + eps);
  EXPECT_NEAR(a.phi0, b.phi0, 1e-12);
  EXPECT_NEAR(a.phi1, b.phi1, 1e-12);
  EXPECT_NEAR(a.phi2, b.phi2, 1e-12);
  EXPECT_NEAR(a.psi1, b.psi1, 1e-12);
  EXPECT_NEAR(a.psi2, b.psi2, 1e-12);
  EXPECT_NEAR(a.chi1, b.chi1, 1e-12);
  EXPECT_NEAR(a.chi2, b.chi2, 1e-12);
  // Values at 0 from the Taylor series of sin and cos.
  const HelixCoefficients z = helixCoefficients(0);
  EXPECT_DOUBLE_EQ(z.phi1, 0.5);
  EXPECT_DOUBLE_EQ(z.psi1, -1.0 / 12);
  EXPECT_DOUBLE_EQ(z.chi2, 1.0 / 630);
}

TEST(SuperHelixKinematics, CoefficientsFromAKnownSineAndCosineMatchTheDirectOnes)
{
  // The reconstruction takes sin and cos at the farther node of each Gauss pair from the
  // angle difference X − x (X = Ω (a + b) on the interval [a, b]). Those differ from a
  // direct sincos by the products' rounding (|sX c| + |cX s| <= 1: <= 3.3e-16) plus each
  // sincos's half ulp and the rounding of the angle X − x itself (half an ulp of it), so
  // δ = 4.4e-16 (1 + x); each coefficient moves by δ times the weights of s and c in its
  // closed form over its power of x, plus a few ulps of its own rounding.
  for (double X = 3.0; X < 60.0; X *= 1.13)
    for (double t = 0.02; t < 0.5; t += 0.037)
    {
      const double x = t * X, xm = X - x;
      double sX, cX, s, c;
      sinCos(X, sX, cX);
      sinCos(x, s, c);
      const HelixCoefficients a = helixCoefficients(xm, sX * c - cX * s, cX * c + sX * s);
      const HelixCoefficients b = helixCoefficients(xm);
      const double d = 4.4e-16 * (1 + xm), y = xm, y2 = y * y, y4 = y2 * y2;
      auto tol = [&](double value, double bound) { return bound + 4e-16 * std::abs(value); };
      EXPECT_NEAR(a.phi0, b.phi0, tol(b.phi0, d / y)) << "x = " << xm;
      EXPECT_NEAR(a.phi1, b.phi1, tol(b.phi1, d / y2)) << "x = " << xm;
      EXPECT_NEAR(a.phi2, b.phi2, tol(b.phi2, d / (y2 * y))) << "x = " << xm;
      EXPECT_NEAR(a.psi1, b.psi1, tol(b.psi1, d * (y + 2) / y4)) << "x = " << xm;
      EXPECT_NEAR(a.psi2, b.psi2, tol(b.psi2, d * (3 + y) / (y4 * y))) << "x = " << xm;
      EXPECT_NEAR(a.chi1, b.chi1, tol(b.chi1, d * (y2 + 5 * y + 8) / (y4 * y2))) << "x = " << xm;
      EXPECT_NEAR(a.chi2, b.chi2, tol(b.chi2, d * (7 * y + y2 + 15) / (y4 * y2 * y)))
          << "x = " << xm;
    }
  // Below the series limit the sine and cosine are not read.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (double x : {0.0, 0.3, 1.0, 1.49})
  {
    const HelixCoefficients a = helixCoefficients(x, nan, nan), b = helixCoefficients(x);
    EXPECT_EQ(a.phi0, b.phi0);
    EXPECT_EQ(a.chi2, b.chi2);
  }
}

TEST(SuperHelixKinematics, SeriesBandsGiveTheFullSeriesToRoundOff)
{
  // Below 1.5 the coefficients are Taylor series with fewer terms for smaller |x| (8, 10, 11
  // terms below 0.5, 1, 1.5). Against the series summed to 25 terms in long double, on a
  // grid that crosses the band limits, they must be exact to 2 ε relative (the double
  // Horner evaluation itself is ~1 ε; two terms too few would leave ≥ 2e-14 near a limit).
  const double eps = std::numeric_limits<double>::epsilon();
  auto reference = [](double xd)
  {
    const long double y = static_cast<long double>(xd) * xd;
    std::array<long double, 7> r{};
    for (int m = 24; m >= 0; --m)
    {
      long double f = 1; // (2m + 1)!
      for (int j = 2; j <= 2 * m + 1; ++j)
        f *= j;
      const long double sg = (m % 2 == 0) ? 1 : -1, a = 2 * m + 2, b = 2 * m + 3, c = 2 * m + 4,
                        d = 2 * m + 5, e = 2 * m + 6, g = 2 * m + 7;
      const std::array<long double, 7> t = {sg / f,
                                            sg / (f * a),
                                            sg / (f * a * b),
                                            -sg * a / (f * a * b * c),
                                            -sg * a / (f * a * b * c * d),
                                            sg * c * a / (f * a * b * c * d * e),
                                            sg * c * a / (f * a * b * c * d * e * g)};
      for (int i = 0; i < 7; ++i)
        r[i] = r[i] * y + t[i];
    }
    return r;
  };
  std::vector<double> xs;
  for (int i = 0; i < 3000; ++i)
    xs.push_back(1.5 * i / 3000);
  for (double lim : {0.5, 1.0, 1.5})
    for (double d : {1e-15, 1e-12, 1e-9, 1e-6})
    {
      xs.push_back(lim - d);
      if (lim < 1.5)
        xs.push_back(lim + d);
    }
  xs.push_back(std::nextafter(0.5, 0.0));
  xs.push_back(std::nextafter(1.0, 0.0));
  xs.push_back(std::nextafter(1.5, 0.0));
  for (double x : xs)
  {
    const auto r = reference(x);
    for (double sx : {x, -x}) // even functions
    {
      const HelixCoefficients h = helixCoefficients(sx);
      const double* v = &h.phi0;
      for (int i = 0; i < 7; ++i)
        EXPECT_LE(std::abs(v[i] - r[i]) / std::abs(r[i]), 2 * eps) << "x = " << sx << " i = " << i;
    }
  }
}

namespace
{
// Random (k, k̇, u) covering the straight, the series and the closed-form ranges up to the
// fuzzy preset's x = |k| ℓ ≈ 16, with some components of k exactly zero.
struct HelixSample
{
  Eigen::Vector3d k, kd;
  double u;
};
std::vector<HelixSample> helixSamples()
{
  std::mt19937 g(11);
  std::normal_distribution<double> n;
  std::uniform_real_distribution<double> un(0, 1);
  std::vector<HelixSample> out;
  for (double om : {0.0, 0.5, 30.0, 60.0, 100.0, 250.0, 530.0})
    for (int r = 0; r < 6; ++r)
    {
      HelixSample s;
      s.k = Eigen::Vector3d(n(g), n(g), n(g)).normalized() * om;
      if (r == 4)
        s.k.y() = 0;
      if (r == 5)
        s.k = Eigen::Vector3d(om, 0, 0) + 1e-3 * s.k; // nearly a pure twist
      s.kd = Eigen::Vector3d(n(g), n(g), n(g)) * 20;
      s.u = 0.03 * (0.1 + 0.9 * un(g));
      out.push_back(s);
    }
  return out;
}
} // namespace

TEST(SuperHelixKinematics, HelixPointAndEndMatchDifferencesUpToFuzzyCurvature)
{
  // Each output against central differences of another, at x up to ~16 (the Curled strand
  // stays below 2.5): dg of g (step δ with δ u = 3e-5: truncation ~x (δu)² < 1e-7 relative,
  // round-off ~1e-16 x/(δu) < 1e-10), d2g = d/dt (dg (k + t k̇) k̇), dGk = d/dt (G(k + t k̇) k̇)
  // with t |k̇| u = 3e-5; ∂g/∂u = E e0 and ∂G/∂u = E; and E = exp(u [k]×). d2g and dGk are
  // measured against at least 1e-3 of their natural sizes u³|k̇|² and u²|k̇|² (dGk = 0 at
  // k = 0, where the difference quotient keeps ~1e-12 u²|k̇|² of round-off).
  for (const HelixSample& s : helixSamples())
  {
    const Eigen::Vector3d& k = s.k;
    const Eigen::Vector3d& kd = s.kd;
    const double u = s.u;
    HelixEnd e;
    helixEnd(k, kd, u, e);
    auto at = [&](const Eigen::Vector3d& kk, double uu)
    {
      HelixEnd r;
      helixEnd(kk, kd, uu, r);
      return r;
    };
    const std::string where = "k = " + std::to_string(k.norm()) + ", u = " + std::to_string(u);
    // dg
    const double dk = 3e-5 / u;
    for (int i = 0; i < 3; ++i)
    {
      const Eigen::Vector3d fd = (at(k + dk * Eigen::Vector3d::Unit(i), u).g -
                                  at(k - dk * Eigen::Vector3d::Unit(i), u).g) /
                                 (2 * dk);
      EXPECT_LT((e.dg.col(i) - fd).cwiseAbs().maxCoeff(), 1e-7 * e.dg.cwiseAbs().maxCoeff())
          << where << " column " << i;
    }
    // d2g and dGk along k̇
    const double t = 3e-5 / (kd.norm() * u);
    const HelixEnd p = at(k + t * kd, u), m = at(k - t * kd, u);
    const Eigen::Vector3d d2gFd = (p.dg * kd - m.dg * kd) / (2 * t);
    const double vv = kd.squaredNorm();
    EXPECT_LT((e.d2g - d2gFd).cwiseAbs().maxCoeff(),
              1e-7 * std::max(e.d2g.cwiseAbs().maxCoeff(), 1e-3 * u * u * u * vv))
        << where;
    const Eigen::Vector3d dGkFd = (p.G * kd - m.G * kd) / (2 * t);
    EXPECT_LT((e.dGk - dGkFd).cwiseAbs().maxCoeff(),
              1e-7 * std::max(e.dGk.cwiseAbs().maxCoeff(), 1e-3 * u * u * vv))
        << where;
    // ∂/∂u with δu = 1e-5 u: truncation ~(|k| δu)²/6 < 1e-8, round-off ~1e-16 u / δu = 1e-11.
    const double du = 1e-5 * u;
    const HelixEnd up = at(k, u + du), um = at(k, u - du);
    EXPECT_LT(((up.g - um.g) / (2 * du) - e.E.col(0)).cwiseAbs().maxCoeff(), 1e-7) << where;
    EXPECT_LT(((up.G - um.G) / (2 * du) - e.E).cwiseAbs().maxCoeff(), 1e-7) << where;
    // E is the rotation exp(u [k]×).
    const double om = k.norm();
    const Eigen::Matrix3d R =
        om > 0 ? Eigen::AngleAxisd(om * u, k / om).toRotationMatrix() : Eigen::Matrix3d::Identity();
    EXPECT_LT((e.E - R).cwiseAbs().maxCoeff(), 1e-14 * (1 + om * u)) << where;
    // helixPoint gives helixEnd's point part, and its coefficients are helixCoefficients(|k| u).
    HelixPoint hp;
    HelixCoefficients hc;
    helixPoint(k, kd, u, hp, &hc);
    EXPECT_EQ(hp.g, e.g);
    EXPECT_EQ(hp.dg, e.dg);
    EXPECT_EQ(hp.d2g, e.d2g);
    const HelixCoefficients h2 = helixCoefficients(std::sqrt(k.squaredNorm()) * u);
    EXPECT_EQ(std::memcmp(&hc, &h2, sizeof hc), 0) << where;
  }
}

TEST(SuperHelixKinematics, HelixBilinearIsThePolarizationOfTheQuadraticForms)
{
  // d2g = D²g[k̇, k̇] and dGk = D(G k̇)[k̇] are quadratic in k̇, so their bilinear forms follow
  // exactly from B[v, w] = (Q(v + w) − Q(v − w)) / 4 with w = s e_i: only round-off remains
  // (~1e-15 relative with s = |v|); 1e-12 of the matrix's largest entry.
  for (const HelixSample& sm : helixSamples())
  {
    const Eigen::Vector3d& k = sm.k;
    const Eigen::Vector3d& v = sm.kd;
    const double u = sm.u;
    Eigen::Matrix3d W, GW;
    helixBilinear(k, v, u, W, &GW);
    const double s = v.norm();
    Eigen::Matrix3d Wp, GWp;
    for (int i = 0; i < 3; ++i)
    {
      HelixEnd a, b;
      helixEnd(k, v + s * Eigen::Vector3d::Unit(i), u, a);
      helixEnd(k, v - s * Eigen::Vector3d::Unit(i), u, b);
      Wp.col(i) = (a.d2g - b.d2g) / (4 * s);
      GWp.col(i) = (a.dGk - b.dGk) / (4 * s);
    }
    const std::string where = "k = " + std::to_string(k.norm()) + ", u = " + std::to_string(u);
    EXPECT_LE((W - Wp).cwiseAbs().maxCoeff(), 1e-12 * W.cwiseAbs().maxCoeff()) << where;
    EXPECT_LE((GW - GWp).cwiseAbs().maxCoeff(), 1e-12 * GW.cwiseAbs().maxCoeff())
        << where; // 0 at k = 0
    // With helixPoint's coefficients passed in, and without dGkW: the same d2gW, bit for bit.
    HelixPoint hp;
    HelixCoefficients hc;
    helixPoint(k, v, u, hp, &hc);
    Eigen::Matrix3d W2;
    helixBilinear(k, v, u, W2, nullptr, &hc);
    EXPECT_EQ(W2, W) << where;
  }
}

TEST(SuperHelixKinematics, HelixBasisRebuildsHelixPoint)
{
  // helixBasis takes helixPoint's expressions apart by element function, so the sums
  // Σ f_i (coefficient i) are the same numbers summed in another order: round-off only.
  // Each term is bounded by Σ |f_i| |coefficient i|, and a sum of m terms rounded in any
  // order differs by at most ~2 m ε of that bound (m ≤ 5 here, ε = 1.1e-16): 1e-14 of it.
  for (const HelixSample& sm : helixSamples())
  {
    const Eigen::Vector3d& k = sm.k;
    const Eigen::Vector3d& kd = sm.kd;
    const double u = sm.u;
    HelixPoint hp;
    HelixCoefficients hc;
    helixPoint(k, kd, u, hp, &hc);
    double f[7];
    helixFunctionValues(u, hc, f);
    HelixBasis b;
    helixBasis(k, kd, b);
    Eigen::Vector3d g = Eigen::Vector3d::Zero(), gb = g, d2g = g, d2gb = g;
    Eigen::Matrix3d dg = Eigen::Matrix3d::Zero(), dgb = dg;
    for (int i = 0; i < 3; ++i)
    {
      g += f[i] * b.g[i];
      gb += std::abs(f[i]) * b.g[i].cwiseAbs();
    }
    for (int i = 0; i < 4; ++i)
    {
      dg += f[i + 1] * b.dg[i];
      dgb += std::abs(f[i + 1]) * b.dg[i].cwiseAbs();
    }
    for (int i = 0; i < 5; ++i)
    {
      d2g += f[i + 2] * b.d2g[i];
      d2gb += std::abs(f[i + 2]) * b.d2g[i].cwiseAbs();
    }
    const std::string where = "k = " + std::to_string(k.norm()) + ", u = " + std::to_string(u);
    for (int r = 0; r < 3; ++r)
    {
      EXPECT_LE(std::abs(g[r] - hp.g[r]), 1e-14 * gb[r] + 1e-300) << where;
      EXPECT_LE(std::abs(d2g[r] - hp.d2g[r]), 1e-14 * d2gb[r] + 1e-300) << where;
      for (int c = 0; c < 3; ++c)
        EXPECT_LE(std::abs(dg(r, c) - hp.dg(r, c)), 1e-14 * dgb(r, c) + 1e-300) << where;
    }
  }
}

TEST(SuperHelixKinematics, HelixBilinearBasisRebuildsHelixBilinear)
{
  // F d2gW = Σ f_i out_i for a frame F: helixBilinearValues taken apart by function, so only
  // the order of the roundings differs. Bound as for HelixBasisRebuildsHelixPoint, with the
  // terms' magnitudes Σ |f_i| |F| |D_i| (|F| |D_i| ≥ |F D_i| entrywise): 1e-14 of it.
  std::mt19937 gen(5);
  std::normal_distribution<double> nd;
  for (const HelixSample& sm : helixSamples())
  {
    const Eigen::Vector3d& k = sm.k;
    const Eigen::Vector3d& kd = sm.kd;
    const double u = sm.u;
    const Eigen::Matrix3d F =
        Eigen::AngleAxisd(nd(gen), Eigen::Vector3d(nd(gen), nd(gen), nd(gen)).normalized())
            .toRotationMatrix();
    Eigen::Matrix3d W;
    helixBilinear(k, kd, u, W, nullptr);
    const HelixCoefficients hc = helixCoefficients(std::sqrt(k.squaredNorm()) * u);
    double f[7];
    helixFunctionValues(u, hc, f);
    Eigen::Matrix3d B[5], I[5];
    helixBilinearBasis(k, kd, F, B);
    helixBilinearBasis(k, kd, Eigen::Matrix3d::Identity(), I);
    Eigen::Matrix3d sum = Eigen::Matrix3d::Zero(), bound = sum;
    for (int i = 0; i < 5; ++i)
    {
      sum += f[i + 2] * B[i];
      bound += std::abs(f[i + 2]) * (F.cwiseAbs() * I[i].cwiseAbs());
    }
    const Eigen::Matrix3d ref = F * W;
    const std::string where = "k = " + std::to_string(k.norm()) + ", u = " + std::to_string(u);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        EXPECT_LE(std::abs(sum(r, c) - ref(r, c)), 1e-14 * bound(r, c) + 1e-300)
            << where << " (" << r << ", " << c << ")";
  }
}

TEST(SuperHelixKinematics, StraightElementIsExact)
{
  // k = 0 (the series at x = 0): g = u e0, E = I, G = u I exactly; the only non-zero
  // entries of dg are ±u²/2 (a = u² φ1(0)), and d2g = b (2 v0 v − 2 |v|² e0), b = u³/6.
  const Eigen::Vector3d k = Eigen::Vector3d::Zero(), v(3, -2, 5);
  for (double u : {1e-3, 0.0123, 0.03})
  {
    HelixEnd e;
    helixEnd(k, v, u, e);
    EXPECT_EQ(e.g, Eigen::Vector3d(u, 0, 0));
    EXPECT_EQ(e.E, Eigen::Matrix3d::Identity());
    EXPECT_EQ(e.G, (u * Eigen::Matrix3d::Identity()).eval());
    Eigen::Matrix3d dg = Eigen::Matrix3d::Zero();
    dg(2, 1) = -u * u / 2;
    dg(1, 2) = u * u / 2;
    EXPECT_EQ(e.dg, dg);
    const double b = u * u * u / 6;
    const Eigen::Vector3d d2g(-2 * b * (v.y() * v.y() + v.z() * v.z()), 2 * b * v.x() * v.y(),
                              2 * b * v.x() * v.z());
    EXPECT_LT((e.d2g - d2g).cwiseAbs().maxCoeff(), 1e-15 * d2g.cwiseAbs().maxCoeff());
  }
}

TEST(SuperHelixKinematics, JacobianMatchesFiniteDifferences)
{
  const Curled c;
  SuperHelix h = c.make(0.3, c.q);
  const double L = h.length();
  // Central differences with step 1e-3 1/m: truncation ~ε² ℓ⁴ |∂³r|, round-off ~1e-16/ε;
  // both below 1e-9 m per (1/m). The Jacobian entries are O(ℓ²) ~ 1e-4 to 1e-2.
  const double eps = 1e-3;
  for (double s : {0.0, 0.013, 0.02, 0.041, 0.055, 0.08, 0.0999, L})
  {
    const Eigen::Matrix3Xd J = h.jacobian(s);
    for (int a = 0; a < 12; ++a)
    {
      Eigen::VectorXd qp = c.q, qm = c.q;
      qp[a] += eps;
      qm[a] -= eps;
      const Eigen::Vector3d fd =
          (c.make(0.3, qp).position(s) - c.make(0.3, qm).position(s)) / (2 * eps);
      EXPECT_LT((J.col(a) - fd).norm(), 1e-9) << "s = " << s << ", coordinate " << a;
    }
  }
}

TEST(SuperHelixKinematics, VelocityAndRestAccelerationMatchTimeDifferences)
{
  // r(t) with q(t) = q + (t − t0) q̇ and the root moving: ṙ = velocity(s), and r̈ with q̈ = 0
  // is accelerationAtRest(s) (root acceleration, centrifugal and Coriolis terms).
  const Curled c;
  const double t0 = 0.3, d = 1e-4;
  SuperHelix h = c.make(t0, c.q);
  SuperHelix hp = c.make(t0 + d, c.q + d * c.qd);
  SuperHelix hm = c.make(t0 - d, c.q - d * c.qd);
  for (double s : {0.0, 0.01, 0.03, 0.06, 0.0999})
  {
    const Eigen::Vector3d rp = hp.position(s), rm = hm.position(s), r0 = h.position(s);
    const Eigen::Vector3d vfd = (rp - rm) / (2 * d);
    const Eigen::Vector3d afd = (rp - 2 * r0 + rm) / (d * d);
    const Eigen::Vector3d v = h.velocity(s), a = h.accelerationAtRest(s);
    // Truncation d²|r'''| / 6 ~ 1e-8 |v| ω²; round-off in the second difference
    // ~1e-16 |r| / d² ~ 1e-9 m/s². Tolerances: 1e-6 relative.
    EXPECT_LT((v - vfd).norm(), 1e-6 * (1 + v.norm())) << s;
    EXPECT_LT((a - afd).norm(), 1e-5 * (1 + a.norm()))
        << s << " a=" << a.transpose() << " fd=" << afd.transpose();
  }
}

TEST(SuperHelixKinematics, PositionAndVelocityTogetherAreTheSameValues)
{
  // The simulation's display points use the combined call; it must give exactly what
  // position(s) and velocity(s) give (the same operations), so that frames do not change.
  const Curled c;
  const SuperHelix h = c.make(0.3, c.q);
  for (double s : {0.0, 0.005, 0.02, 0.03, 0.055, 0.08, 0.0999, 0.1, 0.2})
  {
    Eigen::Vector3d x, v;
    h.positionAndVelocity(s, x, v);
    EXPECT_TRUE(x == h.position(s)) << s;
    EXPECT_TRUE(v == h.velocity(s)) << s;
  }
}

TEST(SuperHelixKinematics, MassMatrixEqualsBruteForceQuadratureAndIsPositiveDefinite)
{
  // M = ∫ ρS JᵀJ ds + ∫ J_ωᵀ I(s) J_ω ds (centreline and cross-section rotary inertia,
  // I(s) = F diag(ρI_p, ρI1, ρI2) Fᵀ). A thick fibre (radius 3 mm on elements of 2–3.5 cm)
  // makes the rotary part ~1 % of M, so that the tolerance below checks it too.
  Curled c;
  c.spec.hair.radius = 3e-3;
  c.spec.hair.ellipticity = 1.3;
  SuperHelix h = c.make(0.3, c.q);
  h.reconstruct();
  h.assemble();
  const Eigen::MatrixXd M = h.massMatrix();
  // Brute force with 64 Gauss points per element: J from jacobian(s); J_ω from central
  // differences of frame(s) ([δθ]× = δF Fᵀ; ε = 1e-6 1/m: truncation ~(εℓ)² and round-off
  // ~1e-16/(εℓ) ≈ 5e-9 relative, far below the tolerance).
  const double eps = 1e-6;
  std::vector<SuperHelix> plus, minus;
  for (int b = 0; b < 12; ++b)
  {
    Eigen::VectorXd qp = c.q, qm = c.q;
    qp[b] += eps;
    qm[b] -= eps;
    plus.push_back(c.make(0.3, qp));
    minus.push_back(c.make(0.3, qm));
  }
  Eigen::MatrixXd Mb = Eigen::MatrixXd::Zero(12, 12), Mrot = Mb;
  const double rhoS = c.spec.hair.linearDensity();
  const Eigen::Vector3d rotI = c.spec.hair.rotaryInertia();
  const double gx[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                        0.8611363115940526};
  const double gw[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                        0.3478548451374538};
  double s0 = 0;
  for (double l : c.spec.elementLengths)
  {
    const int sub = 16;
    for (int k = 0; k < sub; ++k)
      for (int g = 0; g < 4; ++g)
      {
        const double s = s0 + l / sub * (k + 0.5 + 0.5 * gx[g]);
        const double w = 0.5 * l / sub * gw[g];
        const Eigen::Matrix3Xd J = h.jacobian(s);
        Mb += rhoS * w * J.transpose() * J;
        const Eigen::Matrix3d F = h.frame(s);
        Eigen::Matrix3Xd Jw(3, 12);
        for (int b = 0; b < 12; ++b)
        {
          const Eigen::Matrix3d W =
              (plus[b].frame(s) - minus[b].frame(s)) / (2 * eps) * F.transpose();
          Jw.col(b) =
              0.5 * Eigen::Vector3d(W(2, 1) - W(1, 2), W(0, 2) - W(2, 0), W(1, 0) - W(0, 1));
        }
        Mrot += w * Jw.transpose() * F * rotI.asDiagonal() * F.transpose() * Jw;
      }
    s0 += l;
  }
  Mb += Mrot;
  RecordProperty("rotary_share",
                 std::to_string(Mrot.cwiseAbs().maxCoeff() / Mb.cwiseAbs().maxCoeff()));
  EXPECT_GT(Mrot.cwiseAbs().maxCoeff(), 1e-3 * Mb.cwiseAbs().maxCoeff()); // the check has teeth
  // The model's quadrature (4 Gauss points per π/2 of turning) has a Gauss remainder of
  // ~h (Ωh)⁸ (4!)⁴/(9 (8!)³) ≈ 2e-8 relative; 1e-5 of the largest entry leaves room for the
  // brute force's own error while a wrong tail sum (an O(1) relative error in
  // off-diagonal blocks) cannot pass.
  EXPECT_LT((M - Mb).cwiseAbs().maxCoeff(), 1e-5 * Mb.cwiseAbs().maxCoeff());
  EXPECT_LT((M - M.transpose()).cwiseAbs().maxCoeff(), 1e-15 * M.cwiseAbs().maxCoeff());
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(M);
  EXPECT_GT(es.eigenvalues().minCoeff(), 0) << es.eigenvalues().transpose();
}

TEST(SuperHelixKinematics, KineticEnergyOnAFixedRootIsHalfQdotMQdot)
{
  // With the root at rest, ṙ = J q̇ and ω = J_ω q̇, so the kinetic energy the reconstruction
  // sums (centreline and cross-section rotation, the latter in the linear form of E(u)ᵀ
  // (F0ᵀ ω + G(u) k̇)) is ½ q̇ᵀ M q̇ with the M of the same samples: equal to round-off
  // (1e-12 relative: a few hundred products of positive terms). Curled elements from 0 to
  // ~20 rad of turning (the series and the closed forms, from a sincos and from the mirror
  // pair's angle difference; all one-interval rules), a thick fibre
  // so that the rotary part is well above the tolerance (checked against the same strand
  // with the same ρS and 1e-4 of the rotary inertia).
  auto make = [](double radius, double density)
  {
    HairParameters p = plainHair();
    p.radius = radius;
    p.density = density;
    p.ellipticity = 1.3;
    StrandSpec spec = StrandSpec::uniform(0.12, 5, p);
    spec.elementLengths = {0.02, 0.035, 0.025, 0.02, 0.02};
    return spec;
  };
  std::mt19937 g(11);
  std::uniform_real_distribution<double> d(-1, 1);
  Eigen::VectorXd q(15), qd(15);
  const double scale[5] = {1e-7, 40, 200, 600, 1000}; // 1/m: turning up to ~20 rad
  for (int i = 0; i < 15; ++i)
  {
    q[i] = scale[i / 3] * d(g);
    qd[i] = 20 * d(g);
  }
  double kinetic[2];
  for (int c = 0; c < 2; ++c)
  {
    // Same ρS = ρ π r² e: radius / 100, density × 10⁴.
    const StrandSpec spec = c == 0 ? make(3e-3, 1300) : make(3e-5, 1.3e7);
    SuperHelix h;
    ASSERT_TRUE(h.initialize(spec).ok());
    ASSERT_TRUE(h.setState(q, qd).ok());
    h.assemble();
    const double half = 0.5 * qd.dot(h.massMatrix() * qd);
    kinetic[c] = h.energy().kinetic;
    EXPECT_NEAR(kinetic[c], half, 1e-12 * half) << "radius " << spec.hair.radius;
  }
  RecordProperty("rotary_share", std::to_string(std::abs(kinetic[0] - kinetic[1]) / kinetic[0]));
  EXPECT_GT(std::abs(kinetic[0] - kinetic[1]), 1e-4 * kinetic[0]); // the check has teeth
}

TEST(SuperHelixKinematics, StraightStrandsMassMatrixIsDefiniteThroughRotaryInertia)
{
  // An exactly straight strand: twist moves no point of the centreline, so only the
  // cross-section's rotary inertia gives the twist directions a mass: ρ I_p ℓ³/3 for the
  // element's own twist (∫0^ℓ ρ I_p u² du, the frame turning by u δτ about the tangent).
  HairParameters p = plainHair();
  StrandSpec spec = StrandSpec::uniform(0.3, 1, p);
  SuperHelix h;
  ASSERT_TRUE(h.initialize(spec).ok());
  h.reconstruct();
  h.assemble();
  const double l = 0.3, expected = p.rotaryInertia()[0] * l * l * l / 3;
  // Gauss quadrature is exact for this quadratic integrand: round-off only.
  EXPECT_NEAR(h.massMatrix()(0, 0), expected, 1e-12 * expected);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(h.massMatrix());
  EXPECT_GT(es.eigenvalues().minCoeff(), 0.5 * expected) << es.eigenvalues().transpose();
}

TEST(SuperHelixKinematics, NaturalHelixHasTheParametersRadiusAndStep)
{
  // The rest shape of a curled preset must be the helix its parameters name: radius r_h and
  // step Δ_h per turn. Measured on the reconstructed centreline against the parameters
  // alone (a helix of radius r and step Δ = 2πc has arc length 2π√(r² + c²) per turn, so
  // it advances c/√(r² + c²) along its axis per unit length), not against the curvature
  // formula. The axis and centre are fitted from the curve: the axis is the direction of
  // the chord between points one turn apart, the centre the mean over one turn.
  for (HairType type : {HairType::Wavy, HairType::Curly, HairType::Fuzzy})
  {
    HairParameters p = HairParameters::preset(type);
    p.curvatureVariation = 0;
    const double c = p.helixStep / (2 * M_PI), turn = 2 * M_PI * std::hypot(p.helixRadius, c);
    // Three turns on 4 elements (fuzzy: 3 × 2.6 cm, wavy: 3 × 19 cm).
    StrandSpec spec = StrandSpec::uniform(3 * turn, 4, p);
    spec.gravity.setZero();
    SuperHelix h;
    ASSERT_TRUE(h.initialize(spec).ok()) << toString(type);
    const int per = 240; // polyline points per turn
    std::vector<Eigen::Vector3d> pts;
    h.polyline(per * 3 / 4, pts); // 4 elements × 180 = 3 turns × 240
    ASSERT_EQ(pts.size(), size_t(3 * per + 1));
    const Eigen::Vector3d axis = (pts[2 * per] - pts[per]).normalized();
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (int i = 0; i < per; ++i)
      centre += pts[per + i] / per; // the mean of equally spaced points of a turn: on the axis
    const double advance = c / std::hypot(p.helixRadius, c);
    for (int i = 0; i <= 3 * per; ++i)
    {
      const double s = turn * i / per;
      const Eigen::Vector3d d = pts[i] - centre;
      const double axial = d.dot(axis) - (pts[per] - centre).dot(axis);
      // Round-off of the closed-form chain over a few turns: 1e-12 of the turn length.
      EXPECT_NEAR((d - d.dot(axis) * axis).norm(), p.helixRadius, 1e-12 * turn)
          << toString(type) << " s = " << s;
      EXPECT_NEAR(axial, advance * (s - turn), 1e-12 * turn) << toString(type) << " s = " << s;
    }
    // One turn advances exactly the step.
    EXPECT_NEAR((pts[2 * per] - pts[per]).norm(), p.helixStep, 1e-12 * turn) << toString(type);
  }
}

TEST(SuperHelixKinematics, NaturalHelixIsReconstructedExactlyAndStaysAtRest)
{
  // A helix with Darboux vector d (world), |d| = Ω, curvature κ and torsion τ has its axis
  // along d, radius κ/Ω² and advances τ/Ω along the axis per unit length: check those
  // invariants on the chained elements, then that 100 steps without load change nothing.
  for (int n : {1, 3, 10})
  {
    HairParameters p = HairParameters::preset(HairType::Curly);
    p.curvatureVariation = 0;
    StrandSpec spec = StrandSpec::uniform(0.3, n, p);
    spec.gravity.setZero();
    RootState root;
    root.position = Eigen::Vector3d(0.1, 0.2, -0.05);
    root.orientation =
        Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    spec.root = [root](double) { return root; };
    SuperHelix h;
    ASSERT_TRUE(h.initialize(spec).ok());
    const Eigen::Vector3d k = p.naturalCurvature();
    const double om = k.norm(), R = k[1] / (om * om), pitch = k[0] / om;
    const Eigen::Vector3d axis = root.orientation * k / om;
    // The centre of curvature at the root is along d × n0 (the principal normal).
    const Eigen::Vector3d c = root.position + R * axis.cross(root.orientation.col(0)).normalized();
    std::vector<Eigen::Vector3d> before;
    h.polyline(20, before);
    for (size_t i = 0; i < before.size(); ++i)
    {
      const double s = 0.3 * i / (before.size() - 1);
      const Eigen::Vector3d d = before[i] - c;
      const double axial = d.dot(axis);
      const double radial = (d - axial * axis).norm();
      // Round-off: ~n·100 flops on O(0.3 m) quantities: 1e-14 m is 30 ulp of the length.
      EXPECT_NEAR(axial, pitch * s, 1e-14) << "N = " << n << " s = " << s;
      EXPECT_NEAR(radial, R, 1e-14) << "N = " << n << " s = " << s;
    }
    // Both time steps: the rest shape is a fixed point of each (no force, no motion).
    for (Integrator integrator : {Integrator::SemiImplicit, Integrator::Midpoint})
    {
      StrandSpec stepped = spec;
      stepped.integrator = integrator;
      SuperHelix g;
      ASSERT_TRUE(g.initialize(stepped).ok());
      for (int i = 0; i < 100; ++i)
        ASSERT_TRUE(g.step(1.0 / 30).ok());
      std::vector<Eigen::Vector3d> after;
      g.polyline(20, after);
      for (size_t i = 0; i < before.size(); ++i)
        EXPECT_LT((after[i] - before[i]).norm(), 1e-15)
            << "N = " << n << " " << toString(integrator);
      EXPECT_EQ(g.energy().kinetic, 0.0);
    }
  }
}

TEST(SuperHelixKinematics, VelocityJacobianMatchesFiniteDifferencesOfTheForce)
{
  // C = ∂f/∂q̇ (the linearized velocity-dependent terms of the step) against central
  // differences of the generalized force in q̇. f is quadratic in q̇, so central
  // differences are exact up to round-off (~1e-16 |f| / ε); 1e-7 of max |C| is far above
  // that and far below the O(1) error of a missing or doubled term. Both ways of summing the
  // element moments are checked: per sample (threshold above any count) and from the Gram
  // matrix of the helix functions (threshold 1: every element).
  const Curled c;
  for (const int threshold : {1000, 1})
  {
    Curled withThreshold = c;
    withThreshold.spec.gramMinSamples = threshold;
    SuperHelix h = withThreshold.make(0.3, c.q);
    h.reconstruct();
    h.assemble();
    h.assembleVelocityJacobian();
    const Eigen::MatrixXd C = h.velocityJacobian();
    const double eps = 1e-2;
    for (int b = 0; b < 12; ++b)
    {
      SuperHelix hp, hm;
      ASSERT_TRUE(hp.initialize(c.spec, 0.3).ok());
      ASSERT_TRUE(hm.initialize(c.spec, 0.3).ok());
      Eigen::VectorXd vp = c.qd, vm = c.qd;
      vp[b] += eps;
      vm[b] -= eps;
      ASSERT_TRUE(hp.setState(c.q, vp).ok());
      ASSERT_TRUE(hm.setState(c.q, vm).ok());
      hp.assemble();
      hm.assemble();
      const Eigen::VectorXd fd = (hp.generalizedForce() - hm.generalizedForce()) / (2 * eps);
      EXPECT_LT((C.col(b) - fd).cwiseAbs().maxCoeff(), 1e-7 * C.cwiseAbs().maxCoeff())
          << "column " << b << ", Gram threshold " << threshold;
    }
  }
}

TEST(SuperHelixKinematics, VelocityJacobianIsTheSameSummedPerSampleOrFromTheGramMatrix)
{
  // The velocity Jacobian's element moments summed sample by sample and contracted from the
  // Gram matrix of the seven helix functions are the same sums in another order, so they
  // must agree to round-off: on strands of every preset (3 to 16 samples per element),
  // moving, after a second on the shaking head. Bound: 1e-12 of max |C| (each entry is a
  // sum of a few hundred products; measured agreement is reported on failure). The two ways
  // are two strands whose specs differ only in the threshold, put in the same state.
  for (int t = 0; t < 4; ++t)
  {
    StrandSpec spec = StrandSpec::uniform(0.3, 10, HairParameters::preset(HairType(t)));
    HeadShake shake;
    shake.frequency = 3;
    shake.amplitude = 0.5;
    spec.root = shake;
    SuperHelix h;
    ASSERT_TRUE(h.initialize(spec).ok());
    for (int i = 0; i < 30; ++i)
      ASSERT_TRUE(h.step(1.0 / 30).ok());
    Eigen::MatrixXd C[2];
    for (int way = 0; way < 2; ++way)
    {
      StrandSpec wayspec = spec;
      wayspec.gramMinSamples = way == 0 ? 1000 : 1;
      SuperHelix w;
      ASSERT_TRUE(w.initialize(wayspec, h.time()).ok());
      ASSERT_TRUE(w.setState(h.q(), h.qdot()).ok());
      w.reconstruct();
      w.assemble();
      w.assembleVelocityJacobian();
      C[way] = w.velocityJacobian();
    }
    const double scale = C[0].cwiseAbs().maxCoeff();
    ASSERT_GT(scale, 0);
    EXPECT_LT((C[1] - C[0]).cwiseAbs().maxCoeff(), 1e-12 * scale)
        << "preset " << t << ": " << (C[1] - C[0]).cwiseAbs().maxCoeff() / scale;
  }
}

TEST(SuperHelixKinematics, GeneralizedForceAfterReconstructIncludesTheWind)
{
  // f assembled after reconstruct() (without a step) must see the air a step sees: the part
  // that a wind w adds is ν ∫ J(s)ᵀ w(r(s)) ds, here summed over the public samples with
  // their weights and the public Jacobian, for a uniform wind and for a wind field. Bound:
  // round-off of sums of a few hundred terms, 1e-10 of max |Δf| (the two sides reconstruct J
  // by different kernels). Before the fix, f after reconstruct() ignored the wind.
  const Curled c;
  const Eigen::Vector3d uniform(0.7, -0.4, 1.1);
  const AirVelocityField field = [](const Eigen::Vector3d& x, double t)
  { return Eigen::Vector3d(std::sin(30 * x.x() + t), 0.5 * x.y() - 0.2, std::cos(20 * x.z())); };
  for (int variant = 0; variant < 2; ++variant)
  {
    StrandSpec still = c.spec, windy = c.spec;
    still.hair.airFriction = windy.hair.airFriction = 3e-5;
    if (variant == 0)
      windy.wind = uniform;
    else
      windy.windField = field;
    SuperHelix a, b;
    ASSERT_TRUE(a.initialize(still, 0.3).ok());
    ASSERT_TRUE(b.initialize(windy, 0.3).ok());
    ASSERT_TRUE(a.setState(c.q, c.qd).ok());
    ASSERT_TRUE(b.setState(c.q, c.qd).ok());
    a.reconstruct();
    b.reconstruct();
    a.assemble();
    b.assemble();
    const Eigen::VectorXd df = b.generalizedForce() - a.generalizedForce();
    Eigen::VectorXd expected = Eigen::VectorXd::Zero(df.size());
    for (const StrandSample& smp : b.samples())
    {
      const Eigen::Vector3d w = variant == 0 ? uniform : field(smp.position, 0.3);
      expected += smp.weight * windy.hair.airFriction * (b.jacobian(smp.s).transpose() * w);
    }
    const double scale = expected.cwiseAbs().maxCoeff();
    ASSERT_GT(scale, 0);
    EXPECT_LT((df - expected).cwiseAbs().maxCoeff(), 1e-10 * scale)
        << "variant " << variant << ": " << (df - expected).cwiseAbs().maxCoeff() / scale;
  }
}

TEST(SuperHelixKinematics, TensionStiffnessAfterAnotherStrandsAssemblyIsItsOwn)
{
  // The loads per sample that K_T needs are kept per thread by assemble(). Assembling
  // another strand in between (here a straighter one with fewer samples) must not leave K_T
  // reading the other strand's loads: it must equal the K_T of the documented order,
  // exactly (the same sums in the same order).
  StrandSpec curly = StrandSpec::uniform(0.3, 10, HairParameters::preset(HairType::Curly));
  StrandSpec smooth = StrandSpec::uniform(0.3, 3, HairParameters::preset(HairType::Smooth));
  smooth.gravity = Eigen::Vector3d(2, -20, 0); // other loads than a's
  SuperHelix a, b;
  ASSERT_TRUE(a.initialize(curly).ok());
  ASSERT_TRUE(b.initialize(smooth).ok());
  ASSERT_GT(a.samples().size(), b.samples().size());
  const double h = 1.0 / 30;
  a.reconstruct();
  a.assemble();
  a.assembleTensionStiffness(h);
  const Eigen::MatrixXd expected = a.tensionStiffness();
  ASSERT_GT(expected.cwiseAbs().maxCoeff(), 0); // a hanging strand is in tension
  a.assemble();
  b.assemble();
  a.assembleTensionStiffness(h);
  EXPECT_EQ((a.tensionStiffness() - expected).cwiseAbs().maxCoeff(), 0);
}

TEST(SuperHelixKinematics, TensionStiffnessIsItsDefinitionOnCurledStrands)
{
  // K_T = ∫ T⁺(s) J_ω(s)ᵀ (I − n0 n0ᵀ) J_ω(s) ds (docs/super-helix.md), evaluated here from
  // its definition with public pieces only, on curled strands (where the own element's
  // J_ω = F0 G(u) and n0 = F0 E(u) e0 are not trivial): a strand at rest in its natural shape
  // on a fixed root, hanging along its helix axis, so that the load is ρS g and the tension
  // at s is n0(s) · ρS g (L − s);
  // J_ω from central differences of frame(s) in q, δF Fᵀ = [δθ]× (ε = 1e-6 1/m: truncation
  // ~(ε s)² ≈ 1e-14, round-off ~1e-16 / (ε s) ≈ 1e-9 relative); the same samples and weights
  // (samples()). h → ∞ leaves no tension to the explicit part. Tolerance 1e-6 of max |K_T|.
  for (const HairType type : {HairType::Wavy, HairType::Curly, HairType::Fuzzy})
  {
    HairParameters hair = HairParameters::preset(type);
    hair.curvatureVariation = 0;
    StrandSpec spec = StrandSpec::uniform(0.1, 5, hair);
    spec.gravity = Eigen::Vector3d(9.81, 0, 0); // along the helix axis (the root's tangent +x)
    SuperHelix h;
    ASSERT_TRUE(h.initialize(spec).ok());
    const Eigen::MatrixXd Kt = tensionStiffnessOf(h, 1e30);
    const int m = 3 * h.elementCount();
    const Eigen::VectorXd q0 = h.q(), zero = Eigen::VectorXd::Zero(m);
    const std::vector<StrandSample> samples = h.samples();
    const Eigen::Vector3d load = hair.linearDensity() * spec.gravity;
    std::vector<Eigen::Matrix3Xd> Jw(samples.size(), Eigen::Matrix3Xd::Zero(3, m));
    const double eps = 1e-6;
    for (int b = 0; b < m; ++b)
    {
      SuperHelix hp = h, hm = h;
      Eigen::VectorXd qp = q0, qm = q0;
      qp[b] += eps;
      qm[b] -= eps;
      ASSERT_TRUE(hp.setState(qp, zero).ok());
      ASSERT_TRUE(hm.setState(qm, zero).ok());
      for (size_t i = 0; i < samples.size(); ++i)
      {
        const Eigen::Matrix3d dF = (hp.frame(samples[i].s) - hm.frame(samples[i].s)) / (2 * eps) *
                                   h.frame(samples[i].s).transpose();
        Jw[i].col(b) =
            0.5 * Eigen::Vector3d(dF(2, 1) - dF(1, 2), dF(0, 2) - dF(2, 0), dF(1, 0) - dF(0, 1));
      }
    }
    Eigen::MatrixXd ref = Eigen::MatrixXd::Zero(m, m);
    int tense = 0;
    for (size_t i = 0; i < samples.size(); ++i)
    {
      const Eigen::Vector3d n0 = h.frame(samples[i].s).col(0);
      const double T = n0.dot(load * (h.length() - samples[i].s));
      if (!(T > 0))
        continue;
      ++tense;
      const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - n0 * n0.transpose();
      ref += samples[i].weight * T * Jw[i].transpose() * P * Jw[i];
    }
    const double scale = ref.cwiseAbs().maxCoeff();
    ASSERT_GT(tense, 0);
    ASSERT_GT(scale, 0);
    EXPECT_LT((Kt - ref).cwiseAbs().maxCoeff(), 1e-6 * scale)
        << "preset " << static_cast<int>(type) << ": " << (Kt - ref).cwiseAbs().maxCoeff() / scale
        << " of max |K_T|, " << tense << " of " << samples.size() << " samples in tension";
    std::printf("preset %d: K_T against its definition %.1e of max |K_T| (%d of %zu samples in "
                "tension)\n",
                static_cast<int>(type), (Kt - ref).cwiseAbs().maxCoeff() / scale, tense,
                samples.size());
  }
}

TEST(SuperHelixKinematics, TensionStiffnessIsTheLoadStiffnessOfAStraightHangingStrand)
{
  // K_T keeps the tension part of the loads' stiffness −∂f/∂q. For a straight strand hanging
  // at rest along a dead load (gravity along the tangent, plus a tip force along it) the
  // tail force is along the tangent everywhere, the dropped (shear) part vanishes, and
  // K_T must equal the whole −∂f/∂q, which central differences of the generalized force
  // give (ε = 1e-4 1/m on elements of 2.5 cm: truncation ~(εℓ)² ≈ 1e-11, round-off
  // ~1e-16/(εℓ) ≈ 4e-11 relative; tolerance 1e-7 of max |K_T|). With h → ∞ no tension is
  // left to the explicit part (T⁺ = T).
  HairParameters p = plainHair();
  StrandSpec spec = StrandSpec::uniform(0.1, 4, p);
  spec.gravity = Eigen::Vector3d(9.81, 0, 0); // along the tangent n0 = +x of the root frame
  spec.tipForce = Eigen::Vector3d(2e-6, 0, 0);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(12);
  auto force = [&](const Eigen::VectorXd& q)
  {
    SuperHelix h;
    EXPECT_TRUE(h.initialize(spec).ok());
    EXPECT_TRUE(h.setState(q, zero).ok());
    h.assemble();
    return Eigen::VectorXd(h.generalizedForce());
  };
  SuperHelix h;
  ASSERT_TRUE(h.initialize(spec).ok());
  const Eigen::MatrixXd Kt = tensionStiffnessOf(h, 1e30);
  const double scale = Kt.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0);
  const double eps = 1e-4;
  for (int b = 0; b < 12; ++b)
  {
    Eigen::VectorXd qp = zero, qm = zero;
    qp[b] += eps;
    qm[b] -= eps;
    const Eigen::VectorXd fd = -(force(qp) - force(qm)) / (2 * eps);
    EXPECT_LT((Kt.col(b) - fd).cwiseAbs().maxCoeff(), 1e-7 * scale) << b << "\n"
                                                                    << Kt.col(b).transpose() << "\n"
                                                                    << fd.transpose();
  }
  // Positive semi-definite (T⁺ >= 0), and at a step of 1/30 s the tension of this 10 cm
  // strand, ρS g L at most, is below the explicit share ρS ℓ²/(4 h²) = ρS · 0.14 m²/s² only
  // near the tip; at 1 ms it is below it everywhere and K_T vanishes.
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(Kt);
  EXPECT_GT(es.eigenvalues().minCoeff(), -1e-12 * scale);
  h.assembleTensionStiffness(1e-3);
  EXPECT_EQ(h.tensionStiffness().cwiseAbs().maxCoeff(), 0.0);
}
