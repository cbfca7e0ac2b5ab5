#pragma once
// The cluster model of Kurihara, Anjyo and Thalmann (1993): only guide strands are
// simulated; each rendered strand is a copy of a guide moved by a random offset of its
// root in the root's tangent plane (the paper: 20 per guide). Seeded, so that renders
// repeat.
#include "common/Status.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace hair
{

struct ClusterOptions
{
  int copiesPerGuide = 20;   ///< rendered strands per guide (the guide itself not included)
  double radius = 5e-3;      ///< root offsets are uniform in a disc of this radius, metres
  std::uint64_t seed = 1993; ///< same seed, same offsets
  Status validate() const;
};

/// The offsets, drawn once, in each guide's root frame: e1, e2 span the plane across the
/// first segment (the scalp's tangent plane when the strand leaves along the normal).
class Cluster
{
public:
  /// Draws `copiesPerGuide` offsets for each of `guides` guides. Refuses guides ≤ 0.
  Status initialize(int guides, const ClusterOptions& options);

  int numberOfGuides() const { return Guides; }
  int copiesPerGuide() const { return Options.copiesPerGuide; }
  /// Offset of copy c of guide g in the guide's root frame (third component 0).
  const Eigen::Vector3d& offset(int g, int c) const
  {
    return Offsets[static_cast<std::size_t>(g) * Options.copiesPerGuide + c];
  }

  /// Rendered strands of guide g: its nodes (world) translated by rootFrame · offset.
  /// Appends copiesPerGuide polylines to `out`.
  void render(int g, const std::vector<Eigen::Vector3d>& guideNodes,
              const Eigen::Matrix3d& rootFrame,
              std::vector<std::vector<Eigen::Vector3d>>& out) const;

private:
  int Guides = 0;
  ClusterOptions Options;
  std::vector<Eigen::Vector3d> Offsets;
};

} // namespace hair
