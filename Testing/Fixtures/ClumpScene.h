#pragma once
// A clump of guide strands for the hair–hair experiments of the Super-Helices paper
// (Bertails et al., ACM TOG 25(3), 2006, figures 6–7): guides rooted on a horizontal disc
// (sunflower pattern), hanging along −y, squeezed by an air flow converging on the clump's
// axis, v = −β(t) (x, 0, z) with β ramped linearly from 0 to `flowRate` over `rampTime`, and
// from `startOscillation` on, the root disc oscillating vertically. Shared by the hair–hair
// tests and `hair_study clump` (study 3, docs/study-buckling.md).
#include "common/Status.h"
#include "strands/HairParameters.h"
#include "superhelix/SuperHelix.h"

#include <vector>

namespace hair
{

struct ClumpSpec
{
  int count = 50;
  double discRadius = 0.012; ///< radius of the root disc [m]
  double length = 0.3;       ///< strand length [m]
  int elements = 10;
  double flowRate = 25;                                         ///< β at the end of the ramp [1/s]
  double rampTime = 3;                                          ///< [s]
  double amplitude = 0.01, frequency = 3, startOscillation = 3; ///< the root disc's motion
  HairParameters hair; ///< default: the smooth preset, round, straight, without variation

  ClumpSpec();
  Status validate() const;
};

/// The root disc's motion: at rest until startOscillation, then amplitude · sin(2π f (t − start)).
RigidMotion clumpRootMotion(const ClumpSpec& spec);
/// The root disc's vertical offset at time t (0 before the oscillation starts) [m].
double clumpRootOffset(const ClumpSpec& spec, double t);

/// Initializes `strands` (resized to spec.count; ids 0 … count − 1, names "clump i") at rest
/// at t = 0. On error `strands` is left as it was.
Status initializeClump(const ClumpSpec& spec, std::vector<SuperHelix>& strands);

} // namespace hair
