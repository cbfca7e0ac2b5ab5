#include "DemoScene.h"

#include "simulation/GuideDrawing.h"
#include "strands/BundledBody.h"
#include "strands/GuideGrowth.h"
#include "strands/RootSampling.h"

namespace hair
{

Status demoGuides(const BundledBody& body, int count, int elements,
                  std::vector<GuideStrand>& guides)
{
  std::vector<Root> roots;
  RootSamplingOptions ro;
  ro.count = count;
  ro.seed = 1;
  if (Status s = sampleRoots(body.mesh, bundled::scalp(body.mesh), ro, roots); !s)
  {
    return s;
  }
  if (body.mesh.signedVolume() < 0) // normals out of the solid, as Hair Strands makes them
  {
    for (Root& r : roots)
    {
      r.normal = -r.normal;
    }
  }
  GrowthOptions grow;
  grow.length = DemoGuideLength;
  grow.elements = elements;
  grow.combed = true;
  grow.combDirection = Eigen::Vector3d(0, -1, -0.3);
  grow.combWeight = 0.35;
  grow.hair = HairParameters::preset(DemoHairType);
  return growGuides(roots, grow, guides);
}

Status demoGuides(const BundledBody& body, int count, int elements,
                  const std::vector<HairType>& presets, std::vector<GuideStrand>& guides)
{
  if (presets.empty())
  {
    return Status::Error("demoGuides: no hair preset given.");
  }
  const int n = static_cast<int>(presets.size());
  if (Status s = demoGuides(body, count * n, elements, guides); !s)
  {
    return s;
  }
  // The growth is the preset's only through the parameters the guide carries: the models
  // give it its natural shape from them.
  for (std::size_t k = 0; k < guides.size(); ++k)
  {
    guides[k].hair = HairParameters::preset(presets[k % n]);
  }
  return Status::Ok();
}

Scene demoScene(const BundledBody& body)
{
  Scene scene;
  scene.parts = {body.parts[body.head], body.parts[body.trunk]};
  scene.rootMotion = RigidMotion::shake(bundled::neckPivot(), Eigen::Vector3d::UnitY(), 0.5, 1.0);
  scene.parts[0].motion = scene.rootMotion;
  scene.air = AirField::uniform(Eigen::Vector3d(0, 0, -0.5));
  return scene;
}

Status drawnCurves(const Simulation& sim, int frame, int pointsPerElement,
                   const std::vector<std::string>& scalars, GuideCurves& curves)
{
  GuideDrawing drawn;
  if (Status s = drawGuides(sim.header(), sim.frame(frame), pointsPerElement, 2, drawn); !s)
  {
    return s;
  }
  curves = GuideCurves();
  curves.points = drawn.frame.positions;
  for (std::int64_t o : drawn.header.offsets)
  {
    curves.offsets.push_back(std::size_t(o));
  }
  curves.tangents = drawn.tangents;
  curves.directors = drawn.directors;
  for (const std::string& name : scalars)
  {
    const auto found = drawn.frame.pointData.find(name);
    if (found == drawn.frame.pointData.end())
    {
      return Status::Error("the drawn guides have no point data " + name + ".");
    }
    curves.scalars[name] = found->second;
  }
  return Status::Ok();
}

} // namespace hair
