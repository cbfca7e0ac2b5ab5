#include "strands/RootSampling.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace hair
{

Status sampleUniformly(const TriangleMesh& mesh, const std::vector<std::uint8_t>& region,
                       std::size_t count, std::uint32_t seed, std::vector<Root>& samples)
{
  if (!region.empty() && region.size() != mesh.triangles.size())
  {
    return Status::Error("the scalp region has " + std::to_string(region.size()) + " flags for " +
                         std::to_string(mesh.triangles.size()) + " triangles.");
  }
  // Cumulative area of the region's triangles.
  std::vector<double> cumulative;
  std::vector<int> ids;
  double total = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
  {
    if (!region.empty() && !region[t])
    {
      continue;
    }
    const auto& tri = mesh.triangles[t];
    const double area = 0.5 * (mesh.points[tri[1]] - mesh.points[tri[0]])
                                  .cross(mesh.points[tri[2]] - mesh.points[tri[0]])
                                  .norm();
    if (area > 0)
    {
      total += area;
      cumulative.push_back(total);
      ids.push_back(static_cast<int>(t));
    }
  }
  if (ids.empty())
  {
    return Status::Error("the scalp region is empty (no triangle of positive area is selected): "
                         "choose a region on the surface, or none to use all of it.");
  }
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(0, 1);
  samples.assign(count, Root{});
  for (Root& c : samples)
  {
    const double a = U(rng) * total;
    const std::size_t k = std::min<std::size_t>(
        std::lower_bound(cumulative.begin(), cumulative.end(), a) - cumulative.begin(),
        ids.size() - 1);
    const auto& tri = mesh.triangles[ids[k]];
    double u = U(rng), v = U(rng);
    if (u + v > 1)
    {
      u = 1 - u;
      v = 1 - v;
    }
    const Eigen::Vector3d &A = mesh.points[tri[0]], &B = mesh.points[tri[1]],
                          &C = mesh.points[tri[2]];
    c.position = A + u * (B - A) + v * (C - A);
    c.normal = (B - A).cross(C - A).normalized();
    c.triangle = ids[k];
  }
  return Status::Ok();
}

Status sampleRoots(const TriangleMesh& mesh, const std::vector<std::uint8_t>& region,
                   const RootSamplingOptions& options, std::vector<Root>& roots)
{
  if (Status s = mesh.validate("the scalp surface"); !s)
  {
    return s;
  }
  if (options.count < 1 || options.count > RootSamplingOptions::maxCount)
  {
    return Status::Error("the number of strands is " + std::to_string(options.count) +
                         ": give 1 to " + std::to_string(RootSamplingOptions::maxCount) +
                         " (the even spreading of roots costs the square of their number).");
  }
  if (options.candidatesPerRoot < 1)
  {
    return Status::Error("candidatesPerRoot must be at least 1.");
  }
  const std::size_t m = std::size_t(options.count) * options.candidatesPerRoot;
  std::vector<Root> candidates;
  if (Status s = sampleUniformly(mesh, region, m, options.seed, candidates); !s)
  {
    return s;
  }
  // Farthest-point selection, starting from the first candidate.
  std::vector<double> nearest(m, std::numeric_limits<double>::infinity());
  std::vector<Root> picked;
  picked.reserve(options.count);
  std::size_t next = 0;
  for (int r = 0; r < options.count; ++r)
  {
    picked.push_back(candidates[next]);
    const Eigen::Vector3d p = candidates[next].position;
    double best = -1;
    for (std::size_t i = 0; i < m; ++i)
    {
      nearest[i] = std::min(nearest[i], (candidates[i].position - p).squaredNorm());
      if (nearest[i] > best)
      {
        best = nearest[i];
        next = i;
      }
    }
  }
  roots = std::move(picked);
  return Status::Ok();
}

std::vector<std::uint8_t> capRegion(const TriangleMesh& mesh, const Eigen::Vector3d& centre,
                                    const Eigen::Vector3d& axis, double halfAngle,
                                    double maxDistance, double minFacing)
{
  const Eigen::Vector3d a = axis.normalized();
  const double cosHalf = std::cos(halfAngle);
  std::vector<std::uint8_t> region(mesh.triangles.size(), 0);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
  {
    const auto& tri = mesh.triangles[t];
    const Eigen::Vector3d c =
        (mesh.points[tri[0]] + mesh.points[tri[1]] + mesh.points[tri[2]]) / 3.0 - centre;
    const double d = c.norm();
    const Eigen::Vector3d n = (mesh.points[tri[1]] - mesh.points[tri[0]])
                                  .cross(mesh.points[tri[2]] - mesh.points[tri[0]])
                                  .normalized();
    region[t] = d > 0 && d <= maxDistance && c.dot(a) >= cosHalf * d && n.dot(c) >= minFacing * d;
  }
  return region;
}

} // namespace hair
