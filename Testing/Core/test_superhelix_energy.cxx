// Energy budget and long-run stability of the Super-Helix step (docs/super-helix.md).
// Budget: Δ(kinetic + elastic + gravitational) = root work + wind work + contact work
// − friction − air dissipation + residual, with the residual the integrator's own share.
#include "HeadShake.h"
#include "IntegratorNames.h"
#include "superhelix/SuperHelix.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <tuple>
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

// Fitted order p of |r(dt)| ~ dt^p from successive halvings.
double fittedOrder(const std::vector<double>& r)
{
  double sum = 0;
  for (size_t i = 1; i < r.size(); ++i)
    sum += std::log2(std::abs(r[i - 1] / r[i]));
  return sum / (r.size() - 1);
}

Eigen::Matrix3d hangingFrame()
{
  // n0 down (−y), n1 = +x, n2 = n0 × n1 = +z.
  Eigen::Matrix3d f;
  f.col(0) = Eigen::Vector3d(0, -1, 0);
  f.col(1) = Eigen::Vector3d(1, 0, 0);
  f.col(2) = f.col(0).cross(f.col(1));
  return f;
}
} // namespace

namespace
{
// A 30 cm horizontal strand, no friction, no air, no wind, fixed root, falling under
// gravity for `seconds` in steps of dt = seconds / steps. The residual, the energy the fall
// exchanged (gravitational energy released), and the steps taken first order.
struct Fall
{
  double residual = 0, released = 0;
  long firstOrder = 0;
};
Fall frictionlessFall(Integrator integrator, double seconds, int steps)
{
  HairParameters p = HairParameters::preset(HairType::Smooth);
  p.curvatureVariation = 0;
  p.internalFriction = 0;
  p.airFriction = 0;
  StrandSpec spec = StrandSpec::uniform(0.3, 10, p);
  spec.integrator = integrator;
  SuperHelix h;
  EXPECT_TRUE(h.initialize(spec).ok());
  const double e0 = h.energy().mechanical(), g0 = h.energy().gravitational;
  Fall f;
  for (int i = 0; i < steps; ++i)
  {
    const Status st = h.step(seconds / steps);
    EXPECT_TRUE(st.ok()) << st.message();
    if (!st)
      return f;
    f.firstOrder += h.lastFirstOrder();
  }
  const EnergyReport& e = h.energy();
  EXPECT_EQ(e.total.frictionDissipated, 0.0);
  EXPECT_EQ(e.total.airDissipated, 0.0);
  EXPECT_EQ(e.total.rootWork, 0.0);
  // The budget closes by definition of the residual; check the bookkeeping to round-off.
  EXPECT_NEAR(e.mechanical() - e0, e.total.residual, 1e-12 * std::abs(e0 - e.gravitational));
  f.residual = e.total.residual;
  f.released = g0 - e.gravitational;
  return f;
}
} // namespace

TEST(SuperHelixEnergy, ConservedUpToAFirstOrderResidual)
{
  // The strand falls 0.5 s. The semi-implicit step is first order (backward Euler in the
  // elastic force; the loads' configuration dependence explicit up to the tension an explicit
  // step carries, which at these dt is all of it; velocity terms half implicit), so its energy
  // error over a fixed time is O(dt): the residual must halve with dt.
  std::vector<double> residuals;
  double exchanged = 0;
  for (int steps : {500, 1000, 2000, 4000})
  {
    const Fall f = frictionlessFall(Integrator::SemiImplicit, 0.5, steps);
    EXPECT_EQ(f.firstOrder, steps);
    residuals.push_back(f.residual);
    exchanged = f.released;
    RecordProperty("residual_dt_1/" + std::to_string(2 * steps), sci(f.residual));
  }
  const double order = fittedOrder(residuals);
  RecordProperty("residual_order", sci(order));
  // First order: 1 ± 0.2 (a second-order scheme would give 2, an inconsistent one 0).
  EXPECT_NEAR(order, 1.0, 0.2) << residuals[0] << " " << residuals[1] << " " << residuals[2] << " "
                               << residuals[3];
  // At dt = 1/8000 s the residual is below 2 % of the energy the fall exchanged.
  EXPECT_LT(std::abs(residuals.back()), 2e-2 * exchanged);
}

TEST(SuperHelixEnergy, MidpointStepConservesUpToASecondOrderResidual)
{
  // The same fall with the second-order step: the implicit midpoint rule, linearized once
  // about the predicted midpoint, has a local error O(dt³), so the residual over a fixed time
  // must fall four times per halving of dt. dt = 1/240 … 1/1920 s, where no step is declined
  // (coarser steps do not resolve the chain's second pendulum mode: 11 % at 1/120 s).
  std::vector<double> residuals;
  double exchanged = 0;
  for (int steps : {120, 240, 480, 960})
  {
    const Fall f = frictionlessFall(Integrator::Midpoint, 0.5, steps);
    EXPECT_EQ(f.firstOrder, 0) << "dt = 1/" << 2 * steps;
    residuals.push_back(f.residual);
    exchanged = f.released;
    RecordProperty("residual_dt_1/" + std::to_string(2 * steps), sci(f.residual));
  }
  const double order = fittedOrder(residuals);
  RecordProperty("residual_order", sci(order));
  // Second order: 2 ± 0.2, the first-order test's margin (measured 1.98).
  EXPECT_NEAR(order, 2.0, 0.2) << residuals[0] << " " << residuals[1] << " " << residuals[2] << " "
                               << residuals[3];
  // At dt = 1/1920 s below 0.2 % of the energy exchanged (measured 0.04 %; the semi-implicit
  // step needs 1/8000 s for 0.4 %).
  EXPECT_LT(std::abs(residuals.back()), 2e-3 * exchanged);
}

TEST(SuperHelixEnergy, FrictionlessStrandReleasedForTwoSeconds)
{
  // Issue 23's strand: 2 s, through the whip at ~0.75 s, where the tip's curvature rates
  // reach 1e4 1/(m·s) (even at 1/7680 s). The second-order step closes the budget to 5 % of
  // the gravitational energy released once its steps resolve the whip (1/1920 s: 0.15 %),
  // where the semi-implicit step still removes half of it (1/3840 s: 49 %). At 1/30 s no
  // step resolves it: both remove most of the energy (the midpoint step declines the steps
  // that would create energy, 9 of 60), recorded here and in docs/super-helix.md.
  const Fall coarseSemi = frictionlessFall(Integrator::SemiImplicit, 2, 60);
  const Fall coarseMid = frictionlessFall(Integrator::Midpoint, 2, 60);
  RecordProperty("semi_implicit_1/30_residual_share",
                 sci(coarseSemi.residual / coarseSemi.released));
  RecordProperty("midpoint_1/30_residual_share", sci(coarseMid.residual / coarseMid.released));
  RecordProperty("midpoint_1/30_first_order_steps", std::to_string(coarseMid.firstOrder));
  const Fall fineMid = frictionlessFall(Integrator::Midpoint, 2, 3840);
  const Fall fineSemi = frictionlessFall(Integrator::SemiImplicit, 2, 7680);
  RecordProperty("midpoint_1/1920_residual_share", sci(fineMid.residual / fineMid.released));
  RecordProperty("semi_implicit_1/3840_residual_share", sci(fineSemi.residual / fineSemi.released));
  EXPECT_LT(std::abs(fineMid.residual), 0.05 * fineMid.released);
  EXPECT_EQ(fineMid.firstOrder, 0);
  EXPECT_GT(std::abs(fineSemi.residual), 0.4 * fineSemi.released);
  // Neither step creates energy at 1/30 s (the midpoint step's guard).
  EXPECT_LT(coarseMid.residual, 0.0);
  EXPECT_LT(coarseSemi.residual, 0.0);
}

class SuperHelixEnergyBudget : public ::testing::TestWithParam<Integrator>
{
};

TEST_P(SuperHelixEnergyBudget, ClosesWithFrictionAirWindAndMovingRoot)
{
  // Every flow on: internal friction, air drag against a wind that varies in space and
  // time, and a root on a shaking head. If any reported flow were wrong by O(1), the
  // residual would not shrink with dt; it must shrink at the order of the step: 1 for the
  // semi-implicit step's own dissipation, 2 for the midpoint step, whose flows are midpoint
  // quadratures (a flow computed at first order would pin the fitted order at 1).
  // BDF2's flows are taken at the step's end (a rectangle rule, whose error over a run is h/2
  // times the change of each flow's power), so its residual shrinks at order 1 too, from a
  // smaller constant than the semi-implicit step's own dissipation.
  const Integrator integrator = GetParam();
  const bool midpoint = integrator == Integrator::Midpoint;
  const bool bdf = integrator == Integrator::Bdf2;
  HairParameters p = HairParameters::preset(HairType::Wavy);
  std::vector<double> residuals;
  double rootWork = 0, dissipated = 0, wind = 0;
  for (int steps : {300, 600, 1200, 2400})
  {
    StrandSpec spec = StrandSpec::uniform(0.2, 8, p);
    spec.integrator = integrator;
    HeadShake shake;
    shake.attachmentFrame = hangingFrame();
    spec.root = shake;
    spec.windField = [](const Eigen::Vector3d& x, double t)
    { return Eigen::Vector3d(2.0 + std::sin(5 * t), 0.5 * x.y(), 1.0); };
    SuperHelix h;
    ASSERT_TRUE(h.initialize(spec).ok());
    for (int i = 0; i < steps; ++i)
    {
      ASSERT_TRUE(h.step(0.3 / steps).ok());
      // BDF2's first step is semi-implicit (no history yet).
      EXPECT_EQ(h.lastFirstOrder(), midpoint || (bdf && i > 0) ? 0 : 1);
    }
    const EnergyTerms& t = h.energy().total;
    EXPECT_GT(t.frictionDissipated, 0.0);
    EXPECT_GT(t.airDissipated, 0.0);
    residuals.push_back(t.residual);
    rootWork = t.rootWork;
    wind = t.windWork;
    dissipated = t.frictionDissipated + t.airDissipated;
  }
  RecordProperty("root_work", sci(rootWork));
  RecordProperty("wind_work", sci(wind));
  RecordProperty("dissipated", sci(dissipated));
  RecordProperty("residual_finest", sci(residuals.back()));
  const double order = fittedOrder(residuals);
  RecordProperty("residual_order", sci(order));
  EXPECT_NEAR(order, midpoint ? 2.0 : 1.0, 0.25)
      << residuals[0] << " " << residuals[1] << " " << residuals[2] << " " << residuals[3];
  // At the finest step the residual is a few % of the largest flow.
  EXPECT_LT(std::abs(residuals.back()), 0.05 * std::max(std::abs(rootWork), dissipated));
}

INSTANTIATE_TEST_SUITE_P(Integrators, SuperHelixEnergyBudget,
                         ::testing::Values(Integrator::SemiImplicit, Integrator::Midpoint,
                                           Integrator::Bdf2),
                         [](const ::testing::TestParamInfo<Integrator>& info)
                         { return integratorTestName(info.param); });

namespace
{
// Issue 3: a strand of length L, N elements, rooted on a head turning ±30° at 3 Hz, stepped
// with the public step(1/30 s) for `seconds`: every step succeeds without sub-steps
// (lastSubsteps() == 1), stays finite, the mechanical energy stays bounded, and the
// strand keeps its length. Returns the largest energy gain over the bound.
double shakeAtOneThirtieth(HairType type, Integrator integrator, int n, double seconds)
{
  const HairParameters p = HairParameters::preset(type);
  const double L = 0.3;
  StrandSpec spec = StrandSpec::uniform(L, n, p);
  spec.name = toString(type);
  spec.integrator = integrator;
  HeadShake shake;
  shake.attachmentFrame = hangingFrame();
  spec.root = shake;
  SuperHelix h;
  EXPECT_TRUE(h.initialize(spec).ok());
  const double m = p.linearDensity() * L;
  // Energy scale of the drive: the strand moving rigidly with the head's largest angular
  // speed at its farthest point. An instability grows exponentially and passes 100× that
  // within a few steps; a stable damped response stays of order 1×.
  const double wMax = shake.amplitude * 2 * M_PI * shake.frequency;
  const double vRef = wMax * (shake.attachment.norm() + L);
  const double bound = 100 * 0.5 * m * vRef * vRef + 2 * m * 9.81 * L;
  const double e0 = h.energy().mechanical();
  double eMax = 0;
  const int steps = static_cast<int>(std::lround(seconds * 30));
  for (int i = 0; i < steps; ++i)
  {
    const Status st = h.step(1.0 / 30);
    EXPECT_TRUE(st.ok()) << toString(type) << " N = " << n << ": " << st.message();
    if (!st)
      return std::numeric_limits<double>::infinity();
    EXPECT_EQ(h.lastSubsteps(), 1);
    EXPECT_TRUE(h.q().allFinite() && h.qdot().allFinite());
    eMax = std::max(eMax, h.energy().mechanical() - e0);
  }
  EXPECT_LT(eMax, bound) << toString(type) << " N = " << n;
  // Length: the reconstruction is parametrized by arc length, so a fine polyline is
  // shorter than L only by the chord deficit, at most L (Ω h)² / 24 for h = ℓ / 4000.
  double omMax = 0;
  for (int e = 0; e < n; ++e)
    omMax = std::max(omMax, h.q().segment<3>(3 * e).norm());
  std::vector<Eigen::Vector3d> pts;
  h.polyline(4000, pts);
  double len = 0;
  for (size_t i = 1; i < pts.size(); ++i)
    len += (pts[i] - pts[i - 1]).norm();
  const double hseg = L / n / 4000;
  const double deficit = L * std::pow(omMax * hseg, 2) / 24;
  EXPECT_LE(len, L * (1 + 1e-14));
  EXPECT_GE(len, L - 1.01 * deficit - 1e-14 * L) << "deficit bound " << deficit;
  EXPECT_DOUBLE_EQ(h.length(), L);
  return eMax / bound;
}
} // namespace

class SuperHelixPresetStability : public ::testing::TestWithParam<std::tuple<HairType, Integrator>>
{
};

TEST_P(SuperHelixPresetStability, HeadShakingAt3HzFor20sWithoutSubsteps)
{
  // Issue 3: 30 cm, N = 10, dt = 1/30 s, 20 s, every preset, no sub-steps (the semi-implicit
  // step: one linear solve per step; the midpoint step: one, two where it is declined).
  const auto [type, integrator] = GetParam();
  RecordProperty("max_energy_over_bound", sci(shakeAtOneThirtieth(type, integrator, 10, 20)));
}

TEST_P(SuperHelixPresetStability, CoarseStrandsFor120sWithoutSubsteps)
{
  // N = 1 and 3 for 120 s (smooth N = 1 used to refuse a step after 26–56 s of shaking),
  // and N = 2, 5, 20 for 20 s.
  const auto [type, integrator] = GetParam();
  for (int n : {1, 3})
    RecordProperty("N" + std::to_string(n) + "_max_energy_over_bound",
                   sci(shakeAtOneThirtieth(type, integrator, n, 120)));
  for (int n : {2, 5, 20})
    RecordProperty("N" + std::to_string(n) + "_max_energy_over_bound",
                   sci(shakeAtOneThirtieth(type, integrator, n, 20)));
}

INSTANTIATE_TEST_SUITE_P(Presets, SuperHelixPresetStability,
                         ::testing::Combine(::testing::Values(HairType::Smooth, HairType::Wavy,
                                                              HairType::Curly, HairType::Fuzzy),
                                            ::testing::Values(Integrator::SemiImplicit,
                                                              Integrator::Midpoint,
                                                              Integrator::Bdf2)),
                         [](const ::testing::TestParamInfo<std::tuple<HairType, Integrator>>& info)
                         {
                           return std::string(toString(std::get<0>(info.param))) +
                                  integratorTestName(std::get<1>(info.param));
                         });
