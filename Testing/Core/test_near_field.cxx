// The near field of hair–hair interaction (contact/NearField.h, docs/hair-hair-interaction.md):
// pairs of guide pieces that would cross, or end a step within the contact distance, pushed
// apart along the side they were on, solved with each strand's step (stepStrandsWithNearField).
// References: the pass-through count of contact/PassThrough.h, which knows nothing of the
// near field; the same strands stepped without it; Newton's third law.
#include "StrandPairs.h"
#include "contact/NearField.h"
#include "superhelix/SuperHelix.h"

#include <gtest/gtest.h>

#include <cstdio>

using namespace hair;

namespace
{
constexpr double Dt = 1.0 / 30;

// Strand B lies straight along z (root fixed at the origin); strand A, straight along x,
// 10 mm above B's middle, is driven down through it by its root at `speed` (gravity off).
Status driveThrough(bool near, double speed, int frames, long& passes, double& closest)
{
  std::vector<SuperHelix> strands;
  if (Status st = drivenPair(speed, -0.1031, 0.1043, strands); !st)
    return st;
  NearFieldContacts contacts;
  NearFieldParameters p;
  p.thickness = 2.5e-3;
  if (Status st = contacts.setParameters(p); !st)
    return st;
  return runPair(
      strands, frames, 8, 2 * p.thickness,
      [&](std::vector<SuperHelix>& s)
      { return near ? stepStrandsWithNearField(s, contacts, Dt, 1) : stepStrands(s, Dt, 1); },
      passes, closest);
}
} // namespace

TEST(NearField, AStrandDrivenThroughAnotherIsStoppedWithinTheStep)
{
  // A at 0.6 m/s covers 20 mm per 1/30 s step, four contact distances (R = 5 mm): starting
  // 10 mm above B, it would be 10 mm below after one step. The pair is found from where the
  // step takes A, and pushed back to R along its side at the end of that step: A stops on B
  // instead of crossing. Without the near field it crosses within the first step.
  long passes = 0, passesFree = 0;
  double closest = 0, closestFree = 0;
  Status st = driveThrough(true, 0.6, 6, passes, closest);
  ASSERT_TRUE(st.ok()) << st.message();
  st = driveThrough(false, 0.6, 6, passesFree, closestFree);
  ASSERT_TRUE(st.ok()) << st.message();
  EXPECT_EQ(passes, 0);
  EXPECT_GE(passesFree, 1);
  // The gap ends at R less what the linear prediction of the end positions (x + h v) misses
  // of the step's motion and what the chords between quadrature samples miss of the
  // centreline: required above half of R.
  EXPECT_GT(closest, 0.5 * 5e-3);
  std::printf("driven at 0.6 m/s: closest approach %.3g mm with the near field (%ld "
              "pass-throughs), %.3g mm without (%ld)\n",
              1e3 * closest, passes, 1e3 * closestFree, passesFree);
}
