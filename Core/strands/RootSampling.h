#pragma once
// Where guide strands grow: roots spread evenly over a region of a surface.
#include "common/Status.h"
#include "geometry/TriangleMesh.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace hair
{

struct Root
{
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitY(); ///< unit, out of the surface
  int triangle = -1;
};

struct RootSamplingOptions
{
  /// The farthest-point selection costs count² × candidatesPerRoot distance tests
  /// (quadratic: minutes at 100 000); more guides than this are refused (rendered hair
  /// comes from Hair Interpolation, not from guides).
  static constexpr int maxCount = 100000;
  int count = 200;
  std::uint32_t seed = 1;
  /// Candidates drawn per root before the even selection (more: more even, slower).
  int candidatesPerRoot = 8;
};

/// `count` points drawn uniformly by area (seeded) over the triangles of `mesh` where
/// `region` is non-zero (all when empty), with their triangles' normals: the candidates of
/// sampleRoots, and the roots of rendered hair. Refuses an empty region. The mesh must have
/// passed validate().
Status sampleUniformly(const TriangleMesh& mesh, const std::vector<std::uint8_t>& region,
                       std::size_t count, std::uint32_t seed, std::vector<Root>& samples);

/// Spreads `count` roots evenly over the triangles of `mesh` where `region` is non-zero
/// (all triangles when `region` is empty): candidates are drawn uniformly by area (seeded),
/// then roots are picked one by one as the candidate farthest from those already picked
/// (farthest-point sampling), which spaces them almost like a hexagonal packing. Normals are
/// the triangles' (oriented as the mesh is; MeshQueries orients a closed mesh outwards).
/// Refuses an empty region, a count outside [1, maxCount], and NaN.
Status sampleRoots(const TriangleMesh& mesh, const std::vector<std::uint8_t>& region,
                   const RootSamplingOptions& options, std::vector<Root>& roots);

/// Triangles whose centroid lies within `maxDistance` of `centre` and within `halfAngle`
/// (radians) of `axis` seen from `centre` (a spherical cap, e.g. a scalp), and whose normal
/// makes a cosine of at least `minFacing` with the direction from the centre (which leaves
/// out the backs of ears and other creases facing the head).
std::vector<std::uint8_t> capRegion(const TriangleMesh& mesh, const Eigen::Vector3d& centre,
                                    const Eigen::Vector3d& axis, double halfAngle,
                                    double maxDistance, double minFacing = -1);

} // namespace hair
