// The Super-Helix model's drawer (simulation/ModelRegistry.cxx): its strands drawn again
// from q, q̇ and the root at any number of points per element with the code its frames are
// written with (helix/Centerline.h).
#include "common/Parallel.h"
#include "helix/Centerline.h"
#include "model/StrandPoints.h"
#include "superhelixmodel/SuperHelixModel.h"

#include <algorithm>

namespace hair
{

namespace
{
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

} // namespace

Status drawSuperHelixFrame(const StateHeader& header, const StateFrame& frame, int pointsPerElement,
                           int threads, GuideDrawing& out)
{
  const int n = header.coordinatesPerStrand / 3;
  const std::vector<double>* length = strandParameter(header, "length");
  const std::vector<double>* elements = strandParameter(header, "elements");
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

} // namespace hair
