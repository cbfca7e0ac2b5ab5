#include "projective/ProjectiveModel.h"

#include "model/StrandPoints.h"
#include "projective/ProjectiveGroom.h"

#include <algorithm>
#include <cmath>

namespace hair
{

ProjectiveModel::ProjectiveModel(const ProjectiveOptions& options, const SagFreeOptions& sagFree)
    : Options(options), SagFree(sagFree)
{
}

double ProjectiveModel::stepFor(const RunSettings& run)
{
  return run.frameInterval / std::ceil(run.frameInterval / std::min(run.timeStep, 1e-3) - 1e-9);
}

ProjectiveParameters ProjectiveModel::material(const HairParameters& hair)
{
  ProjectiveParameters p;
  p.linearDensity = hair.linearDensity();
  p.bendingStiffness = 0.5 * (hair.stiffness()[1] + hair.stiffness()[2]);
  p.dragDiameter = 2 * hair.radius;
  return p;
}

Status ProjectiveModel::initialize(const std::vector<GuideStrand>& guides, const Scene& scene,
                                   const RunSettings& run)
{
  std::vector<ProjectiveStrand> strands(guides.size());
  Built = guides;
  Reports.assign(guides.size(), GroomReport());
  // The parts at t = 0, over which a grown strand that starts inside them is draped.
  std::vector<PosedPart> parts;
  scene.posedParts(0, parts);
  for (std::size_t k = 0; k < guides.size(); ++k)
  {
    const GuideStrand& g = guides[k];
    const int n = g.elements;
    std::vector<Eigen::Vector3d> points;
    if (g.curve.empty())
    {
      for (int i = 0; i <= n; ++i)
      {
        points.push_back(g.root + (g.length * i / n) * g.growth.normalized());
      }
    }
    else
    {
      // A groom: equal segments inscribed in its curve; their angles are both the shape at
      // t = 0 and (as grown) the styled rest shape.
      if (Status s = segmentsAlongCurve(g.curve, n, points, Reports[k].fitError); !s)
      {
        return Status::Error("strand " + std::to_string(run.strandId(k)) + ": " + s.message());
      }
      Built[k].length = n * (points[1] - points[0]).norm();
      Built[k].growth = (points[1] - points[0]).normalized();
    }
    if (Status s = strandFromPolyline(points, Built[k].rootFrame().col(1), strands[k]); !s)
    {
      return Status::Error("strand " + std::to_string(run.strandId(k)) + ": " + s.message());
    }
    strands[k].parameters = material(g.hair);
    if (g.curve.empty() && !parts.empty())
    {
      // Grown into the body (a straight guide through the shoulders): it starts draped over
      // it, a contact margin out; its rest shape stays the grown one.
      Reports[k].drape = drapeOutside(parts, Options.contactMargin, points);
      if (Reports[k].drape > 0)
      {
        strands[k].angles = anglesAlong(strands[k].rootFrame, points);
      }
    }
  }
  ProjectiveOptions o = Options;
  o.timeStep = stepFor(run);
  o.threads = run.threads;
  if (Status s = Strands.initialize(std::move(strands), scene, o); !s)
  {
    return s;
  }
  // Sag-free rest angles, strand by strand (each leaves its strand in its start shape).
  for (std::size_t k = 0; k < guides.size(); ++k)
  {
    if (guides[k].restShape != RestShape::SagFree)
    {
      continue;
    }
    ProjectiveSagFree r;
    if (Status s = projectiveSagFree(Strands, static_cast<int>(k), SagFree, r); !s)
    {
      return Status::Error("strand " + std::to_string(run.strandId(k)) + ": " + s.message());
    }
    const double fit = Reports[k].fitError;
    Reports[k] = r.report;
    Reports[k].fitError = fit;
  }
  return Status::Ok();
}

void ProjectiveModel::groomed(std::vector<GuideStrand>& guides,
                              std::vector<GroomReport>& reports) const
{
  guides = Built;
  reports = Reports;
}

void ProjectiveModel::restCoordinates(std::vector<double>& values) const
{
  values.clear();
  for (int s = 0; s < Strands.numberOfStrands(); ++s)
  {
    for (const Eigen::Vector2d& a : Strands.restAngles(s))
    {
      values.push_back(a.x());
      values.push_back(a.y());
    }
  }
}

Status ProjectiveModel::advanceTo(double target)
{
  const double h = Strands.options().timeStep;
  const int steps = std::max(1, static_cast<int>(std::lround((target - Strands.time()) / h)));
  for (int i = 0; i < steps; ++i)
  {
    if (Status s = Strands.step(); !s)
    {
      return s;
    }
  }
  return Status::Ok();
}

void ProjectiveModel::describe(StateHeader& header) const
{
  header.model = name();
  const int n = Strands.numberOfStrands() ? Strands.numberOfSegments(0) : 0;
  header.coordinatesPerStrand = 2 * n;
  header.offsets.clear();
  std::int64_t first = 0;
  header.offsets.push_back(first);
  for (int s = 0; s < Strands.numberOfStrands(); ++s)
  {
    first += Strands.numberOfSegments(s) + 1;
    header.offsets.push_back(first);
  }
  auto& at = header.attributes;
  at["friction_coefficient"] = Options.friction;
  at["friction_anisotropy"] = Options.anisotropy;
  at["static_friction_coefficient"] = Options.staticFriction;
}

void ProjectiveModel::writeFrame(StateFrame& f) const
{
  f.positions.clear();
  f.velocities.clear();
  f.q.clear();
  f.qdot.clear();
  f.rootFrames.clear();
  f.rootVelocities.clear();
  // The roots' rates: the head's velocity field at the model's time (the roots move with it).
  const RigidRates rates = Strands.scene().rootMotion.rates(Strands.time());
  for (int s = 0; s < Strands.numberOfStrands(); ++s)
  {
    const auto& nodes = Strands.nodes(s);
    const auto& velocities = Strands.nodeVelocities(s);
    f.positions.insert(f.positions.end(), nodes.begin(), nodes.end());
    f.velocities.insert(f.velocities.end(), velocities.begin(), velocities.end());
    RootState root;
    root.position = nodes.front();
    root.orientation = materialFrame(Strands.rootFrame(s));
    root.velocity = rates.velocityAt(root.position);
    root.angularVelocity = rates.angularVelocity;
    appendRoot(root, f.rootFrames, f.rootVelocities);
    for (std::size_t k = 0; k < Strands.angles(s).size(); ++k)
    {
      f.q.push_back(Strands.angles(s)[k].x());
      f.q.push_back(Strands.angles(s)[k].y());
      f.qdot.push_back(Strands.rates(s)[k].x());
      f.qdot.push_back(Strands.rates(s)[k].y());
    }
  }
}

EnergyBudget ProjectiveModel::energy() const
{
  const ProjectiveEnergy e = Strands.energy();
  EnergyBudget b;
  b.add(energy::Kinetic, EnergyKind::State, e.kinetic);
  b.add(energy::Elastic, EnergyKind::State, e.elastic);
  b.add(energy::Gravitational, EnergyKind::State, e.gravitational);
  b.add("damping_dissipated", EnergyKind::Dissipation, e.dissipated);
  b.add("contact_dissipated", EnergyKind::Dissipation, e.contactDissipated);
  if (Options.friction > 0 || Options.staticFriction > 0)
  {
    b.add("body_friction_dissipated", EnergyKind::Dissipation, e.frictionDissipated);
  }
  b.add("body_work", EnergyKind::Work, e.bodyWork);
  b.add("wind_work", EnergyKind::Work, e.windWork);
  b.add("contact_work", EnergyKind::Work, e.contactWork);
  b.add(energy::Residual, EnergyKind::Residual, e.residual);
  return b;
}

} // namespace hair

namespace hair
{

std::size_t ProjectiveModel::continuationCapacity(std::size_t k) const
{
  return Strands.continuationSize(int(k));
}

void ProjectiveModel::saveContinuation(StateContinuation& out) const
{
  out.strands.resize(std::size_t(Strands.numberOfStrands()));
  for (int s = 0; s < Strands.numberOfStrands(); ++s)
  {
    out.strands[s].clear();
    Strands.saveContinuation(s, out.strands[s]);
  }
  out.run = {Strands.time(), double(Strands.steps())};
}

Status ProjectiveModel::restoreContinuation(const StateContinuation& in)
{
  if (in.strands.size() != std::size_t(Strands.numberOfStrands()) || in.run.size() != 2 ||
      !std::isfinite(in.run[0]) || !(in.run[1] >= 0))
  {
    return Status::Error("the continuation is of " + std::to_string(in.strands.size()) +
                         " projective strands and " + std::to_string(in.run.size()) +
                         " model values; this model has " +
                         std::to_string(Strands.numberOfStrands()) + " strands and 2.");
  }
  for (int s = 0; s < Strands.numberOfStrands(); ++s)
  {
    if (Status st = Strands.restoreContinuation(s, in.strands[s]); !st)
    {
      return st;
    }
  }
  Strands.restoreClock(in.run[0], long(in.run[1]));
  return Status::Ok();
}

} // namespace hair
