#include "projective/Cluster.h"

#include <cmath>
#include <random>

namespace hair
{

Status ClusterOptions::validate() const
{
  if (copiesPerGuide < 0)
  {
    return Status::Error("cluster: the number of copies per guide must be ≥ 0");
  }
  if (!std::isfinite(radius) || radius < 0)
  {
    return Status::Error("cluster: the offset radius must be a number ≥ 0 m");
  }
  return Status::Ok();
}

Status Cluster::initialize(int guides, const ClusterOptions& options)
{
  if (guides <= 0)
  {
    return Status::Error("cluster: no guide strands to copy");
  }
  if (Status st = options.validate(); !st)
  {
    return st;
  }
  Guides = guides;
  Options = options;
  Offsets.clear();
  Offsets.reserve(static_cast<std::size_t>(guides) * options.copiesPerGuide);
  // std::mt19937_64 is fully specified by the standard, so the offsets repeat everywhere;
  // the uniform distributions are not, so the mapping to the disc is written out here.
  std::mt19937_64 rng(options.seed);
  auto uniform = [&rng]() { return (rng() >> 11) * (1.0 / 9007199254740992.0); };
  for (int g = 0; g < guides; ++g)
  {
    for (int c = 0; c < options.copiesPerGuide; ++c)
    {
      const double r = options.radius * std::sqrt(uniform());
      const double a = 6.28318530717958647692 * uniform();
      Offsets.emplace_back(r * std::cos(a), r * std::sin(a), 0.0);
    }
  }
  return Status::Ok();
}

void Cluster::render(int g, const std::vector<Eigen::Vector3d>& guideNodes,
                     const Eigen::Matrix3d& rootFrame,
                     std::vector<std::vector<Eigen::Vector3d>>& out) const
{
  for (int c = 0; c < Options.copiesPerGuide; ++c)
  {
    const Eigen::Vector3d shift = rootFrame * offset(g, c);
    std::vector<Eigen::Vector3d> strand(guideNodes.size());
    for (std::size_t i = 0; i < guideNodes.size(); ++i)
    {
      strand[i] = guideNodes[i] + shift;
    }
    out.push_back(std::move(strand));
  }
}

} // namespace hair
