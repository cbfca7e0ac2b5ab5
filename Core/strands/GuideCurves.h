#pragma once
// Guide strands from guide curves (polylines, root first): each curve checked on its own
// (one point, a NaN, a repeated point, a fold back on itself, a length out of range, a root
// far from the scalp), its root moved onto the scalp when one is given, and made a groomed
// guide (GuideStrand::curve). A curve that is refused is named with the reason and left out;
// the others are kept.
#include "common/Status.h"
#include "geometry/TriangleMesh.h"
#include "strands/GuideStrand.h"
#include "strands/HairParameters.h"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace hair
{

struct CurveGuideOptions
{
  int elements = 10; ///< Super-Helix elements or projective segments per guide
  HairParameters hair;
  std::uint32_t seed = 1;
  RestShape restShape = RestShape::AsGrown;
  /// With a scalp: a curve whose first point is farther than this from it is refused [m];
  /// a nearer one has its root moved onto the scalp (the whole curve translated with it).
  double maxRootDistance = 0.01;
  static constexpr double minLength = 0.001, maxLength = 2; ///< m, as Hair Strands grows them
  static constexpr int maxElements = 100;
  /// Refuses elements outside [1, maxElements], a maximum root distance that is negative or
  /// NaN, and bad hair parameters.
  Status validate() const;
};

/// Why a curve was left out.
struct CurveRefusal
{
  int curve = -1; ///< index in the input
  std::string reason;
};

/// One guide per curve that passes the checks, in the input's order; `source[i]` is the index
/// of the curve guide i comes from, `refused` names every other curve and why. `normals`
/// (empty, or one per curve; a zero or NaN entry counts as none) gives the root normal of a
/// curve when there is no scalp, as a RootNormal cell array of the curves does. With a
/// `scalp` the root normal is the scalp's at the moved root, out of the solid for a closed
/// surface (turned towards the curve's first segment for an open one); without either it is
/// the first segment's direction (the root frame's roll is then Eigen's unitOrthogonal: a
/// gauge that changes no shape). Returns an error only for bad options or when every curve is
/// refused (the message names the first few).
Status guidesFromCurves(const std::vector<std::vector<Eigen::Vector3d>>& curves,
                        const std::vector<Eigen::Vector3d>& normals, const MeshQueries* scalp,
                        const CurveGuideOptions& options, std::vector<GuideStrand>& guides,
                        std::vector<int>& source, std::vector<CurveRefusal>& refused);

/// The check of one curve alone (what guidesFromCurves refuses it for), without the scalp:
/// empty when it can be a guide.
std::string curveProblem(const std::vector<Eigen::Vector3d>& curve);

} // namespace hair
