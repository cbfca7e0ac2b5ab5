// The projective model's drawer (simulation/ModelRegistry.cxx): its strands at their nodes,
// with each segment's frame from the root's and the angles.
#include "model/StrandPoints.h"
#include "projective/ProjectiveModel.h"
#include "projective/Segments.h"

#include <cmath>

namespace hair
{

Status drawProjectiveFrame(const StateHeader& header, const StateFrame& frame, int pointsPerElement,
                           int threads, GuideDrawing& out)
{
  (void)pointsPerElement; // a projective strand is drawn at its nodes, whatever it says
  (void)threads;
  const int c = header.coordinatesPerStrand;
  bool nodes = c % 2 == 0 && c > 0;
  for (std::size_t k = 0; nodes && k < header.numberOfStrands(); ++k)
  {
    nodes = header.offsets[k + 1] - header.offsets[k] == std::int64_t(c / 2 + 1);
  }
  if (!nodes)
  {
    out.warning = "the projective strands' points are not their nodes (one more than their "
                  "segments): they are shown at their stored points, without material frames.";
    return Status::Ok();
  }
  out.tangents.clear();
  out.directors.clear();
  std::vector<double>& curvature = out.frame.pointData["curvature"];
  std::vector<double>& twist = out.frame.pointData["twist"];
  curvature.assign(header.numberOfPoints(), 0.0);
  twist.assign(header.numberOfPoints(), 0.0); // the projective model has no twist
  std::vector<Eigen::Vector3d> t, d;
  for (std::size_t k = 0; k < header.numberOfStrands(); ++k)
  {
    nodeFrames(segmentFrame(rootOf(frame, k).orientation), frame.q.data() + k * c, c / 2, t, d);
    out.tangents.insert(out.tangents.end(), t.begin(), t.end());
    out.directors.insert(out.directors.end(), d.begin(), d.end());
    // Discrete curvature: the turning angle at an inner node over the segment length.
    const std::int64_t first = header.offsets[k], last = header.offsets[k + 1] - 1;
    for (std::int64_t i = first + 1; i < last; ++i)
    {
      const Eigen::Vector3d a = frame.positions[i] - frame.positions[i - 1];
      const Eigen::Vector3d b = frame.positions[i + 1] - frame.positions[i];
      curvature[i] = std::atan2(a.cross(b).norm(), a.dot(b)) / a.norm();
    }
  }
  return Status::Ok();
}

} // namespace hair
