#include "analysis/StrandAnalysis.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

namespace hair
{

namespace
{
bool allFinite(const std::vector<double>& values)
{
  return std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
}

/// z of (a − o) × (b − o): > 0 when o, a, b turn counter-clockwise.
double turn(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b)
{
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

/// Indices of the convex hull's vertices of `p` (Andrew's monotone chain; collinear points
/// on an edge are left out, which cannot drop a farthest pair: both ends of one are
/// extreme points).
std::vector<std::size_t> convexHull(const std::vector<Eigen::Vector2d>& p)
{
  std::vector<std::size_t> order(p.size());
  for (std::size_t i = 0; i < p.size(); ++i)
  {
    order[i] = i;
  }
  std::sort(order.begin(), order.end(),
            [&p](std::size_t a, std::size_t b)
            { return p[a].x() < p[b].x() || (p[a].x() == p[b].x() && p[a].y() < p[b].y()); });
  if (order.size() < 3)
  {
    return order;
  }
  std::vector<std::size_t> hull(2 * order.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < order.size(); ++i) // lower chain
  {
    while (k >= 2 && turn(p[hull[k - 2]], p[hull[k - 1]], p[order[i]]) <= 0)
    {
      --k;
    }
    hull[k++] = order[i];
  }
  for (std::size_t i = order.size() - 1, lower = k + 1; i-- > 0;) // upper chain
  {
    while (k >= lower && turn(p[hull[k - 2]], p[hull[k - 1]], p[order[i]]) <= 0)
    {
      --k;
    }
    hull[k++] = order[i];
  }
  hull.resize(k - 1); // the last point is the first one again
  return hull;
}
} // namespace

Status StrandsFrame::validate(bool empty) const
{
  if (empty && offsets.size() <= 1 && positions.empty() && curvature.empty() && twist.empty() &&
      contactDepth.empty() && ids.empty())
  {
    return Status::Ok();
  }
  if (offsets.size() < 2)
  {
    return Status::Error("the frame has no strand (offsets hold fewer than two values).");
  }
  if (!ids.empty() && ids.size() != numberOfStrands())
  {
    return Status::Error("the frame has " + std::to_string(ids.size()) + " strand numbers for " +
                         std::to_string(numberOfStrands()) + " strands.");
  }
  if (offsets.front() != 0)
  {
    return Status::Error("the strands' offsets start at " + std::to_string(offsets.front()) +
                         ", not 0.");
  }
  for (std::size_t k = 0; k + 1 < offsets.size(); ++k)
  {
    if (offsets[k + 1] - offsets[k] < 2)
    {
      return Status::Error("strand " + std::to_string(k) + " has " +
                           std::to_string(offsets[k + 1] - offsets[k]) +
                           " points; a strand needs at least its root and its tip.");
    }
  }
  const std::size_t n = static_cast<std::size_t>(offsets.back());
  const std::pair<const char*, std::size_t> sizes[] = {{"positions", positions.size()},
                                                       {"curvature", curvature.size()},
                                                       {"twist", twist.size()},
                                                       {"contact_depth", contactDepth.size()}};
  for (const auto& [name, size] : sizes)
  {
    if (size != n)
    {
      return Status::Error(std::string("the frame has ") + std::to_string(size) + " " + name +
                           " values for " + std::to_string(n) + " points.");
    }
  }
  for (const Eigen::Vector3d& p : positions)
  {
    if (!p.allFinite())
    {
      return Status::Error("the frame has a position that is not finite (NaN or infinite).");
    }
  }
  if (!allFinite(curvature) || !allFinite(twist) || !allFinite(contactDepth))
  {
    return Status::Error(
        "the frame's curvature, twist or contact_depth holds a value that is not finite.");
  }
  return Status::Ok();
}

namespace
{
/// The points whose projections on the plane perpendicular to `vertical` are the vertices of
/// the projections' convex hull (all of them for fewer than three).
std::vector<std::size_t> horizontalHull(const std::vector<Eigen::Vector3d>& points,
                                        const Eigen::Vector3d& vertical)
{
  const Eigen::Vector3d up = vertical.normalized();
  const Eigen::Vector3d e1 = up.unitOrthogonal();
  const Eigen::Vector3d e2 = up.cross(e1);
  std::vector<Eigen::Vector2d> plane(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    plane[i] = Eigen::Vector2d(points[i].dot(e1), points[i].dot(e2));
  }
  return convexHull(plane);
}
} // namespace

double horizontalDiameter(const std::vector<Eigen::Vector3d>& points,
                          const Eigen::Vector3d& vertical)
{
  if (points.size() < 2)
  {
    return 0;
  }
  const Eigen::Vector3d up = vertical.normalized();
  // The projections, in 3-D (for the distances); the hull in a basis of the plane.
  std::vector<Eigen::Vector3d> flat(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    flat[i] = points[i] - points[i].dot(up) * up;
  }
  const std::vector<std::size_t> hull = horizontalHull(points, vertical);
  // Every pair of hull vertices: the hull of a group of tips has few vertices.
  double widest = 0;
  for (std::size_t a = 0; a < hull.size(); ++a)
  {
    for (std::size_t b = a + 1; b < hull.size(); ++b)
    {
      widest = std::max(widest, (flat[hull[a]] - flat[hull[b]]).norm());
    }
  }
  return widest;
}

double lateralDeflection(const Eigen::Vector3d& root, const Eigen::Vector3d& tip,
                         const Eigen::Vector3d& vertical)
{
  const Eigen::Vector3d up = vertical.normalized();
  const Eigen::Vector3d d = tip - root;
  return (d - d.dot(up) * up).norm();
}

Status StrandAnalysis::configure(const StrandAnalysisOptions& options)
{
  if (!options.vertical.allFinite() || options.vertical.norm() == 0)
  {
    return Status::Error("the vertical direction is zero or not finite: give the up "
                         "direction, e.g. (0, 1, 0) for the bundled body.");
  }
  for (const auto* list : {&options.tracked, &options.group})
  {
    for (std::int64_t k : *list)
    {
      if (k < 0)
      {
        return Status::Error("strand " + std::to_string(k) +
                             " does not exist: strand numbers start at 0.");
      }
    }
  }
  Options = options;
  ReferenceTips.clear();
  return Status::Ok();
}

Status StrandAnalysis::measure(const StrandsFrame& frame, StrandMeasures& out, const Ranks& ranks)
{
  const bool shared = ranks.parallel();
  Status s = frame.validate(shared);
  const std::size_t strands = frame.numberOfStrands();
  // Where each named strand is in this frame (−1: not here; under MPI, another rank's).
  std::map<std::int64_t, std::int64_t> indexOf;
  for (std::size_t k = 0; s && k < strands; ++k)
  {
    indexOf[frame.id(k)] = std::int64_t(k);
  }
  auto where = [&](const std::vector<std::int64_t>& named)
  {
    std::vector<std::int64_t> at;
    for (std::int64_t id : named)
    {
      const auto it = indexOf.find(id);
      at.push_back(it == indexOf.end() ? -1 : it->second);
    }
    return at;
  };
  const std::vector<std::int64_t> tracked = where(Options.tracked), group = where(Options.group);
  if (s && !shared)
  {
    for (const auto* list : {&Options.tracked, &Options.group})
    {
      for (std::int64_t id : *list)
      {
        if (s && !indexOf.count(id))
        {
          s = Status::Error("strand " + std::to_string(id) + " does not exist: the strands are " +
                            (frame.ids.empty()
                                 ? "0 … " + std::to_string(strands - 1)
                                 : "numbered " + std::to_string(indexOf.begin()->first) + " … " +
                                       std::to_string(indexOf.rbegin()->first)) +
                            ".");
        }
      }
    }
  }
  if (s && !ReferenceTips.empty() && ReferenceTips.size() != strands)
  {
    s = Status::Error("the frame has " + std::to_string(strands) +
                      " strands, the first frame had " + std::to_string(ReferenceTips.size()) +
                      ": the strands must stay the same over time.");
  }
  if (Status agreed = ranks.agree(s); !agreed)
  {
    return agreed;
  }
  std::vector<Eigen::Vector3d> tips(strands);
  for (std::size_t k = 0; k < strands; ++k)
  {
    tips[k] = frame.positions[frame.offsets[k + 1] - 1];
  }
  if (ReferenceTips.empty())
  {
    ReferenceTips = tips;
  }

  out = StrandMeasures();
  double deflectionSum = 0, displacementSum = 0;
  for (std::size_t k = 0; k < strands; ++k)
  {
    out.meanTip += tips[k];
    const double deflection =
        lateralDeflection(frame.positions[frame.offsets[k]], tips[k], Options.vertical);
    out.maxDeflection = std::max(out.maxDeflection, deflection);
    deflectionSum += deflection;
    const double displacement = (tips[k] - ReferenceTips[k]).norm();
    out.maxTipDisplacement = std::max(out.maxTipDisplacement, displacement);
    displacementSum += displacement;
  }
  for (std::size_t i = 0; i < frame.positions.size(); ++i)
  {
    out.maxCurvature = std::max(out.maxCurvature, std::abs(frame.curvature[i]));
    out.maxTwist = std::max(out.maxTwist, std::abs(frame.twist[i]));
    if (frame.contactDepth[i] > 0)
    {
      ++out.contacts;
      out.maxContactDepth = std::max(out.maxContactDepth, frame.contactDepth[i]);
    }
  }
  std::vector<Eigen::Vector3d> groupTips;
  if (Options.group.empty())
  {
    groupTips = tips;
  }
  else
  {
    for (std::int64_t k : group)
    {
      if (k >= 0)
      {
        groupTips.push_back(tips[k]);
      }
    }
  }
  double count = double(strands);
  for (std::int64_t k : tracked)
  {
    out.trackedTips.push_back(k >= 0 ? tips[k] : Eigen::Vector3d::Zero());
  }
  if (shared)
  {
    // Sums (strands, tips, deflections, displacements, contacts, and each tracked strand's
    // tip with a count of the ranks that have it), maxima, and every piece's hull vertices.
    std::vector<double> sums{count,         out.meanTip.x(), out.meanTip.y(),     out.meanTip.z(),
                             deflectionSum, displacementSum, double(out.contacts)};
    for (std::size_t i = 0; i < tracked.size(); ++i)
    {
      sums.push_back(tracked[i] >= 0 ? 1 : 0);
      sums.insert(sums.end(), out.trackedTips[i].data(), out.trackedTips[i].data() + 3);
    }
    std::vector<double> found(group.size());
    for (std::size_t i = 0; i < group.size(); ++i)
    {
      found[i] = group[i] >= 0 ? 1 : 0;
    }
    sums.insert(sums.end(), found.begin(), found.end());
    ranks.sum(sums.data(), int(sums.size()));
    double maxima[5] = {out.maxDeflection, out.maxTipDisplacement, out.maxCurvature, out.maxTwist,
                        out.maxContactDepth};
    ranks.max(maxima, 5);
    std::vector<double> hull;
    for (std::size_t i : horizontalHull(groupTips, Options.vertical))
    {
      hull.insert(hull.end(), groupTips[i].data(), groupTips[i].data() + 3);
    }
    const std::vector<double> all = ranks.gather(hull);
    groupTips.assign(all.size() / 3, Eigen::Vector3d::Zero());
    for (std::size_t i = 0; i < groupTips.size(); ++i)
    {
      groupTips[i] = Eigen::Vector3d(all[3 * i], all[3 * i + 1], all[3 * i + 2]);
    }
    count = sums[0];
    out.meanTip = Eigen::Vector3d(sums[1], sums[2], sums[3]);
    deflectionSum = sums[4];
    displacementSum = sums[5];
    out.contacts = std::int64_t(std::llround(sums[6]));
    std::size_t at = 7;
    for (std::size_t i = 0; i < tracked.size(); ++i, at += 4)
    {
      if (sums[at] != 1)
      {
        return Status::Error("strand " + std::to_string(Options.tracked[i]) +
                             " is not in the frame (in no rank's piece).");
      }
      out.trackedTips[i] = Eigen::Vector3d(sums[at + 1], sums[at + 2], sums[at + 3]);
    }
    for (std::size_t i = 0; i < group.size(); ++i, ++at)
    {
      if (sums[at] != 1)
      {
        return Status::Error("strand " + std::to_string(Options.group[i]) +
                             " is not in the frame (in no rank's piece).");
      }
    }
    if (count == 0)
    {
      return Status::Error("the frame has no strand on any rank.");
    }
    out.maxDeflection = maxima[0];
    out.maxTipDisplacement = maxima[1];
    out.maxCurvature = maxima[2];
    out.maxTwist = maxima[3];
    out.maxContactDepth = maxima[4];
  }
  out.meanTip /= count;
  out.meanDeflection = deflectionSum / count;
  out.meanTipDisplacement = displacementSum / count;
  out.span = horizontalDiameter(groupTips, Options.vertical);
  return Status::Ok();
}

} // namespace hair
