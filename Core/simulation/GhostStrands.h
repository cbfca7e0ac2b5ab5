#pragma once
// Ghost strands under MPI: copies of other ranks' strands that lie near this rank's, sent
// frame by frame, so that what works on a rank's piece near its edges (interpolating rendered
// hair between neighbouring guides) sees the neighbouring pieces' strands as if they were
// there: ParaView's ghost cells, for strands.
#include "common/Ranks.h"
#include "io/StateFile.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace hair
{

/// The typical distance between neighbouring roots: the median, over the roots, of the
/// distance to the nearest other root (0 for fewer than two roots).
double typicalSpacing(const std::vector<Eigen::Vector3d>& roots);

class GhostStrands
{
public:
  /// Which strands rank `rank` holds as ghosts, and which of its own it sends to whom: the
  /// strands of other ranks whose roots lie within `reach` of the root of one of its own.
  /// `roots` and `owner` (each strand's rank) are the whole run's, the same on every rank,
  /// so every rank plans its part of the same exchange without a message; nearness is
  /// mutual, so the ranks that exchange are each other's partners.
  void plan(const std::vector<Eigen::Vector3d>& roots, const std::vector<int>& owner, int rank,
            double reach);
  /// This rank's ghost strands, increasing.
  const std::vector<std::int64_t>& ghosts() const { return Ghosts; }
  /// The ranks this one exchanges strands with.
  const std::vector<int>& partners() const { return Partners; }

  /// Collective: sends the strands of this rank's `piece` (of the strands `mine` describes)
  /// that others hold as ghosts, and gives the ghosts' frame: the strands of
  /// `run`.piece(ghosts()) (`run` is the whole run's header), their points, velocities,
  /// per-point arrays, q, q̇ and roots, at the piece's time. Two messages each way per
  /// partner.
  Status exchange(const Ranks& ranks, const StateHeader& run, const StateHeader& mine,
                  const StateFrame& piece, StateFrame& ghosts) const;

private:
  std::vector<int> Partners;
  std::vector<std::vector<std::int64_t>> Send;    ///< per partner: own strands it needs
  std::vector<std::vector<std::int64_t>> Receive; ///< per partner: its strands held here
  std::vector<std::int64_t> Ghosts;
};

} // namespace hair
