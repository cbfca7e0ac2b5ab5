#pragma once
// Reading meshes without VTK: Core's tests, benchmarks and studies read the bundled body
// (Data/body.vtk, legacy VTK polydata) through this.
#include "common/Status.h"
#include "geometry/TriangleMesh.h"

#include <string>
#include <vector>

namespace hair
{

/// Reads an ASCII legacy VTK file holding POLYDATA with POINTS and POLYGONS (polygons are
/// split into fans of triangles). Anything else is refused with a message naming the file
/// and the line.
Status readVtkPolyData(const std::string& path, TriangleMesh& mesh);

} // namespace hair
