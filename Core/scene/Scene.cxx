#include "scene/Scene.h"

#include <cstdint>

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

namespace
{
/// FNV-1a, 64 bits, over bytes.
struct Hash
{
  std::uint64_t value = 1469598103934665603ull;
  void bytes(const void* data, std::size_t n)
  {
    const unsigned char* b = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i)
    {
      value = (value ^ b[i]) * 1099511628211ull;
    }
  }
  void number(double x)
  {
    x = x == 0 ? 0.0 : x; // −0 as 0
    bytes(&x, sizeof x);
  }
  template <class M>
  void matrix(const M& m)
  {
    for (Eigen::Index i = 0; i < m.size(); ++i)
    {
      number(m.data()[i]);
    }
  }
};
} // namespace

double Scene::fingerprint() const
{
  const double times[] = {0, 0.013, 0.37, 1.1, 2.9, 7.3, 19.1, 53, 101};
  const Eigen::Vector3d points[] = {Eigen::Vector3d::Zero(), Eigen::Vector3d(0.1, 1.6, 0.05),
                                    Eigen::Vector3d(-0.2, 1.2, 0.3)};
  Hash h;
  for (const ScenePart& p : parts)
  {
    h.bytes(p.name.data(), p.name.size());
    const TableSpec& s = p.table.spec();
    h.number(double(s.projection));
    h.matrix(s.frame.origin);
    h.matrix(s.frame.axis);
    h.matrix(s.frame.reference);
    for (double x :
         {double(s.azimuthSamples), double(s.secondSamples), s.heightMin, s.heightMax, s.maxRadius})
    {
      h.number(x);
    }
    h.bytes(p.table.hit().data(), p.table.hit().size());
    for (double x : p.table.outerRadius())
    {
      h.number(x);
    }
    for (double x : p.table.innerRadius())
    {
      h.number(x);
    }
    for (double t : times)
    {
      h.matrix(p.motion.pose(t).matrix());
    }
  }
  for (double t : times)
  {
    h.matrix(rootMotion.pose(t).matrix());
    for (const Eigen::Vector3d& x : points)
    {
      h.matrix(air.velocity(x, t));
    }
  }
  h.matrix(gravity);
  return double(h.value >> 12);
}

} // namespace hair
