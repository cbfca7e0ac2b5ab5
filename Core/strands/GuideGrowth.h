#pragma once
// Guide strands grown from roots: straight, along the scalp normal or combed towards a
// direction, in the natural shape of their hair type (the models curl them at rest).
#include "common/Status.h"
#include "strands/GuideStrand.h"
#include "strands/HairParameters.h"
#include "strands/RootSampling.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace hair
{

struct GrowthOptions
{
  double length = 0.3; ///< m
  int elements = 10;
  /// false: along the scalp normal; true: the normal blended towards `combDirection` by
  /// `combWeight` (0: the normal, 1: the comb direction).
  bool combed = false;
  Eigen::Vector3d combDirection = Eigen::Vector3d(0, -1, 0);
  double combWeight = 0.5;
  HairParameters hair;
  std::uint32_t seed = 1;
  static constexpr double minLength = 0.001, maxLength = 2; ///< m
  static constexpr int maxElements = 100;
  /// Refuses a length outside [minLength, maxLength] (NaN included), elements outside
  /// [1, maxElements], a zero or NaN comb direction or a weight outside [0, 1] when combed,
  /// and bad hair parameters, with the value and the range in the message.
  Status validate() const;
};

/// One guide per root (its normal unit and out of the surface), numbered along the roots'
/// Hilbert curve (common/Partition.h: so that an MPI rank's share is a range of numbers),
/// each with the curvature variation of its root's place among `roots`. The growth
/// direction is the blend of the normal and the comb direction, or the normal where the
/// blend vanishes.
Status growGuides(const std::vector<Root>& roots, const GrowthOptions& options,
                  std::vector<GuideStrand>& guides);

/// The points of a guide as grown: straight from the root along its growth direction,
/// `elements` + 1 of them, equally spaced.
std::vector<Eigen::Vector3d> grownPolyline(const GuideStrand& guide);

} // namespace hair
