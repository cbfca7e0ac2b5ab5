#pragma once
// A guide strand as it is grown (Hair Strands) and handed to a model: where it roots, which
// way it leaves the scalp, how long it is, how finely a model cuts it, and its hair type.
#include "common/Status.h"
#include "strands/HairParameters.h"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace hair
{

/// What a strand's natural shape (the shape it takes with no load) is set to when a model
/// builds it.
enum class RestShape
{
  /// The model's own: the hair type's natural helix (Super-Helix; the projective model's
  /// rest angles are the strand's shape at t = 0). Under gravity the strand then sags away
  /// from its shape at t = 0.
  AsGrown = 0,
  /// Chosen so that the strand's shape at t = 0 is a stable static equilibrium under gravity
  /// and the body's contacts (inverse statics, docs/super-helix.md and
  /// docs/projective-strands.md, "Sag-free rest shape"); where no natural shape can hold it,
  /// the closest stable one, reported per strand.
  SagFree = 1
};

struct GuideStrand
{
  Eigen::Vector3d root = Eigen::Vector3d::Zero();
  Eigen::Vector3d growth = Eigen::Vector3d::UnitY(); ///< direction of the first element
  Eigen::Vector3d normal = Eigen::Vector3d::UnitY(); ///< scalp normal at the root
  double length = 0.3;                               ///< m
  int elements = 10; ///< Super-Helix elements, or projective segments
  HairParameters hair;
  std::uint32_t seed = 1; ///< of the natural-curvature variation
  /// The groom: a guide curve the strand starts in, root first (curve[0] == root). Empty: the
  /// strand grows straight along `growth` in its natural shape (as Hair Strands grows it).
  /// A model fits it (Super-Helix: curvatures and twist per element; projective: equal
  /// segments along it), so the strand's length and root tangent become the fit's.
  std::vector<Eigen::Vector3d> curve;
  RestShape restShape = RestShape::AsGrown;

  /// Bounds that keep a strand's work and memory sane whatever a file or an array says (a
  /// Super-Helix of N elements assembles N × N blocks; positions of 1e300 m overflow).
  static constexpr int maxElements = 1000;
  static constexpr double maxLength = 10; ///< m

  /// Refuses a NaN root, a zero or NaN growth direction, a NaN normal, elements outside
  /// [1, maxElements], a length outside (0, maxLength] m, bad hair parameters, and a curve
  /// of one point, with a NaN, a repeated point or a root other than `root`. The message
  /// starts with `what` (e.g. "strand 3").
  Status validate(const std::string& what) const;
  /// Orthonormal root frame: n0 along the growth, n1 as close as possible to the scalp
  /// normal made perpendicular (any perpendicular when they are parallel), n2 = n0 × n1.
  Eigen::Matrix3d rootFrame() const;
};

/// Columns n0 along `first`, n1 as close to `second` as possible made perpendicular to n0
/// (any perpendicular when they are parallel), n2 = n0 × n1.
Eigen::Matrix3d orthonormalFrame(const Eigen::Vector3d& first, const Eigen::Vector3d& second);

} // namespace hair
