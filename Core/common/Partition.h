#pragma once
// Splitting weighted points of space into parts of nearly equal weight, each a compact
// region: how a run's strands are shared among MPI ranks (by their roots, weighted by their
// step's cost), so that neighbours, which may touch, mostly share a rank.
#include <Eigen/Core>

#include <vector>

namespace hair
{

/// Recursive coordinate bisection: the points are cut across the longest side of their
/// bounding box, at the weight that gives each side its share of the parts (⌊p/2⌋ and
/// ⌈p/2⌉ of p), and each side is cut again until every part is one. Returns each point's
/// part, 0 … parts − 1. A part gets no point only when there are fewer points than parts.
/// The cut falls between two points where the weight on the first side comes closest to
/// its share, so a part differs from its share by at most one point's weight per level
/// (⌈log2 parts⌉ levels). Deterministic: the same input gives the same parts on every rank
/// (ties in a coordinate are broken by the points' order). Weights must be > 0.
std::vector<int> bisect(const std::vector<Eigen::Vector3d>& points,
                        const std::vector<double>& weights, int parts);

} // namespace hair
