#pragma once
// A stored frame of guides as the filters show it (Hair Simulation's output 0, Hair State
// Reader's output), drawn by its model's registered drawer (simulation/ModelRegistry.h):
// the Super-Helix again from q, q̇ and the root at any number of points per element with
// the code its model writes frames with (helix/Centerline.h), the projective strands at
// their nodes; and the material frame at every point, which the interpolation of rendered
// hair carries its offsets in. Frames without root poses (state files written without
// /frames/root_frames) and frames of a model no one registered are shown as stored.
#include "common/Status.h"
#include "io/StateFile.h"
#include "model/GuideDrawing.h"

namespace hair
{

/// Draws `frame` of a file or run described by `header`. `pointsPerElement`: Super-Helix
/// points per element (0: as stored); the projective model's points are its nodes, whatever
/// it says. At a Super-Helix resolution other than the stored one, curvature and twist are
/// those of the element a point starts (as the model writes them) and the other per-point
/// scalars (contact_depth, …) are interpolated linearly in arc length between the stored
/// points. Refuses a frame whose q or roots do not match the header.
Status drawGuides(const StateHeader& header, const StateFrame& frame, int pointsPerElement,
                  int threads, GuideDrawing& out);

/// A frame read from a state file that keeps its nodes in single precision
/// (header.singlePrecisionPoints: the Super-Helix's) given back its nodes and their velocities
/// in double, drawn again from its state by the code the model writes them with: the frame
/// the run kept, bit for bit. Other frames are left as they are.
Status restoreNodes(const StateHeader& header, StateFrame& frame);

} // namespace hair
