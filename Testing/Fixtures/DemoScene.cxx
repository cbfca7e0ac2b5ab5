#include "DemoScene.h"

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
  grow.length = 0.30;
  grow.elements = elements;
  grow.combed = true;
  grow.combDirection = Eigen::Vector3d(0, -1, -0.3);
  grow.combWeight = 0.35;
  grow.hair = HairParameters::preset(HairType::Wavy);
  return growGuides(roots, grow, guides);
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

} // namespace hair
