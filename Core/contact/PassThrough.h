#pragma once
// Pairs of strands that went through each other between two frames: the measure of
// docs/hair-hair-contacts.md ("No pass-through"), independent of how contacts are solved.
#include <Eigen/Core>

#include <vector>

namespace hair
{

/// One pass-through: pieces (segments between consecutive points) of two strands.
struct PassThrough
{
  int strandA = 0, pieceA = 0, strandB = 0, pieceB = 0; ///< strandA < strandB
  double distanceBefore = 0, distanceAfter = 0;         ///< of their closest points [m]
};

/// Pieces of different strands whose closest-point direction reverses between two frames
/// (before[i] and after[i] are strand i's points, the same count in both) while they are
/// within `distance` of each other: with the closest points inside both pieces in both
/// frames (not at an end), the direction is the pieces' common normal, and its reversal
/// means that one piece crossed the other's line within the pieces' extent. "Within
/// `distance`": the vector between the closest points, taken linear in time from one frame
/// to the other, comes within `distance` of zero (a pair crossing faster than a contact
/// distance per frame counts too). Pieces whose closest point is an end in either frame are
/// skipped (a piece sliding past the end of another turns that direction without any
/// crossing), so a crossing whose closest points stay at an end in one of the frames is not
/// counted by that pair (its neighbours usually count it). Pairs found by geometry/UniformGrid,
/// in order (strandA, pieceA, strandB, pieceB).
std::vector<PassThrough> findPassThroughs(const std::vector<std::vector<Eigen::Vector3d>>& before,
                                          const std::vector<std::vector<Eigen::Vector3d>>& after,
                                          double distance);

} // namespace hair
