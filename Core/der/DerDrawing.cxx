// The Discrete Elastic Rods model's drawer (simulation/ModelRegistry.cxx): its strands at
// their stored points, the root's frame carried along the nodes and turned by each edge's
// material angle φ (DerModel::describe).
#include "der/DerModel.h"
#include "der/DerStencil.h"
#include "model/StrandPoints.h"

#include <cmath>

namespace hair
{

Status drawDerFrame(const StateHeader& header, const StateFrame& frame, int pointsPerElement,
                    int threads, GuideDrawing& out)
{
  (void)pointsPerElement; // a rod is drawn at its nodes, whatever it says
  (void)threads;
  const int c = header.coordinatesPerStrand;
  const int n = (c - 3) / 4;
  bool nodes = c > 3 && (c - 3) % 4 == 0;
  for (std::size_t k = 0; nodes && k < header.numberOfStrands(); ++k)
  {
    nodes = header.offsets[k + 1] - header.offsets[k] == std::int64_t(n + 1);
  }
  if (!nodes)
  {
    out.warning = "the discrete elastic rods' points are not their root and nodes (one more "
                  "than their edges): they are shown at their stored points, without material "
                  "frames.";
    return Status::Ok();
  }
  const std::size_t points = header.numberOfPoints();
  out.tangents.assign(points, Eigen::Vector3d::UnitX());
  out.directors.assign(points, Eigen::Vector3d::UnitY());
  std::vector<double>& curvature = out.frame.pointData["curvature"];
  std::vector<double>& twist = out.frame.pointData["twist"];
  curvature.assign(points, 0.0);
  twist.assign(points, 0.0);
  for (std::size_t k = 0; k < header.numberOfStrands(); ++k)
  {
    const double* q = frame.q.data() + k * std::size_t(c);
    const auto node = [&](int j) { return Eigen::Vector3d(q[4 * j], q[4 * j + 1], q[4 * j + 2]); };
    const Eigen::Matrix3d root = rootOf(frame, k).orientation;
    const std::size_t first = std::size_t(header.offsets[k]);
    Eigen::Vector3d carried = root.col(1), previous = root.col(0);
    for (int j = 0; j < n; ++j)
    {
      const Eigen::Vector3d t = (node(j + 1) - node(j)).normalized();
      if (j > 0)
      {
        carried = parallelTransport(carried, previous, t);
        carried = (carried - carried.dot(t) * t).normalized();
      }
      const double phi = q[4 * j + 3];
      // Point j is the root (j = 0) or node j: the frame of the edge it starts.
      out.tangents[first + j] = t;
      out.directors[first + j] = std::cos(phi) * carried + std::sin(phi) * t.cross(carried);
      if (j > 0)
      {
        // Node j's turning angle and twist over its Voronoi length.
        const double length =
            0.5 * ((node(j) - node(j - 1)).norm() + (node(j + 1) - node(j)).norm());
        curvature[first + j] = std::atan2(previous.cross(t).norm(), previous.dot(t)) / length;
        twist[first + j] = (phi - q[4 * (j - 1) + 3]) / length;
      }
      previous = t;
    }
    out.tangents[first + n] = out.tangents[first + n - 1];
    out.directors[first + n] = out.directors[first + n - 1];
  }
  return Status::Ok();
}

} // namespace hair
