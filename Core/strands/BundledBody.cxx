#include "strands/BundledBody.h"

#include "strands/RootSampling.h"

#include <cmath>

namespace hair
{
namespace bundled
{

bool isBundledBody(const TriangleMesh& mesh)
{
  const auto [lo, hi] = mesh.bounds();
  return std::abs(lo.y()) < 0.02 && std::abs(hi.y() - 1.66) < 0.02;
}

std::vector<std::uint8_t> scalp(const TriangleMesh& mesh)
{
  constexpr double Degree = 3.14159265358979323846 / 180;
  const Eigen::Vector3d axis(0, std::cos(36.5 * Degree), -std::sin(36.5 * Degree));
  return capRegion(mesh, headCentre(), axis, 88 * Degree, 0.16, 0.5);
}

} // namespace bundled
} // namespace hair
