#include "strands/GuideGrowth.h"

#include "common/Partition.h"

#include <sstream>

#include <cmath>

namespace hair
{

Status GrowthOptions::validate() const
{
  if (!(length >= minLength && length <= maxLength))
  {
    std::ostringstream m;
    m << "the strand length is " << length << " m; give a length from " << minLength << " to "
      << maxLength << " m.";
    return Status::Error(m.str());
  }
  if (elements < 1 || elements > maxElements)
  {
    return Status::Error("a strand of " + std::to_string(elements) + " elements: give 1 to " +
                         std::to_string(maxElements) + ".");
  }
  if (combed)
  {
    if (!combDirection.allFinite() || !(combDirection.norm() > 0))
    {
      return Status::Error("the comb direction is zero or NaN: give a direction.");
    }
    if (!(combWeight >= 0 && combWeight <= 1))
    {
      std::ostringstream m;
      m << "the comb weight is " << combWeight << "; give a weight in [0, 1].";
      return Status::Error(m.str());
    }
  }
  return hair.validate();
}

Status growGuides(const std::vector<Root>& roots, const GrowthOptions& options,
                  std::vector<GuideStrand>& guides)
{
  if (Status s = options.validate(); !s)
  {
    return s;
  }
  const Eigen::Vector3d comb = options.combDirection.normalized();
  // Numbered along the roots' Hilbert curve, the curve the strands are shared among MPI
  // ranks by (common/Partition.h): each rank's share is a range of numbers, written as one
  // run of rows of the state file.
  std::vector<Eigen::Vector3d> positions;
  for (const Root& r : roots)
  {
    positions.push_back(r.position);
  }
  const std::vector<std::size_t> order = spaceFillingOrder(positions);
  std::vector<GuideStrand> out(roots.size());
  for (std::size_t k = 0; k < roots.size(); ++k)
  {
    const std::size_t from = order[k];
    GuideStrand& g = out[k];
    g.root = roots[from].position;
    g.normal = roots[from].normal;
    g.growth = roots[from].normal;
    if (options.combed)
    {
      const Eigen::Vector3d blend = (1 - options.combWeight) * g.normal + options.combWeight * comb;
      if (blend.norm() > 1e-9)
      {
        g.growth = blend.normalized();
      }
    }
    g.length = options.length;
    g.elements = options.elements;
    g.hair = options.hair;
    // The model varies strand k's natural curvature by the seed seed + k: the variation
    // stays that of the root's place among the roots given, whatever its number.
    g.seed = options.seed + static_cast<std::uint32_t>(from) - static_cast<std::uint32_t>(k);
  }
  guides = std::move(out);
  return Status::Ok();
}

std::vector<Eigen::Vector3d> grownPolyline(const GuideStrand& g)
{
  std::vector<Eigen::Vector3d> points(g.elements + 1);
  for (int i = 0; i <= g.elements; ++i)
  {
    points[i] = g.root + (g.length * i / g.elements) * g.growth;
  }
  return points;
}

} // namespace hair
