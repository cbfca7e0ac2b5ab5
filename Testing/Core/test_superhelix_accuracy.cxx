// Motion accuracy of the two time steps (docs/super-helix.md, "The second-order step" and
// "Accuracy on request"): a 30 cm smooth strand clamped horizontally and released under
// gravity with air drag 1e-5 kg/(m·s) and no internal friction (issue 23), its tip followed
// frame by frame (1/30 s) for 1 s against a converged run of the second-order step at
// 1/7680 s (which differs from the run at 1/15360 s by 2.8e-5 m).
#include "superhelix/SuperHelix.h"

#include <gtest/gtest.h>

#include <chrono>
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

struct Released
{
  std::vector<Eigen::Vector3d> tips; // at every frame, t = 0 … 1 s
  long steps = 0, rejected = 0;
  double seconds = 0; // wall time
};

// Frames of 1/30 s, each `per` steps of advance(dt, tolerance · dt) (tolerance in m/s).
Released released(Integrator integrator, int per, double tolerance)
{
  HairParameters p = HairParameters::preset(HairType::Smooth);
  p.curvatureVariation = 0;
  p.internalFriction = 0;
  p.airFriction = 1e-5;
  StrandSpec spec = StrandSpec::uniform(0.3, 10, p);
  spec.integrator = integrator;
  SuperHelix h;
  EXPECT_TRUE(h.initialize(spec).ok());
  Released r;
  r.tips.push_back(h.position(0.3));
  const double dt = 1.0 / (30 * per);
  const auto start = std::chrono::steady_clock::now();
  for (int f = 0; f < 30; ++f)
  {
    for (int k = 0; k < per; ++k)
    {
      const Status st = h.advance(dt, tolerance * dt);
      EXPECT_TRUE(st.ok()) << st.message();
      if (!st)
        return r;
      r.steps += h.lastSubsteps();
      r.rejected += h.lastRejected();
    }
    r.tips.push_back(h.position(0.3));
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

double largestDistance(const Released& a, const Released& b)
{
  double d = 0;
  for (size_t i = 0; i < a.tips.size() && i < b.tips.size(); ++i)
    d = std::max(d, (a.tips[i] - b.tips[i]).norm());
  return d;
}

const Released& reference()
{
  static const Released r = released(Integrator::Midpoint, 256, 0);
  return r;
}
} // namespace

TEST(SuperHelixAccuracy, TipConvergesAtSecondOrderWithTheMidpointStep)
{
  // Fixed steps of 1/480, 1/960, 1/1920 s: the second-order step's largest tip error over the
  // second falls four times per halving (measured 9.7, 2.3, 0.56 mm: order 2.05), the
  // semi-implicit step's at most twice (19.0, 3.8, 2.3 mm). At 1/30 s neither resolves the
  // chain's second pendulum mode (≈ 16 rad/s, h ω = 0.5): recorded, not bounded (issue 23
  // asked for 30 mm there; the converged midpoint rule itself, with Newton iterations to
  // convergence, is 82 mm off; docs/super-helix.md).
  std::vector<double> mid, semi;
  for (int per : {16, 32, 64})
  {
    mid.push_back(largestDistance(released(Integrator::Midpoint, per, 0), reference()));
    semi.push_back(largestDistance(released(Integrator::SemiImplicit, per, 0), reference()));
    RecordProperty("midpoint_tip_error_1/" + std::to_string(30 * per), sci(mid.back()));
    RecordProperty("semi_implicit_tip_error_1/" + std::to_string(30 * per), sci(semi.back()));
  }
  const double order = 0.5 * std::log2(mid[0] / mid[2]);
  RecordProperty("midpoint_order", sci(order));
  EXPECT_NEAR(order, 2.0, 0.3) << mid[0] << " " << mid[1] << " " << mid[2];
  EXPECT_LT(mid[2], 0.5 * semi[2]);
  RecordProperty("midpoint_tip_error_1/30",
                 sci(largestDistance(released(Integrator::Midpoint, 1, 0), reference())));
  RecordProperty("semi_implicit_tip_error_1/30",
                 sci(largestDistance(released(Integrator::SemiImplicit, 1, 0), reference())));
}

TEST(SuperHelixAccuracy, ToleranceOfFiveMillimetresPerSecondKeepsTheTipWithinFive)
{
  // Frames of 1/30 s with advance(1/30, 5e-3 / 30): each strand's estimates add up to at
  // most 5 mm over the second. The tip stays within 5 mm of the converged run with either
  // step (measured 1.5 mm semi-implicit, 0.06 mm midpoint, whose estimate, the difference
  // of its update from the first-order one, is far above its own error); the cost is
  // recorded (steps and wall time for the simulated second).
  for (Integrator integrator : {Integrator::SemiImplicit, Integrator::Midpoint})
  {
    const Released r = released(integrator, 1, 5e-3);
    const double error = largestDistance(r, reference());
    const std::string name = toString(integrator);
    RecordProperty(name + "_tip_error", sci(error));
    RecordProperty(name + "_steps", std::to_string(r.steps));
    RecordProperty(name + "_rejected", std::to_string(r.rejected));
    RecordProperty(name + "_seconds", sci(r.seconds));
    EXPECT_LT(error, 5e-3) << name;
  }
}

TEST(SuperHelixAccuracy, TipConvergesAtSecondOrderWithBdf2)
{
  // BDF2 at fixed steps of 1/480, 1/960, 1/1920 s against the midpoint step's converged run
  // (another scheme, so the reference owes nothing to BDF2): measured 3.8, 1.04, 0.21 mm,
  // order 2.06. Only its first step is semi-implicit (no history yet); the energy guard
  // declines none here.
  std::vector<double> bdf;
  for (int per : {16, 32, 64})
  {
    bdf.push_back(largestDistance(released(Integrator::Bdf2, per, 0), reference()));
    RecordProperty("bdf2_tip_error_1/" + std::to_string(30 * per), sci(bdf.back()));
  }
  const double order = 0.5 * std::log2(bdf[0] / bdf[2]);
  RecordProperty("bdf2_order", sci(order));
  EXPECT_NEAR(order, 2.0, 0.3) << bdf[0] << " " << bdf[1] << " " << bdf[2];
  RecordProperty("bdf2_tip_error_1/30",
                 sci(largestDistance(released(Integrator::Bdf2, 1, 0), reference())));
}

TEST(SuperHelixAccuracy, Bdf2ToleranceControlsTheErrorAtAFractionOfTheSteps)
{
  // BDF2's estimate is its own local error, −(qⁿ⁺¹ − q*)/3 (docs/super-helix.md, "BDF2"),
  // not a first-order bound, so the sub-steps it asks for are few: measured, tolerance
  // 0.01 m/s: 14 mm at 181 steps (the midpoint step's 0.05: 9.3 mm at 408); 0.002: 2.1 mm
  // at 474. The global error is then of the order of the tolerance rather than below it:
  // the bounds here are what the local errors' sum can grow to over one second of a whip
  // (twice the tolerance), and the error must fall with the tolerance (five times smaller
  // tolerance, at least four times smaller error: order 2 in the sub-step, at least 0.86
  // in the tolerance).
  const Released coarse = released(Integrator::Bdf2, 1, 0.01);
  const Released fine = released(Integrator::Bdf2, 1, 0.002);
  const double eCoarse = largestDistance(coarse, reference());
  const double eFine = largestDistance(fine, reference());
  RecordProperty("tip_error_0.01", sci(eCoarse));
  RecordProperty("tip_error_0.002", sci(eFine));
  RecordProperty("steps_0.01", std::to_string(coarse.steps));
  RecordProperty("steps_0.002", std::to_string(fine.steps));
  EXPECT_LT(eCoarse, 2 * 0.01);
  EXPECT_LT(eFine, 2 * 0.002);
  EXPECT_LT(eFine, 0.25 * eCoarse);
  // Fewer steps than the midpoint step needs for a coarser result (its tolerance 0.05).
  const Released mid = released(Integrator::Midpoint, 1, 0.05);
  EXPECT_LT(coarse.steps, mid.steps);
  EXPECT_LT(eCoarse, 2 * largestDistance(mid, reference()));
}
