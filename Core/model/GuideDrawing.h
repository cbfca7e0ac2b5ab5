#pragma once
// A stored frame of guides as the filters show it (Hair Simulation's output 0, Hair State
// Reader's output), and the drawer a model registers to make it from its frames
// (simulation/ModelRegistry.h): its strands drawn again from the frame's state at any
// resolution it can, with the material frame at every point, which the interpolation of
// rendered hair carries its offsets in.
#include "common/Status.h"
#include "io/StateFile.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace hair
{

struct GuideDrawing
{
  /// The drawn points' offsets; the stored header's strand parameters, vectors and the rest.
  StateHeader header;
  /// Positions, velocities and per-point scalars at the drawn points; q, q̇ and the roots as
  /// stored.
  StateFrame frame;
  /// Per drawn point: the material frame's tangent and first director (unit, orthogonal).
  /// Empty when the frame has no root poses.
  std::vector<Eigen::Vector3d> tangents, directors;
  /// Why the frame is shown at its stored points or without material frames; empty if not.
  std::string warning;
};

/// A model's drawer: `frame` of `header` (this model's, with root poses, its points, q and q̇
/// checked against the header, at least one strand) drawn into `out`, which arrives as a copy
/// of them. It sets out.header's offsets and out.frame's points for the resolution it draws
/// (`pointsPerElement` points per element where the model can draw at any; 0: as stored),
/// fills out.tangents and out.directors, adds "curvature" and "twist" to out.frame.pointData
/// and resamples the other per-point arrays to its points. A frame it cannot draw is left as
/// stored with out.warning saying why.
using DrawFrame = Status (*)(const StateHeader& header, const StateFrame& frame,
                             int pointsPerElement, int threads, GuideDrawing& out);

/// The stored parameter `file` of every strand of `header` (/strands/<file>), or null.
const std::vector<double>* strandParameter(const StateHeader& header, const char* file);

} // namespace hair
