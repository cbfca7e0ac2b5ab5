// The Gauss–Legendre rules and the per-element choice of a rule (Core/helix/Quadrature).
#include "helix/Quadrature.h"
#include "superhelix/SuperHelix.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace hair;

TEST(Quadrature, GaussRulesIntegratePolynomialsOfDegree2nMinus1)
{
  // ∫0^1 x^d dx = 1/(d + 1), exact for d <= 2n − 1; the first degree beyond is not.
  // Round-off of n products and sums of O(1) terms: 1e-14.
  for (int n = 1; n <= MaxGaussPoints; ++n)
  {
    const GaussRule& r = gaussLegendre(n);
    ASSERT_EQ(r.points, n);
    double sumW = 0;
    for (int i = 0; i < n; ++i)
    {
      EXPECT_GT(r.w[i], 0) << "n = " << n;
      if (i > 0)
        EXPECT_GT(r.x[i], r.x[i - 1]) << "n = " << n;
      sumW += r.w[i];
    }
    EXPECT_NEAR(sumW, 1.0, 1e-14) << "n = " << n;
    for (int d = 0; d <= 2 * n; ++d)
    {
      double sum = 0;
      for (int i = 0; i < n; ++i)
        sum += r.w[i] * std::pow(r.x[i], d);
      if (d <= 2 * n - 1)
        EXPECT_NEAR(sum, 1.0 / (d + 1), 1e-14) << "n = " << n << " degree " << d;
      else if (n <= 8) // remainder of x^(2n): (n!)⁴/((2n+1)((2n)!)²) >= 3.6e-10 for n <= 8
        EXPECT_GT(std::abs(sum - 1.0 / (d + 1)), 1e-14) << "n = " << n;
    }
  }
  // The 4-point rule of the earlier versions (tabulated, Abramowitz & Stegun table 25.4).
  const GaussRule& r4 = gaussLegendre(4);
  EXPECT_NEAR(r4.x[0], 0.5 - 0.5 * 0.8611363115940526, 1e-15);
  EXPECT_NEAR(r4.x[1], 0.5 - 0.5 * 0.3399810435848563, 1e-15);
  EXPECT_NEAR(r4.w[0], 0.5 * 0.3478548451374538, 1e-15);
  EXPECT_NEAR(r4.w[1], 0.5 * 0.6521451548625461, 1e-15);
}

TEST(Quadrature, ChooserKeepsTheBoundAndReproducesTheFormerRule)
{
  const double tol = QuadratureChooser::defaultTolerance();
  EXPECT_NEAR(tol, 5.3e-6, 0.05e-6); // c_4 π⁸
  const QuadratureChooser fixed4(tol, 4, 4), chooser;
  for (double turning = 0; turning < 60; turning += 0.01)
  {
    // The former rule: 4 points per π/2 of turning.
    const ElementRule f = fixed4.choose(turning);
    EXPECT_EQ(f.points, 4);
    EXPECT_EQ(f.intervals, std::max(1, static_cast<int>(std::ceil(turning / (M_PI / 2) - 1e-12))))
        << turning;
    // The chosen rule never needs more samples and keeps its bound below the tolerance.
    const ElementRule c = chooser.choose(turning);
    EXPECT_LE(c.samples(), f.samples()) << turning;
    EXPECT_GE(c.points, 3);
    const double theta = 2 * turning / c.intervals;
    EXPECT_LE(gaussRemainderLog(c.points) + 2 * c.points * std::log(std::max(theta, 1e-300)),
              std::log(tol) + 1e-12)
        << turning;
  }
  EXPECT_EQ(chooser.choose(0).samples(), 3); // straight elements: 3 points are exact
  // A non-finite turning (never reached by a step, which refuses such states) gives the
  // smallest rule instead of an undefined interval count.
  EXPECT_EQ(chooser.choose(std::nan("")).samples(), 3);
  EXPECT_EQ(chooser.choose(INFINITY).samples(), 3);
}

namespace
{
struct Operators
{
  Eigen::MatrixXd M, C;
  Eigen::VectorXd f;
  size_t samples;
};

Operators operators(StrandSpec spec, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                    double tolerance, int points)
{
  spec.quadratureTolerance = tolerance;
  spec.quadraturePoints = points;
  SuperHelix h;
  EXPECT_TRUE(h.initialize(spec, 0.1).ok());
  EXPECT_TRUE(h.setState(q, qd).ok());
  h.reconstruct();
  h.assemble();
  h.assembleVelocityJacobian();
  return {h.massMatrix(), h.velocityJacobian(), h.generalizedForce(), h.samples().size()};
}

double relative(const Eigen::MatrixXd& a, const Eigen::MatrixXd& ref)
{
  return (a - ref).cwiseAbs().maxCoeff() / ref.cwiseAbs().maxCoeff();
}
} // namespace

TEST(Quadrature, OperatorsAgreeWithATightRuleWithinTheTolerance)
{
  // M, f and C of deformed, moving strands of every preset (root moving and spinning, wind)
  // with the default rule against the same with the bound at 1e-15. The a priori bound
  // (5.3e-6) is the tolerance; measured worst over these states: 5.7e-7 (f, wavy; 6.6e-7,
  // f, curly, before reconstruct() set the wind: f then saw still air). The former fixed
  // rule is measured too and must not need fewer samples.
  std::mt19937 g(7);
  std::normal_distribution<double> normal(0, 1);
  const double tol = QuadratureChooser::defaultTolerance();
  for (HairType type : {HairType::Smooth, HairType::Wavy, HairType::Curly, HairType::Fuzzy})
  {
    for (int trial = 0; trial < 5; ++trial)
    {
      StrandSpec spec = StrandSpec::uniform(0.3, 10, HairParameters::preset(type));
      spec.wind = Eigen::Vector3d(0.5, 0.2, -0.3);
      RootState root;
      root.velocity = Eigen::Vector3d(0.3, -0.2, 0.1);
      root.acceleration = Eigen::Vector3d(-2, 1, 3);
      root.angularVelocity = Eigen::Vector3d(1, 2, -1);
      root.angularAcceleration = Eigen::Vector3d(5, -3, 2);
      spec.root = [root](double) { return root; };
      SuperHelix rest;
      ASSERT_TRUE(rest.initialize(spec, 0.1).ok());
      Eigen::VectorXd q = rest.restCurvature(), qd(q.size());
      const double scale = std::max(20.0, q.norm() / std::sqrt(double(q.size())));
      for (int i = 0; i < q.size(); ++i)
      {
        q[i] += 0.5 * scale * normal(g);
        qd[i] = 5 * scale * normal(g);
      }
      const Operators ref = operators(spec, q, qd, 1e-15, 0);
      const Operators chosen = operators(spec, q, qd, tol, 0);
      const Operators former = operators(spec, q, qd, tol, 4);
      const char* name = toString(type);
      EXPECT_LT(relative(chosen.M, ref.M), tol) << name;
      EXPECT_LT(relative(chosen.f, ref.f), tol) << name;
      EXPECT_LT(relative(chosen.C, ref.C), tol) << name;
      EXPECT_LT(relative(former.M, ref.M), tol) << name;
      EXPECT_LE(chosen.samples, former.samples) << name;
    }
  }
}

TEST(Quadrature, BadSettingsAreRefused)
{
  StrandSpec spec = StrandSpec::uniform(0.3, 5, HairParameters::preset(HairType::Wavy));
  SuperHelix h;
  spec.quadratureTolerance = 0;
  Status st = h.initialize(spec);
  EXPECT_FALSE(st.ok());
  EXPECT_NE(st.message().find("quadratureTolerance"), std::string::npos) << st.message();
  spec.quadratureTolerance = std::nan("");
  EXPECT_FALSE(h.initialize(spec).ok());
  spec.quadratureTolerance = 1e-8;
  spec.quadraturePoints = 2;
  st = h.initialize(spec);
  EXPECT_FALSE(st.ok());
  EXPECT_NE(st.message().find("quadraturePoints"), std::string::npos) << st.message();
  spec.quadraturePoints = 4;
  EXPECT_TRUE(h.initialize(spec).ok());
}
