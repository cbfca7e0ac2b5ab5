#include "ProjectiveScenes.h"

#include "collision/BodyPartList.h"
#include "geometry/MeshIO.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace hair
{

Status loadBundledBody(const std::string& dataDir, BundledBody& body)
{
  BundledBody b;
  if (Status st = readVtkPolyData(dataDir + "/body.vtk", b.mesh); !st)
  {
    return st;
  }
  if (Status st = b.mesh.validate("the bundled body"); !st)
  {
    return st;
  }
  std::vector<BodyPartSpec> specs;
  if (Status st = readBodyParts(dataDir + "/body_parts.txt", specs); !st)
  {
    return st;
  }
  const MeshQueries queries(b.mesh);
  for (const BodyPartSpec& spec : specs)
  {
    BodyPart part;
    part.name = spec.name;
    if (Status st = part.table.build(spec.spec, queries); !st)
    {
      return Status::Error("body part '" + spec.name + "': " + st.message());
    }
    if (spec.name == "head")
    {
      b.head = static_cast<int>(b.parts.size());
      b.headCentre = spec.spec.frame.origin;
    }
    if (spec.name == "trunk")
    {
      b.trunk = static_cast<int>(b.parts.size());
    }
    b.parts.push_back(std::move(part));
  }
  if (b.head < 0 || b.trunk < 0)
  {
    return Status::Error(dataDir + "/body_parts.txt: a 'head' and a 'trunk' part are needed");
  }
  // The head turns about the top of the neck: below the head centre, a little behind it.
  b.neckPivot = b.headCentre + Eigen::Vector3d(0, -0.10, -0.03);
  body = std::move(b);
  return Status::Ok();
}

namespace
{
/// Puts p outside every part (at rest) by `clearance`, turning the segment from `prev`.
Eigen::Vector3d keepOutside(const std::vector<BodyPart>& parts, const Eigen::Vector3d& prev,
                            Eigen::Vector3d p, double d, double clearance)
{
  for (int iter = 0; iter < 6; ++iter)
  {
    bool moved = false;
    for (const BodyPart& part : parts)
    {
      const TableQuery q = part.query(p);
      if (q.covered && q.depth > -clearance)
      {
        const Eigen::Vector3d target = p + (q.depth + clearance) * q.normal;
        p = prev + d * (target - prev).normalized();
        moved = true;
      }
    }
    if (!moved)
    {
      break;
    }
  }
  return p;
}
} // namespace

Status scalpStrands(const BundledBody& body, const ScalpOptions& options,
                    std::vector<ProjectiveStrand>& strands)
{
  if (options.strands <= 0 || options.segments <= 0 || !(options.length > 0))
  {
    return Status::Error("scalp strands: give > 0 strands, > 0 segments and a length > 0 m");
  }
  const Eigen::Vector3d c = body.headCentre;
  // Scalp triangles and their areas.
  std::vector<int> tris;
  std::vector<double> cumulative;
  double total = 0;
  for (std::size_t t = 0; t < body.mesh.triangles.size(); ++t)
  {
    const auto& tri = body.mesh.triangles[t];
    const Eigen::Vector3d a = body.mesh.points[tri[0]], b = body.mesh.points[tri[1]],
                          e = body.mesh.points[tri[2]];
    const Eigen::Vector3d g = (a + b + e) / 3.0;
    if (g.y() < options.minHeight || (g - c).norm() > 0.16)
    {
      continue;
    }
    const Eigen::Vector3d radial = (g - c).normalized();
    if (radial.z() > 0.35 && radial.y() < 0.55) // the face and the forehead
    {
      continue;
    }
    const Eigen::Vector3d n = (b - a).cross(e - a);
    if (n.norm() <= 0 || std::abs(n.normalized().dot(radial)) < 0.3) // not facing outward
    {
      continue;
    }
    total += 0.5 * n.norm();
    tris.push_back(static_cast<int>(t));
    cumulative.push_back(total);
  }
  if (tris.empty())
  {
    return Status::Error("scalp strands: no scalp triangles found on the bundled body");
  }
  std::mt19937_64 rng(options.seed);
  auto uniform = [&rng]() { return (rng() >> 11) * (1.0 / 9007199254740992.0); };
  const int k = options.segments;
  const double d = options.length / k;
  strands.clear();
  strands.reserve(options.strands);
  for (int s = 0; s < options.strands; ++s)
  {
    const double pick = uniform() * total;
    const std::size_t idx = std::min<std::size_t>(
        std::lower_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin(),
        tris.size() - 1);
    const auto& tri = body.mesh.triangles[tris[idx]];
    const Eigen::Vector3d a = body.mesh.points[tri[0]], b = body.mesh.points[tri[1]],
                          e = body.mesh.points[tri[2]];
    double u = uniform(), v = uniform();
    if (u + v > 1)
    {
      u = 1 - u;
      v = 1 - v;
    }
    const Eigen::Vector3d x = a + u * (b - a) + v * (e - a);
    Eigen::Vector3d n = (b - a).cross(e - a).normalized();
    if (n.dot(x - c) < 0)
    {
      n = -n;
    }
    // Comb: start along the normal, turn down (−y) and a little backwards (−z).
    std::vector<Eigen::Vector3d> pts(k + 1);
    pts[0] = x + 0.5e-3 * n;
    Eigen::Vector3d dir = n;
    const Eigen::Vector3d comb = Eigen::Vector3d(0, -1, -0.25).normalized();
    for (int i = 1; i <= k; ++i)
    {
      const double turn = options.bendPerMetre * d;
      dir = (dir + turn * (comb - comb.dot(dir) * dir)).normalized();
      Eigen::Vector3d p = pts[i - 1] + d * dir;
      p = keepOutside(body.parts, pts[i - 1], p, d, options.clearance);
      dir = (p - pts[i - 1]).normalized();
      pts[i] = p;
    }
    Eigen::Vector3d side = n.cross(Eigen::Vector3d::UnitY());
    if (side.norm() < 1e-3)
    {
      side = Eigen::Vector3d::UnitX();
    }
    ProjectiveStrand strand;
    if (Status st = strandFromPolyline(pts, side, strand); !st)
    {
      return st;
    }
    strands.push_back(std::move(strand));
  }
  return Status::Ok();
}

ProjectiveScene paperScene(const BundledBody& body, PaperScene which, double& duration)
{
  ProjectiveScene scene;
  scene.parts = body.parts;
  scene.motions.assign(body.parts.size(), BodyMotion::still());
  if (which == PaperScene::Wind)
  {
    scene.wind.direction = Eigen::Vector3d(0, 0, -1); // from the front (the face is +Z)
    scene.wind.speed = 2.0;
    scene.wind.gustAmplitude = 0.3;
    scene.wind.gustPeriod = 0.8;
    scene.wind.start = 0.3;
    scene.wind.rampTime = 0.3;
    duration = 2.5;
  }
  else
  {
    // Left, right, left: 1.5 periods of 0.8 s, ±0.6 rad (≈ 34°) about the neck's vertical.
    const BodyMotion shake =
        BodyMotion::shake(body.neckPivot, Eigen::Vector3d::UnitY(), 0.6, 0.8, 0.3, 1.5);
    scene.motions[body.head] = shake;
    scene.rootMotion = shake;
    scene.wind.direction = Eigen::Vector3d(0, 0, -1);
    scene.wind.speed = 0.5;
    scene.wind.gustAmplitude = 0.2;
    scene.wind.gustPeriod = 1.0;
    duration = 2.5;
  }
  return scene;
}

} // namespace hair
