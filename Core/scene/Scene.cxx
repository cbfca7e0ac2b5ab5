#include "scene/Scene.h"

namespace hair
{

Status Scene::validate() const
{
  for (std::size_t k = 0; k < parts.size(); ++k)
  {
    const ScenePart& p = parts[k];
    const std::string name = "body part '" + p.name + "'";
    if (p.table.empty() || p.table.numberOfHits() == 0)
    {
      return Status::Error(name + " has an empty collision table: build it from the part's "
                                  "mesh first.");
    }
    if (Status s = p.motion.validate("the motion of " + name); !s)
    {
      return s;
    }
  }
  if (Status s = rootMotion.validate("the root motion"); !s)
  {
    return s;
  }
  if (!gravity.allFinite())
  {
    return Status::Error("gravity must be a finite vector.");
  }
  return air.validate();
}

void Scene::posedParts(double t, std::vector<PosedPart>& out) const
{
  out.resize(parts.size());
  for (std::size_t k = 0; k < parts.size(); ++k)
  {
    const ScenePart& p = parts[k];
    PosedPart& posed = out[k];
    posed.table = &p.table;
    if (p.motion.moves())
    {
      const RigidRates r = p.motion.rates(t);
      posed.pose = p.motion.pose(t);
      posed.reference = r.reference;
      posed.velocity = r.velocity;
      posed.angularVelocity = r.angularVelocity;
    }
    else
    {
      posed.pose = Eigen::Isometry3d::Identity();
      posed.reference = posed.velocity = posed.angularVelocity = Eigen::Vector3d::Zero();
    }
  }
}

} // namespace hair
