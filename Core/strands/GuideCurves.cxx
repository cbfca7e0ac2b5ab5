#include "strands/GuideCurves.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace hair
{

Status CurveGuideOptions::validate() const
{
  if (elements < 1 || elements > maxElements)
  {
    return Status::Error("a guide of " + std::to_string(elements) + " elements: give 1 to " +
                         std::to_string(maxElements) + ".");
  }
  if (!(maxRootDistance >= 0) || !std::isfinite(maxRootDistance))
  {
    std::ostringstream m;
    m << "the maximum root distance is " << maxRootDistance
      << " m; give a distance >= 0 m (how far from the scalp a curve's first point may be).";
    return Status::Error(m.str());
  }
  return hair.validate();
}

std::string curveProblem(const std::vector<Eigen::Vector3d>& curve)
{
  if (curve.empty())
  {
    return "has no points: a guide curve needs a root and at least one more point";
  }
  if (curve.size() == 1)
  {
    return "has one point: a guide curve needs a root and at least one more point";
  }
  for (std::size_t j = 0; j < curve.size(); ++j)
  {
    if (!curve[j].allFinite())
    {
      return "point " + std::to_string(j) + " is NaN or infinite: fix or remove it";
    }
  }
  double length = 0;
  for (std::size_t j = 1; j < curve.size(); ++j)
  {
    length += (curve[j] - curve[j - 1]).norm();
  }
  for (std::size_t j = 1; j < curve.size(); ++j)
  {
    if (!((curve[j] - curve[j - 1]).norm() > 1e-9 * length))
    {
      return "points " + std::to_string(j - 1) + " and " + std::to_string(j) +
             " are the same point (a segment of zero length): remove the repeated point";
    }
  }
  for (std::size_t j = 1; j + 1 < curve.size(); ++j)
  {
    const Eigen::Vector3d a = (curve[j] - curve[j - 1]).normalized();
    const Eigen::Vector3d b = (curve[j + 1] - curve[j]).normalized();
    if (std::atan2(a.cross(b).norm(), a.dot(b)) > M_PI - 1e-6)
    {
      return "turns straight back on itself at point " + std::to_string(j) +
             " (a fold of 180°, which no strand can follow): remove or move the point";
    }
  }
  if (!(length >= CurveGuideOptions::minLength && length <= CurveGuideOptions::maxLength))
  {
    std::ostringstream m;
    m << "is " << length << " m long: give curves from " << CurveGuideOptions::minLength << " to "
      << CurveGuideOptions::maxLength << " m long";
    return m.str();
  }
  return {};
}

Status guidesFromCurves(const std::vector<std::vector<Eigen::Vector3d>>& curves,
                        const std::vector<Eigen::Vector3d>& normals, const MeshQueries* scalp,
                        const CurveGuideOptions& options, std::vector<GuideStrand>& guides,
                        std::vector<int>& source, std::vector<CurveRefusal>& refused)
{
  if (Status s = options.validate(); !s)
  {
    return s;
  }
  std::vector<GuideStrand> out;
  std::vector<int> from;
  std::vector<CurveRefusal> no;
  const bool closed = scalp && scalp->signedVolume() != 0;
  for (std::size_t k = 0; k < curves.size(); ++k)
  {
    std::vector<Eigen::Vector3d> c = curves[k];
    if (std::string why = curveProblem(c); !why.empty())
    {
      no.push_back({int(k), "curve " + std::to_string(k) + " " + why + "."});
      continue;
    }
    const Eigen::Vector3d first = (c[1] - c[0]).normalized();
    Eigen::Vector3d normal = first;
    if (k < normals.size() && normals[k].allFinite() && normals[k].norm() > 0)
    {
      normal = normals[k].normalized();
    }
    if (scalp)
    {
      Eigen::Vector3d onScalp, n;
      scalp->closestPointAndNormal(c[0], onScalp, n);
      const double distance = (onScalp - c[0]).norm();
      if (!(distance <= options.maxRootDistance))
      {
        std::ostringstream m;
        m << "curve " << k << " starts " << distance << " m from the scalp, more than the "
          << "maximum root distance " << options.maxRootDistance
          << " m: move its first point onto the scalp, or raise the maximum root distance.";
        no.push_back({int(k), m.str()});
        continue;
      }
      const Eigen::Vector3d shift = onScalp - c[0];
      for (Eigen::Vector3d& x : c)
      {
        x += shift;
      }
      if (n.norm() > 0)
      {
        normal = !closed && n.dot(first) < 0 ? Eigen::Vector3d(-n) : n;
      }
    }
    GuideStrand g;
    g.root = c[0];
    g.growth = first;
    g.normal = normal;
    g.length = 0;
    for (std::size_t j = 1; j < c.size(); ++j)
    {
      g.length += (c[j] - c[j - 1]).norm();
    }
    g.elements = options.elements;
    g.hair = options.hair;
    g.seed = options.seed;
    g.restShape = options.restShape;
    g.curve = std::move(c);
    if (Status s = g.validate("curve " + std::to_string(k)); !s)
    {
      no.push_back({int(k), s.message()});
      continue;
    }
    out.push_back(std::move(g));
    from.push_back(int(k));
  }
  if (out.empty())
  {
    std::string list;
    for (std::size_t i = 0; i < no.size() && i < 3; ++i)
    {
      list += (i ? " " : "") + no[i].reason;
    }
    guides.clear();
    source.clear();
    refused = std::move(no);
    return Status::Error(curves.empty() ? std::string("there are no guide curves.")
                                        : "no guide curve can be used: " + list);
  }
  guides = std::move(out);
  source = std::move(from);
  refused = std::move(no);
  return Status::Ok();
}

} // namespace hair
