#include "simulation/GuideDrawing.h"

#include "common/Parallel.h"
#include "model/StrandPoints.h"
#include "projective/Segments.h"
#include "superhelix/Centerline.h"

#include <algorithm>
#include <cmath>

namespace hair
{

namespace
{
// The models' names as their describe() writes them (StrandModel::name()).
constexpr char SuperHelixName[] = "super-helix";
constexpr char ProjectiveName[] = "projective";

const std::vector<double>* parameter(const StateHeader& h, const char* file)
{
  const auto it = h.strandParameters.find(file);
  return it == h.strandParameters.end() ? nullptr : &it->second;
}

/// The points per element every strand of a Super-Helix file stores (0: not a whole number,
/// or strands that differ).
int storedPerElement(const StateHeader& h, int elements)
{
  int per = 0;
  for (std::size_t k = 0; k < h.numberOfStrands(); ++k)
  {
    const std::int64_t segments = h.offsets[k + 1] - h.offsets[k] - 1;
    if (elements < 1 || segments < elements || segments % elements != 0 ||
        (per != 0 && segments / elements != per))
    {
      return 0;
    }
    per = static_cast<int>(segments / elements);
  }
  return per;
}

/// A stored per-point scalar at `per` points per element from `stored` per element: linear in
/// arc length between the stored points (the elements are equal).
void resample(const std::vector<double>& values, const StateHeader& from, int stored,
              const StateHeader& to, int per, std::vector<double>& out)
{
  out.assign(to.numberOfPoints(), 0.0);
  for (std::size_t k = 0; k < to.numberOfStrands(); ++k)
  {
    const std::int64_t first = from.offsets[k], last = from.offsets[k + 1] - 1;
    for (std::int64_t j = 0; j < to.offsets[k + 1] - to.offsets[k]; ++j)
    {
      const double x = double(j) * stored / per;
      const std::int64_t i = std::min<std::int64_t>(static_cast<std::int64_t>(x), last - first);
      const double w = x - double(i);
      const double a = values[first + i];
      const double b = first + i < last ? values[first + i + 1] : a;
      out[to.offsets[k] + j] = (1 - w) * a + w * b;
    }
  }
}

Status drawSuperHelices(const StateHeader& header, const StateFrame& frame, int pointsPerElement,
                        int threads, GuideDrawing& out)
{
  const int n = header.coordinatesPerStrand / 3;
  const std::vector<double>* length = parameter(header, "length");
  const std::vector<double>* elements = parameter(header, "elements");
  const int stored = storedPerElement(header, n);
  bool uniform = length && elements && stored > 0 && header.coordinatesPerStrand == 3 * n;
  for (std::size_t k = 0; uniform && k < header.numberOfStrands(); ++k)
  {
    uniform = (*elements)[k] == n && (*length)[k] > 0;
  }
  if (!uniform)
  {
    out.warning = "the Super-Helix strands cannot be drawn again (the file lacks "
                  "/strands/length or /strands/elements, or its points are not a whole number "
                  "per element): they are shown at their stored points, without material frames.";
    return Status::Ok();
  }
  const int per = pointsPerElement > 0 ? pointsPerElement : stored;
  const std::size_t strands = header.numberOfStrands();
  StateHeader& h = out.header;
  for (std::size_t k = 0; k < strands; ++k)
  {
    h.offsets[k + 1] = h.offsets[k] + std::int64_t(n) * per + 1;
  }
  const std::size_t points = h.numberOfPoints();
  StateFrame& f = out.frame;
  f.positions.resize(points);
  f.velocities.resize(points);
  out.tangents.resize(points);
  out.directors.resize(points);
  std::vector<double> curvature(points), twist(points);
  const int c = header.coordinatesPerStrand;
  parallelBlocks(
      static_cast<std::int64_t>(strands), 16, threads,
      [&](std::int64_t begin, std::int64_t end)
      {
        StrandPoints drawn;
        for (std::int64_t k = begin; k < end; ++k)
        {
          // The elements as StrandSpec::uniform cuts them.
          const std::vector<double> lengths(n, (*length)[k] / n);
          drawSuperHelix(lengths, frame.q.data() + k * c, frame.qdot.data() + k * c,
                         rootOf(frame, k), per, drawn);
          const std::size_t at = h.offsets[k];
          std::copy(drawn.positions.begin(), drawn.positions.end(), f.positions.begin() + at);
          std::copy(drawn.velocities.begin(), drawn.velocities.end(), f.velocities.begin() + at);
          std::copy(drawn.tangents.begin(), drawn.tangents.end(), out.tangents.begin() + at);
          std::copy(drawn.directors.begin(), drawn.directors.end(), out.directors.begin() + at);
          std::copy(drawn.curvature.begin(), drawn.curvature.end(), curvature.begin() + at);
          std::copy(drawn.twist.begin(), drawn.twist.end(), twist.begin() + at);
        }
      });
  for (auto& [name, values] : f.pointData)
  {
    if (name != "curvature" && name != "twist" && per != stored)
    {
      std::vector<double> resampled;
      resample(values, header, stored, h, per, resampled);
      values.swap(resampled);
    }
  }
  f.pointData["curvature"].swap(curvature);
  f.pointData["twist"].swap(twist);
  return Status::Ok();
}

void drawProjective(const StateHeader& header, const StateFrame& frame, GuideDrawing& out)
{
  const int c = header.coordinatesPerStrand;
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
}

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
  if (header.model == SuperHelixName)
  {
    const Status drawn = drawSuperHelices(header, frame, pointsPerElement, threads, out);
    namePointData(out);
    return drawn;
  }
  bool nodes = header.model == ProjectiveName && c % 2 == 0 && c > 0;
  for (std::size_t k = 0; nodes && k < strands; ++k)
  {
    nodes = header.offsets[k + 1] - header.offsets[k] == std::int64_t(c / 2 + 1);
  }
  if (nodes)
  {
    drawProjective(header, frame, out);
    namePointData(out);
    return Status::Ok();
  }
  out.warning = "the model '" + header.model +
                "' is not one this HairDynamics draws: the strands are shown at their stored "
                "points, without material frames.";
  return Status::Ok();
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
