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
