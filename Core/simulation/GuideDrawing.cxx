#include "simulation/GuideDrawing.h"

#include "model/StrandPoints.h"
#include "simulation/ModelRegistry.h"

#include <algorithm>
#include <cmath>

namespace hair
{

namespace
{
/// The drawn header names the drawn frame's per-point arrays (curvature and twist added).
void namePointData(GuideDrawing& out)
{
  out.header.pointData.clear();
  for (const auto& [name, values] : out.frame.pointData)
  {
    out.header.pointData.push_back(name);
  }
}
} // namespace

Status drawGuides(const StateHeader& header, const StateFrame& frame, int pointsPerElement,
                  int threads, GuideDrawing& out)
{
  out.header = header;
  out.frame = frame;
  out.tangents.clear();
  out.directors.clear();
  out.warning.clear();
  const std::size_t strands = header.numberOfStrands();
  const std::size_t c = std::size_t(std::max(0, header.coordinatesPerStrand));
  if (frame.positions.size() != header.numberOfPoints() || frame.q.size() != strands * c ||
      frame.qdot.size() != strands * c)
  {
    return Status::Error("the frame at t = " + std::to_string(frame.time) +
                         " s does not match its header (points, q or qdot).");
  }
  if (strands == 0)
  {
    return Status::Ok(); // a piece of a run without strands (an MPI rank's): nothing to draw
  }
  const bool roots = header.rootFrames && frame.rootFrames.size() == strands * RootFrameValues &&
                     frame.rootVelocities.size() == strands * RootVelocityValues;
  if (!roots)
  {
    out.warning = "the file stores no root poses (/frames/root_frames, root_velocities), which "
                  "drawing the strands again needs: they are shown at their stored points, "
                  "without material frames (Tangent, Director1), whatever the points per "
                  "element.";
    return Status::Ok();
  }
  const ModelEntry* model = findModel(header.model);
  if (!model || !model->draw)
  {
    out.warning = "the model '" + header.model + "' is not one this HairDynamics draws (" +
                  modelNames() +
                  "): the strands are shown at their stored points, without material frames.";
    return Status::Ok();
  }
  const Status drawn = model->draw(header, frame, pointsPerElement, threads, out);
  namePointData(out);
  return drawn;
}

Status restoreNodes(const StateHeader& header, StateFrame& frame)
{
  if (!header.singlePrecisionPoints)
  {
    return Status::Ok();
  }
  GuideDrawing nodes;
  if (Status s = drawGuides(header, frame, 1, 1, nodes); !s)
  {
    return s;
  }
  if (nodes.warning.empty() && nodes.frame.positions.size() == frame.positions.size())
  {
    frame.positions.swap(nodes.frame.positions);
    frame.velocities.swap(nodes.frame.velocities);
  }
  return Status::Ok();
}

} // namespace hair
