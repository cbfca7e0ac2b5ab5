// The Super-Helix model against Euler–Bernoulli beam theory (references in
// docs/super-helix.md): cantilever frequencies f_n = (β_n L)² / (2π L²) · √(EI / ρS) with
// β1 L = 1.8751041, β2 L = 4.6940911, and the static tip deflection ρ S g L⁴ / (8 E I).
#include "IntegratorNames.h"
#include "superhelix/SuperHelix.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

using namespace hair;

namespace
{
std::string sci(double v)
{
  std::ostringstream s;
  s.precision(4);
  s << std::scientific << v;
  return s.str();
}

constexpr double Beta1L = 1.8751041, Beta2L = 4.6940911;
constexpr double Length = 0.1;

HairParameters roundHair()
{
  HairParameters p = HairParameters::preset(HairType::Smooth);
  p.curvatureVariation = 0;
  p.internalFriction = 0;
  p.airFriction = 0;
  return p;
}

double ebFrequency(double betaL, const HairParameters& p)
{
  return betaL * betaL / (2 * M_PI * Length * Length) *
         std::sqrt(p.stiffness()[1] / p.linearDensity());
}

struct Modes
{
  std::vector<double> f; // ascending
  std::vector<Eigen::VectorXd> shapes;
};

// Linearized about the straight clamped rod: M(0) ẍ + 𝕂 x = 0 restricted to κ1, which
// decouples from τ and κ2 there. Solved as M x = λ 𝕂 x (𝕂 is SPD), ω² = 1/λ.
Modes bendingModes(int n, const std::vector<double>& lengths = {})
{
  StrandSpec spec = StrandSpec::uniform(Length, n, roundHair());
  if (!lengths.empty())
    spec.elementLengths = lengths;
  spec.gravity.setZero();
  SuperHelix h;
  EXPECT_TRUE(h.initialize(spec).ok());
  h.reconstruct();
  h.assemble();
  const int m = h.elementCount();
  Eigen::MatrixXd Mb(m, m), Kb = Eigen::MatrixXd::Zero(m, m);
  for (int a = 0; a < m; ++a)
  {
    for (int b = 0; b < m; ++b)
      Mb(a, b) = h.massMatrix()(3 * a + 1, 3 * b + 1);
    Kb(a, a) = h.stiffnessDiagonal()[3 * a + 1];
  }
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(Mb, Kb);
  Modes out;
  for (int i = m - 1; i >= 0; --i)
  {
    out.f.push_back(1.0 / std::sqrt(es.eigenvalues()[i]) / (2 * M_PI));
    Eigen::VectorXd full = Eigen::VectorXd::Zero(3 * m);
    for (int a = 0; a < m; ++a)
      full[3 * a + 1] = es.eigenvectors()(a, i);
    out.shapes.push_back(full);
  }
  return out;
}

// Least-squares slope of log(err) against log(N).
double order(const std::vector<int>& ns, const std::vector<double>& err)
{
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double k = static_cast<double>(ns.size());
  for (size_t i = 0; i < ns.size(); ++i)
  {
    const double x = std::log(static_cast<double>(ns[i])), y = std::log(std::abs(err[i]));
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  return -(k * sxy - sx * sy) / (k * sxx - sx * sx);
}
} // namespace

TEST(SuperHelixEulerBernoulli, FrequenciesConvergeAtSecondOrder)
{
  const HairParameters p = roundHair();
  const double f1 = ebFrequency(Beta1L, p), f2 = ebFrequency(Beta2L, p);
  const std::vector<int> ns = {5, 10, 20, 40};
  std::vector<double> e1, e2;
  for (int n : ns)
  {
    const Modes m = bendingModes(n);
    e1.push_back(m.f[0] / f1 - 1);
    e2.push_back(m.f[1] / f2 - 1);
    RecordProperty("f1_error_N" + std::to_string(n), sci(e1.back()));
    RecordProperty("f2_error_N" + std::to_string(n), sci(e2.back()));
  }
  // Issue 3: at N = 10, f1 within 0.3 % and f2 within 2 % of Euler–Bernoulli.
  EXPECT_LT(std::abs(e1[1]), 3e-3) << e1[1];
  EXPECT_LT(std::abs(e2[1]), 2e-2) << e2[1];
  // Piecewise-constant curvature is a second-order discretization (midpoint-like): the
  // fitted order over N = 5…40 must be 2 within ±0.15 (a first-order scheme gives 1).
  const double o1 = order(ns, e1), o2 = order(ns, e2);
  RecordProperty("order_f1", sci(o1));
  RecordProperty("order_f2", sci(o2));
  EXPECT_NEAR(o1, 2.0, 0.15) << "errors " << e1[0] << " " << e1[1] << " " << e1[2] << " " << e1[3];
  EXPECT_NEAR(o2, 2.0, 0.15) << "errors " << e2[0] << " " << e2[1] << " " << e2[2] << " " << e2[3];
}

TEST(SuperHelixEulerBernoulli, UnequalElementsStillConverge)
{
  // Lengths alternating 2:1 must still give f1 within 1 % at N = 10 (the same order of
  // error as equal elements: the largest element, 4/3 of the mean, bounds it, (4/3)² · 0.2 %).
  std::vector<double> l;
  for (int i = 0; i < 10; ++i)
    l.push_back((i % 2 == 0 ? 2.0 : 1.0) * Length / 15);
  const Modes m = bendingModes(10, l);
  EXPECT_LT(std::abs(m.f[0] / ebFrequency(Beta1L, roundHair()) - 1), 1e-2);
}

class SuperHelixPeriod : public ::testing::TestWithParam<Integrator>
{
};

TEST_P(SuperHelixPeriod, OfSmallFreeOscillationByTimeIntegration)
{
  const int n = 10;
  const HairParameters p = roundHair();
  const Modes m = bendingModes(n);
  const double f1 = ebFrequency(Beta1L, p);
  const double period = 1 / m.f[0];
  StrandSpec spec = StrandSpec::uniform(Length, n, p);
  spec.gravity.setZero();
  spec.integrator = GetParam();
  SuperHelix h;
  ASSERT_TRUE(h.initialize(spec).ok());
  // First mode shape, tip amplitude ~1e-4 L: nonlinear frequency shifts ~(1e-4)² vanish.
  Eigen::VectorXd q0 = m.shapes[0].normalized() * 1e-3; // linear regime
  ASSERT_TRUE(h.setState(q0, Eigen::VectorXd::Zero(3 * n)).ok());
  const double scale = 1e-5 / std::abs(h.position(Length).z());
  ASSERT_TRUE(h.setState(q0 * scale, Eigen::VectorXd::Zero(3 * n)).ok());
  // dt = T/2000: the scheme's period error O((ω dt)²) ~ 1e-5 is negligible against 1 %.
  const double dt = period / 2000;
  std::vector<double> crossings;
  double zPrev = h.position(Length).z(), tPrev = 0;
  while (crossings.size() < 9)
  {
    const Status st = h.step(dt);
    ASSERT_TRUE(st.ok()) << st.message();
    const double z = h.position(Length).z();
    if ((z > 0) != (zPrev > 0))
      crossings.push_back(tPrev + dt * zPrev / (zPrev - z));
    zPrev = z;
    tPrev = h.time();
    ASSERT_LT(h.time(), 10 * period);
  }
  const double measured = 2 * (crossings.back() - crossings.front()) / (crossings.size() - 1);
  RecordProperty("period_error", sci(measured * f1 - 1));
  // Issue 3: within 1 % of Euler–Bernoulli's f1 (the model's own f1 is 0.2 % off).
  EXPECT_LT(std::abs(measured * f1 - 1), 1e-2) << measured * f1 - 1;
}

INSTANTIATE_TEST_SUITE_P(Integrators, SuperHelixPeriod,
                         ::testing::Values(Integrator::SemiImplicit, Integrator::Midpoint,
                                           Integrator::Bdf2),
                         [](const ::testing::TestParamInfo<Integrator>& info)
                         { return integratorTestName(info.param); });

TEST(SuperHelixEulerBernoulli, StiffCantileverTipDeflection)
{
  // Horizontal clamped rod (tangent +x, gravity −y), E raised so that δ/L = 1e-3: the
  // geometric nonlinearity then changes δ by O((δ/L)²) = 1e-6, so linear theory is the
  // reference. The semi-implicit step's fixed point (q̇ = 0) is the static equilibrium;
  // large steps (h = 1 s) damp everything numerically and reach it.
  HairParameters p = roundHair();
  const double g = 9.81;
  const double deflectionRatio = 1e-3;
  p.youngModulus = p.linearDensity() * g * std::pow(Length, 3) /
                   (8 * deflectionRatio * p.stiffness()[2] / p.youngModulus);
  const double expected = p.linearDensity() * g * std::pow(Length, 4) / (8 * p.stiffness()[2]);
  for (int n : {5, 10})
  {
    StrandSpec spec = StrandSpec::uniform(Length, n, p);
    spec.gravity = Eigen::Vector3d(0, -g, 0);
    SuperHelix h;
    ASSERT_TRUE(h.initialize(spec).ok());
    for (int i = 0; i < 60; ++i)
      ASSERT_TRUE(h.step(1.0).ok());
    EXPECT_LT(h.qdot().norm(), 1e-12 * h.q().norm() + 1e-300);
    const double delta = -h.position(Length).y();
    RecordProperty("deflection_error_N" + std::to_string(n), sci(delta / expected - 1));
    if (n == 10)
      EXPECT_LT(std::abs(delta / expected - 1), 1e-2) << delta / expected - 1; // issue 3
    else
      EXPECT_LT(std::abs(delta / expected - 1), 2e-2) << delta / expected - 1; // ~4× N = 10
    // The second-order step does not damp (it would oscillate about the equilibrium for
    // ever from rest), but the equilibrium is its fixed point too: started there it stays,
    // within round-off of the step's sums (1e-12 of the deflection).
    StrandSpec second = spec;
    second.integrator = Integrator::Midpoint;
    SuperHelix g;
    ASSERT_TRUE(g.initialize(second).ok());
    ASSERT_TRUE(g.setState(h.q(), Eigen::VectorXd::Zero(3 * n)).ok());
    for (int i = 0; i < 60; ++i)
      ASSERT_TRUE(g.step(1.0).ok());
    EXPECT_EQ(g.lastFirstOrder(), 0);
    EXPECT_NEAR(-g.position(Length).y(), delta, 1e-12 * delta);
  }
}
