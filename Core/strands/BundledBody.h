#pragma once
// What is known of the bundled body (Data/body.vtk, MakeHuman, Y up, facing +Z): where its
// head is, where the head turns, where hair grows, and how to recognise the mesh. One home
// for these numbers; Data/body_parts.txt holds its collision tables' frames.
#include "geometry/TriangleMesh.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace hair
{
namespace bundled
{

/// The head's centre (the origin of its spherical table in Data/body_parts.txt), m.
inline Eigen::Vector3d headCentre()
{
  return Eigen::Vector3d(0, 1.555, 0.055);
}
/// Where the head turns when it shakes or nods: the top of the neck, below the head's
/// centre and a little behind it, m.
inline Eigen::Vector3d neckPivot()
{
  return Eigen::Vector3d(0, 1.45, 0.02);
}

/// Whether `mesh` is the bundled body: its bounding box runs from the soles (y ≈ 0) to the
/// crown (y ≈ 1.66 m).
bool isBundledBody(const TriangleMesh& mesh);

/// The scalp: a cap about the head's centre, its axis tilted 36.5° back from +Y,
/// half-angle 88°, within 0.16 m, on triangles facing within 60° of the direction from the
/// centre: from the hairline at the top of the forehead (y ≈ 1.615) to the nape
/// (y ≈ 1.49), above the ears.
std::vector<std::uint8_t> scalp(const TriangleMesh& mesh);

} // namespace bundled
} // namespace hair
