#pragma once
// Reading meshes without VTK: Core's tests, benchmarks and studies read the bundled body
// (Data/body.vtk, legacy VTK polydata) through this.
#include "collision/CollisionTable.h"
#include "collision/TriangleMesh.h"
#include "common/Status.h"

#include <string>
#include <vector>

namespace hair
{

/// Reads an ASCII legacy VTK file holding POLYDATA with POINTS and POLYGONS (polygons are
/// split into fans of triangles). Anything else is refused with a message naming the file
/// and the line.
Status readVtkPolyData(const std::string& path, TriangleMesh& mesh);

/// A named body part's table specification, as listed in Data/body_parts.txt.
struct BodyPartSpec
{
  std::string name;
  TableSpec spec;
};

/// Reads a body-part list: one part a line,
///   name projection ox oy oz ax ay az rx ry rz azimuthSamples secondSamples hmin hmax maxRadius
/// projection is "cylindrical" or "spherical"; maxRadius "inf" for none; '#' starts a
/// comment.
Status readBodyParts(const std::string& path, std::vector<BodyPartSpec>& parts);

} // namespace hair
