// Golden results: what a change meant to leave the results alone (a refactoring, speed
// work) must reproduce. The values were recorded from earlier code and are never
// recomputed by the code under test.
#include "DemoScene.h"
#include "GoldenStates.h"
#include "HeadShake.h"
#include "simulation/Simulation.h"
#include "superhelix/SuperHelix.h"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

using namespace hair;

TEST(Golden, SuperHelixStateAfterThirtyStepsOfTheShake)
{
  for (int preset = 0; preset < 4; ++preset)
  {
    const StrandSpec spec = shakenStrand(HairType(preset), 10);
    SuperHelix h;
    ASSERT_TRUE(h.initialize(spec).ok());
    for (int i = 0; i < 30; ++i)
      ASSERT_TRUE(h.step(1.0 / 30).ok());
    const double* ref = golden::ShakenQ[preset];
    double diff = 0, scale = 0;
    for (int i = 0; i < 30; ++i)
    {
      diff = std::max(diff, std::abs(h.q()[i] - ref[i]));
      scale = std::max(scale, std::abs(ref[i]));
    }
    std::ostringstream shown;
    shown << diff / scale;
    RecordProperty(std::string("relative_difference_") + toString(HairType(preset)), shown.str());
    EXPECT_LE(diff / scale, golden::ShakenQTolerance) << toString(HairType(preset));
  }
}

TEST(Golden, DemoSummaryOfTheSuperHelixRun)
{
  // The demo's Super-Helix run (200 guides, 5 s, body contacts, the head shaking) as its
  // summary printed it before the models shared one scene: |residual| / work 0.241354 at
  // the end (read from Output/super-helix.h5 of `bash Scripts/demo.sh` at commit 2148a99).
  // The penetration is measured at the model's nodes since the state file keeps states
  // (format version 3; it was 1032 display points at 4 per element, 11.2466 mm deep). The
  // body's contact law is continuous in the state since issue 31 (arriving samples' damping
  // ramped in, friction with it): re-derived from that run, at most 296 nodes inside the
  // tables after t = 0 (305 before), the deepest 6.7022 mm (5.9680), |residual| / work
  // 0.263895 (0.241354). The run
  // is chaotic where strands touch the body: round-off differences of 1e-11 m after one
  // frame grow to millimetres by the end (measured against that file), so the figures the
  // summary shows carry round-off of their own: the count exactly, the depth to 1 µm, the
  // ratio to 1e-4 of itself (measured: 2e-5). That run had no hair–hair interaction (on by
  // default since): this pins the body's contacts and the step, which it still runs.
  BundledBody body;
  ASSERT_TRUE(loadBundledBody(HAIR_DATA_DIR, body).ok());
  std::vector<GuideStrand> guides;
  ASSERT_TRUE(demoGuides(body, 200, 10, guides).ok());
  SimulationOptions o;
  o.threads = 2;
  o.hairHair.enabled = false;
  Simulation sim;
  ASSERT_TRUE(sim.initialize(guides, demoScene(body), o).ok());
  ASSERT_TRUE(sim.advanceTo(151).ok());
  long inside = 0;
  double deepest = 0;
  for (int f = 1; f < sim.numberOfFrames(); ++f)
  {
    inside = std::max(inside, sim.contacts()[f]);
    deepest = std::max(deepest, sim.maxDepth()[f]);
  }
  const auto& e = sim.frame(150).energy;
  const double ratio =
      std::abs(e.at("residual")) / (std::abs(e.at("external_work")) + std::abs(e.at("dissipated")));
  RecordProperty("nodes_inside", std::to_string(inside));
  RecordProperty("deepest_mm", std::to_string(1e3 * deepest));
  RecordProperty("residual_over_work", std::to_string(ratio));
  EXPECT_EQ(inside, 296);
  EXPECT_NEAR(deepest, 6.7022e-3, 1e-6);
  EXPECT_NEAR(ratio, 0.263895, 1e-4 * 0.263895);
}
