#pragma once
// Sharing weighted points of space among parts of nearly equal weight, each a compact region
// and a range of one order: how a run's strands are shared among MPI ranks (by their roots,
// weighted by their step's cost), so that neighbours, which may touch, mostly share a rank,
// and, the guides being numbered along the same order (strands/GuideGrowth.h), each rank's
// strands are consecutive numbers: one run of rows per dataset in the state file.
#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace hair
{

/// The points' order along a Hilbert curve through their bounding box (2^21 cells a side,
/// J. Skilling, "Programming the Hilbert curve", AIP Conf. Proc. 707, 2004): points near
/// along the curve are near in space, and a range of the curve is a compact region. Ties
/// (points in one cell) keep the points' order. Deterministic.
std::vector<std::size_t> spaceFillingOrder(const std::vector<Eigen::Vector3d>& points);

/// Shares the points among `parts`: spaceFillingOrder cut into ranges, each cut where the
/// weight before it comes closest to its share (so a part differs from its share by at most
/// one point's weight). Returns each point's part, 0 … parts − 1, increasing along the
/// curve; points given in the curve's order get parts of consecutive indices. A part gets
/// no point only when there are fewer points than parts. Deterministic: the same input
/// gives the same parts on every rank. Weights must be > 0.
std::vector<int> shareAlongCurve(const std::vector<Eigen::Vector3d>& points,
                                 const std::vector<double>& weights, int parts);

} // namespace hair
