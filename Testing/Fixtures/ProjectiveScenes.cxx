#include "ProjectiveScenes.h"

#include "collision/BodyPartList.h"
#include "geometry/MeshIO.h"
#include "strands/BundledBody.h"
#include "strands/RootSampling.h"

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
    ScenePart part;
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
  b.neckPivot = bundled::neckPivot();
  body = std::move(b);
  return Status::Ok();
}

namespace
{
/// Puts p outside every part (at rest) by `clearance`, turning the segment from `prev`.
Eigen::Vector3d keepOutside(const std::vector<ScenePart>& parts, const Eigen::Vector3d& prev,
                            Eigen::Vector3d p, double d, double clearance)
{
  for (int iter = 0; iter < 6; ++iter)
  {
    bool moved = false;
    for (const ScenePart& part : parts)
    {
      const TableQuery q = PosedPart::still(part.table).query(p);
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
  RootSamplingOptions ro;
  ro.count = options.strands;
  ro.seed = static_cast<std::uint32_t>(options.seed);
  std::vector<Root> roots;
  if (Status st = sampleRoots(body.mesh, bundled::scalp(body.mesh), ro, roots); !st)
  {
    return Status::Error("scalp strands: " + st.message());
  }
  const int k = options.segments;
  const double d = options.length / k;
  strands.clear();
  strands.reserve(options.strands);
  for (const Root& root : roots)
  {
    const Eigen::Vector3d x = root.position;
    Eigen::Vector3d n = root.normal;
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

Scene paperScene(const BundledBody& body, PaperScene which, double& duration)
{
  Scene scene;
  scene.parts = body.parts;
  if (which == PaperScene::Wind)
  {
    scene.air.direction = Eigen::Vector3d(0, 0, -1); // from the front (the face is +Z)
    scene.air.speed = 2.0;
    scene.air.gustAmplitude = 0.3;
    scene.air.gustPeriod = 0.8;
    scene.air.start = 0.3;
    scene.air.rampTime = 0.3;
    duration = 2.5;
  }
  else
  {
    // Left, right, left: 1.5 periods of 0.8 s, ±0.6 rad (≈ 34°) about the neck's vertical,
    // fading in and out over a quarter period.
    const RigidMotion shake =
        RigidMotion::shake(body.neckPivot, Eigen::Vector3d::UnitY(), 0.6, 1 / 0.8)
            .during(0.3, 1.5)
            .fading(0.25 * 0.8);
    scene.parts[body.head].motion = shake;
    scene.rootMotion = shake;
    scene.air.direction = Eigen::Vector3d(0, 0, -1);
    scene.air.speed = 0.5;
    scene.air.gustAmplitude = 0.2;
    scene.air.gustPeriod = 1.0;
    scene.air.rampTime = 0.25;
    duration = 2.5;
  }
  return scene;
}

} // namespace hair
