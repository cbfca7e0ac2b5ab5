#pragma once
// A Super-Helix drawn from its coordinates alone: given q, q̇ and the root's pose and rates,
// the points of its centreline, their velocities and the material frame at each, in the
// closed form of HelixFunctions.h, element by element from the root (no quadrature, no
// stepping). SuperHelixModel writes its frames with it and the state file's strands are
// drawn again with it at any number of points per element (simulation/GuideDrawing.h).
#include "model/StrandPoints.h"
#include "scene/RigidMotion.h"

#include <vector>

namespace hair
{

/// Element ends r(s_0 = 0), …, r(s_N) and `perElement` − 1 points inside each element, at
/// equal steps of its arc length: N·perElement + 1 points. Tangent and director are the
/// columns n0 and n1 of the frame at each point (SuperHelix::frame); curvature |κ| and twist
/// τ those of the element the point starts (the tip: the last element's). q and qdot hold
/// 3N values (τ, κ1, κ2 per element); `root` gives position, orientation, velocity and
/// angular velocity. `out` is overwritten.
void drawSuperHelix(const std::vector<double>& elementLengths, const double* q, const double* qdot,
                    const RootState& root, int perElement, StrandPoints& out);

} // namespace hair
