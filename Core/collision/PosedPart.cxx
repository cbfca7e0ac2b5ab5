#include "collision/PosedPart.h"

#include <algorithm>

namespace hair
{

namespace
{
/// PosedPart::near for a point already in the part's rest coordinates.
bool nearAtRest(const CollisionTable& table, const Eigen::Vector3d& rest, double slack)
{
  const TableSpec& spec = table.spec();
  const Eigen::Vector3d rel = rest - spec.frame.origin;
  const double reach = table.reach() + slack;
  if (spec.projection == Projection::Spherical)
  {
    return rel.squaredNorm() <= reach * reach;
  }
  const Eigen::Vector3d a = table.basis().col(2);
  const double h = rel.dot(a);
  return h >= spec.heightMin && h <= spec.heightMax && (rel - h * a).squaredNorm() <= reach * reach;
}

/// PosedPart::query for a point given in both coordinates.
TableQuery queryAtRest(const PosedPart& part, const Eigen::Vector3d& x, const Eigen::Vector3d& rest)
{
  TableQuery q = part.table->query(rest);
  if (q.covered)
  {
    q.surfacePoint = part.pose * q.surfacePoint;
    q.normal = part.pose.linear() * q.normal;
    q.nearest = x + q.depth * q.normal; // T = P + ((Q − P)·N) N, in world coordinates
  }
  return q;
}
} // namespace

PosedPart PosedPart::still(const CollisionTable& table)
{
  PosedPart p;
  p.table = &table;
  return p;
}

TableQuery PosedPart::query(const Eigen::Vector3d& x) const
{
  return queryAtRest(*this, x, toRest(x));
}

bool PosedPart::near(const Eigen::Vector3d& x, double slack) const
{
  return nearAtRest(*table, toRest(x), slack);
}

bool deepestPart(const std::vector<PosedPart>& parts, const Eigen::Vector3d& x, double slack,
                 PartContact& contact)
{
  contact = PartContact();
  bool any = false;
  double best = 0;
  for (std::size_t k = 0; k < parts.size(); ++k)
  {
    const PosedPart& part = parts[k];
    const Eigen::Vector3d rest = part.toRest(x);
    if (!nearAtRest(*part.table, rest, slack))
    {
      continue;
    }
    const TableQuery q = queryAtRest(part, x, rest);
    if (!q.covered)
    {
      continue;
    }
    // The table's inside test is authoritative; the depth along N follows it in sign
    // (where the interpolated normal disagrees with it near an edge of the table).
    const double depth = q.inside ? std::max(q.depth, 1e-9) : std::min(q.depth, 0.0);
    if (!any || depth > best)
    {
      any = true;
      best = depth;
      contact.part = static_cast<int>(k);
      contact.depth = depth;
      contact.normal = q.normal;
      contact.surface = q.surfacePoint;
    }
  }
  return any;
}

bool insideAny(const std::vector<PosedPart>& parts, const Eigen::Vector3d& x)
{
  for (const PosedPart& part : parts)
  {
    const Eigen::Vector3d rest = part.toRest(x);
    if (nearAtRest(*part.table, rest, 0) && part.table->inside(rest))
    {
      return true;
    }
  }
  return false;
}

bool insideDepth(const std::vector<PosedPart>& parts, const Eigen::Vector3d& x, double& depth)
{
  bool inside = false;
  depth = 0;
  for (const PosedPart& part : parts)
  {
    const Eigen::Vector3d rest = part.toRest(x);
    if (!nearAtRest(*part.table, rest, 0))
    {
      continue; // farther from the axis than any of its surface: not inside
    }
    const TableQuery q = queryAtRest(part, x, rest);
    if (q.inside)
    {
      inside = true;
      depth = std::max(depth, std::max(q.depth, 0.0));
    }
  }
  return inside;
}

double drapeOutside(const std::vector<PosedPart>& parts, double clearance,
                    std::vector<Eigen::Vector3d>& points)
{
  const std::vector<Eigen::Vector3d> grown = points;
  double moved = 0;
  for (std::size_t i = 1; i < points.size(); ++i)
  {
    const Eigen::Vector3d segment = grown[i] - grown[i - 1];
    const double length = segment.norm();
    Eigen::Vector3d q = points[i - 1] + segment;
    PartContact c;
    // Out along the normal, back to the segment's length; where that does not leave the part
    // within a few turns (a segment pointing into a concave place), the last try is kept.
    for (int iter = 0; iter < 8 && deepestPart(parts, q, clearance, c) && c.depth > 0; ++iter)
    {
      const Eigen::Vector3d target = q + (c.depth + clearance) * c.normal;
      const Eigen::Vector3d towards = target - points[i - 1];
      if (!(towards.norm() > 0))
      {
        break;
      }
      q = points[i - 1] + length * towards.normalized();
    }
    points[i] = q;
    moved = std::max(moved, (q - grown[i]).norm());
  }
  return moved;
}

} // namespace hair
