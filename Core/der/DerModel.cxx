#include "der/DerModel.h"

#include "common/Parallel.h"
#include "model/StrandPoints.h"

#include <algorithm>
#include <cmath>

namespace hair
{

namespace
{
constexpr std::size_t AnchorValues = 6; ///< set, rest (3), flows, sliding

/// The first point of polyline `curve` past position (segment `i`, fraction `u`) at distance
/// `r` from `from` (a sphere–segment intersection); false when the curve ends first. On
/// success (i, u) is moved to it.
bool marchChord(const std::vector<Eigen::Vector3d>& curve, const Eigen::Vector3d& from, double r,
                std::size_t& i, double& u, Eigen::Vector3d& to)
{
  for (; i + 1 < curve.size(); ++i, u = 0)
  {
    const Eigen::Vector3d a = curve[i], d = curve[i + 1] - curve[i];
    // |a + s d − from|² = r², the larger root s in [u, 1].
    const Eigen::Vector3d f = a - from;
    const double A = d.squaredNorm(), B = 2 * f.dot(d), C = f.squaredNorm() - r * r;
    const double disc = B * B - 4 * A * C;
    if (disc < 0)
    {
      continue;
    }
    const double s = (-B + std::sqrt(disc)) / (2 * A);
    if (s >= u && s <= 1)
    {
      u = s;
      to = a + s * d;
      return true;
    }
  }
  return false;
}

/// Nodes x_1 … x_N inscribed in `curve` from its first point: x_1 at ℓ/2, the others ℓ apart.
/// How far along the curve the last node falls short of its end (in segments; < 0: the
/// curve ended first).
double inscribe(const std::vector<Eigen::Vector3d>& curve, int n, double edge,
                std::vector<Eigen::Vector3d>& nodes)
{
  nodes.assign(1, curve[0]);
  std::size_t i = 0;
  double u = 0;
  Eigen::Vector3d at = curve[0], next;
  for (int k = 1; k <= n; ++k)
  {
    if (!marchChord(curve, at, k == 1 ? 0.5 * edge : edge, i, u, next))
    {
      return -double(n - k + 1);
    }
    nodes.push_back(next);
    at = next;
  }
  return double(curve.size() - 1) - (double(i) + u);
}

double distanceToSegment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                         const Eigen::Vector3d& b)
{
  const Eigen::Vector3d d = b - a;
  const double s = std::clamp((p - a).dot(d) / std::max(d.squaredNorm(), 1e-300), 0.0, 1.0);
  return (a + s * d - p).norm();
}
} // namespace

DerModel::DerModel(const BodyContactParameters& contacts, const HairHairOptions& hairHair,
                   const DerSolverOptions& solver)
    : ContactLaw(contacts), HairHair(hairHair), Solver(solver)
{
}

int DerModel::edgesFor(const HairParameters& hair, double length)
{
  // Edges of L/(N − ½) (specFor): κ L/(N − ½) <= RobustTurn.
  return std::max(
      20, static_cast<int>(std::ceil(hair.largestNaturalBending() * length / RobustTurn + 0.5)));
}

double DerModel::stepFor(const RunSettings& run)
{
  return run.frameInterval / std::ceil(run.frameInterval / run.timeStep - 1e-9);
}

Status DerModel::specFor(const GuideStrand& g, const Scene& scene, DerSpec& spec, double& fitError)
{
  const int n = g.elements;
  if (n < 2)
  {
    return Status::Error("has " + std::to_string(n) +
                         " element: a discrete elastic rod needs at least 2 edges (Elements).");
  }
  fitError = 0;
  double length = g.length;
  Eigen::Vector3d growth = g.growth.normalized();
  std::vector<Eigen::Vector3d> nodes;
  if (!g.curve.empty())
  {
    // The edge length that puts the last node on the curve's end: bisection between an edge
    // too short (the nodes end before the curve does) and one too long.
    double curveLength = 0;
    for (std::size_t i = 1; i < g.curve.size(); ++i)
    {
      curveLength += (g.curve[i] - g.curve[i - 1]).norm();
    }
    double lo = 0, hi = 2 * curveLength / (n - 0.5);
    for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; ++it)
    {
      const double mid = 0.5 * (lo + hi);
      (inscribe(g.curve, n, mid, nodes) >= 0 ? lo : hi) = mid;
    }
    if (inscribe(g.curve, n, lo, nodes) < 0 || lo <= 0)
    {
      return Status::Error("its guide curve cannot be inscribed with " + std::to_string(n) +
                           " equal edges: give a longer curve or fewer elements.");
    }
    length = (n - 0.5) * lo;
    growth = (nodes[1] - nodes[0]).normalized();
    // The curve's points from the polyline root, x_1, …, x_N.
    for (const Eigen::Vector3d& p : g.curve)
    {
      double d = std::numeric_limits<double>::infinity();
      for (std::size_t k = 0; k + 1 < nodes.size(); ++k)
      {
        d = std::min(d, distanceToSegment(p, nodes[k], nodes[k + 1]));
      }
      fitError = std::max(fitError, d);
    }
  }
  const double edge = length / (n - 0.5);
  const Eigen::Matrix3d frame = orthonormalFrame(growth, g.normal);
  spec = DerSpec::uniform(edge * n, n, g.hair);
  spec.seed = g.seed;
  // The clamp's edge has the root at its middle: x_0 half an edge behind it.
  const Eigen::Vector3d x0 = g.root - 0.5 * edge * frame.col(0);
  spec.root = scene.rootMotion.carriedRoot(x0, frame);
  spec.gravity = scene.gravity;
  if (scene.air.isSteadyAndUniform())
  {
    spec.wind = scene.air.velocity(Eigen::Vector3d::Zero(), 0);
  }
  else
  {
    const AirField air = scene.air;
    spec.windField = [air](const Eigen::Vector3d& x, double t) { return air.velocity(x, t); };
  }
  if (!nodes.empty())
  {
    // x_0 behind the root, then the inscribed nodes x_1 … x_N.
    nodes[0] = x0;
    spec.initialNodes = nodes;
  }
  return Status::Ok();
}

Status DerModel::initialize(const std::vector<GuideStrand>& guides, const Scene& scene,
                            const RunSettings& run)
{
  Run = run;
  World = scene;
  Step = stepFor(run);
  Time = 0;
  Steps = 0;
  BodyContactParameters law = ContactLaw;
  law.lookAhead = Step;
  if (Status s = Body.setParameters(law); !s)
  {
    return Status::Error("hair–body contacts: " + s.message());
  }
  if (Status s = HairHair.validate(); !s)
  {
    return s;
  }
  if (HairHair.enabled && HairHair.solver != HairHairSolver::Grid)
  {
    // The near field and the coupled pairs step the strands together through the
    // Super-Helix's compliance (contact/HairHairContacts, contact/NearField).
    return Status::Error(std::string("hair–hair interaction: the ") + toString(HairHair.solver) +
                         " solver is not available for the discrete-elastic-rods model: it "
                         "has the grid's volume and friction. Choose the grid (Hair Hair "
                         "Contacts = Grid) or none, or run the Super-Helix model.");
  }
  if (HairHair.usesGrid())
  {
    if (Status s = Grid.setParameters(HairHair.grid); !s)
    {
      return Status::Error("hair–hair interaction: " + s.message());
    }
    // A guide stands for the head's fibres shared among the run's guides (every rank's).
    const double count = run.ranks.sum(static_cast<double>(guides.size()));
    ClumpArea.resize(guides.size());
    for (std::size_t k = 0; k < guides.size(); ++k)
    {
      ClumpArea[k] = guideClumpArea(guides[k].hair.radius, count);
    }
  }
  Rods.assign(guides.size(), DerRod());
  Anchors.assign(guides.size(), {});
  Built = guides;
  Reports.assign(guides.size(), GroomReport());
  const Status built = parallelEach(static_cast<std::int64_t>(guides.size()), run.threads,
                                    [&](std::int64_t k) { return buildRod(k, guides[k]); });
  if (!built)
  {
    return built;
  }
  for (std::size_t k = 0; k < Rods.size(); ++k)
  {
    // The model lives on the heap and owns the rods: `this` outlives the hook.
    Rods[k].setContactForces([this, k](int, double t, const std::vector<StrandSample>& samples,
                                       std::vector<ContactResponse>& response)
                             { respond(k, t, samples, response); });
  }
  return Status::Ok();
}

Status DerModel::buildRod(std::int64_t k, const GuideStrand& g)
{
  const std::string name = "strand " + std::to_string(Run.strandId(k));
  if (g.restShape == RestShape::SagFree)
  {
    return Status::Error(name + ": a sag-free rest shape is not available for the "
                                "discrete-elastic-rods model yet: grow it as grown, or run the "
                                "Super-Helix or projective model.");
  }
  DerSpec spec;
  if (Status s = specFor(g, World, spec, Reports[k].fitError); !s)
  {
    return Status::Error(name + " " + s.message());
  }
  spec.name = name;
  spec.id = Run.strandId(k);
  spec.solver = Solver;
  Status s = Rods[k].initialize(spec, 0);
  if (s && g.curve.empty())
  {
    // A grown strand starts at rest in its natural shape (StrandModel): its rest strains as
    // drawn, the shape they give from the clamp.
    const int n = Rods[k].edgeCount();
    spec.restStrains.clear();
    for (int i = 1; i < n; ++i)
    {
      const double lbar = 0.5 * (spec.edgeLengths[i - 1] + spec.edgeLengths[i]);
      for (int c = 0; c < 3; ++c)
      {
        spec.restStrains.push_back(Rods[k].restStrains(i)[c] / lbar);
      }
    }
    Rods[k].naturalShape(spec.initialNodes, spec.initialTwists);
    s = Rods[k].initialize(spec, 0);
  }
  if (s && !g.curve.empty())
  {
    Built[k].length = spec.edgeLengths[0] * (g.elements - 0.5);
    Built[k].growth = spec.root(0).orientation.col(0);
  }
  return s;
}

void DerModel::respond(std::size_t k, double t, const std::vector<StrandSample>& samples,
                       std::vector<ContactResponse>& response) const
{
  const double rhoS = Rods[k].spec().hair.linearDensity();
  if (Body.parameters().enabled && !World.parts.empty())
  {
    thread_local std::vector<PosedPart> parts; // no allocation after the first call
    World.posedParts(t, parts);
    Body.respond(samples, rhoS, parts.data(), static_cast<int>(parts.size()), response, nullptr,
                 &Anchors[k]);
  }
  if (HairHair.usesGrid())
  {
    for (std::size_t j = 0; j < samples.size(); ++j)
    {
      Grid.respond(samples[j].position, rhoS, ClumpArea[k], response[j]);
    }
  }
}

void DerModel::buildGrid(double h)
{
  // Each rod's polyline from its root through nodes 1 … N (node 0 lies behind the root,
  // inside the clamp), on the run's threads.
  GridPoints.resize(Rods.size());
  GridVelocities.resize(Rods.size());
  parallelBlocks(static_cast<std::int64_t>(Rods.size()), 16, std::max(1, Run.threads),
                 [&](std::int64_t b0, std::int64_t b1)
                 {
                   for (std::int64_t k = b0; k < b1; ++k)
                   {
                     const DerRod& rod = Rods[k];
                     const int n = rod.edgeCount();
                     const RootState root = rod.rootState(rod.time());
                     std::vector<Eigen::Vector3d>& x = GridPoints[k];
                     std::vector<Eigen::Vector3d>& v = GridVelocities[k];
                     x.resize(n + 1);
                     v.resize(n + 1);
                     x[0] = root.position;
                     v[0] = root.velocity;
                     for (int j = 1; j <= n; ++j)
                     {
                       x[j] = rod.position(j);
                       v[j] = rod.velocity(j);
                     }
                   }
                 });
  std::vector<HairGrid::Strand> strands(Rods.size());
  for (std::size_t k = 0; k < Rods.size(); ++k)
  {
    strands[k] = {GridPoints[k].data(), GridVelocities[k].data(),
                  static_cast<int>(GridPoints[k].size()), ClumpArea[k], Built[k].length};
  }
  Grid.build(strands, h, Run.ranks, Run.threads);
}

Status DerModel::stepRod(DerRod& rod, double h, int depth, double& iterations)
{
  // A step whose Newton iteration does not converge (a strand thrown into a contact, a
  // sharp turn of the root) is taken again as two halves, down to 1/64 of the step; the rod
  // is left as it was by a failed step.
  Status s = rod.step(h);
  iterations += rod.lastIterations();
  if (s || depth >= MaxHalvings)
  {
    return s;
  }
  Status first = stepRod(rod, 0.5 * h, depth + 1, iterations);
  return first ? stepRod(rod, 0.5 * h, depth + 1, iterations) : first;
}

Status DerModel::advanceTo(double target)
{
  const int steps = std::max(0, static_cast<int>(std::lround((target - Time) / Step)));
  FrameIterations = FrameSteps = 0; // the statistics are of the steps since the last frame
  std::vector<double> iterations(Rods.size(), 0.0);
  for (int i = 0; i < steps; ++i)
  {
    if (HairHair.usesGrid())
    {
      // Once a step, from every rank's rods (collective); a step halved goes through the
      // same grid.
      buildGrid(Step);
    }
    const Status mine =
        parallelEach(static_cast<std::int64_t>(Rods.size()), Run.threads,
                     [&](std::int64_t k) { return stepRod(Rods[k], Step, 0, iterations[k]); });
    // The grid is built by every rank at every step (collective): when a rod failed on any
    // rank, all stop at this step, the others with Ok so that the run reports the failure's
    // own rank and message (Simulation::advanceTo agrees on it).
    if (HairHair.usesGrid() ? Run.ranks.any(!mine) : !mine)
    {
      return mine;
    }
    ++Steps;
    // Every rod's own clock; the model's is the steps taken (no drift between strands).
    Time = double(Steps) * Step;
  }
  for (double n : iterations)
  {
    FrameIterations += n;
  }
  FrameSteps += double(steps) * double(Rods.size());
  return Status::Ok();
}

std::map<std::string, double> DerModel::stepStatistics() const
{
  // Newton iterations per step of a strand since the previous frame; read once a frame.
  const double mean = FrameSteps > 0 ? FrameIterations / FrameSteps : 0.0;
  const double steps = Rods.empty() ? 0.0 : FrameSteps / double(Rods.size());
  return {{"newton_iterations", mean}, {"steps", steps}};
}

std::vector<StepStatisticRule> DerModel::stepStatisticRules() const
{
  using R = StepStatisticRule::Reduction;
  return {{"newton_iterations", R::StrandMean, "steps"}, {"steps", R::StrandMean, ""}};
}

double DerModel::bytesPerElement() const
{
  // Measured with `hair_study scene model=discrete-elastic-rods n=40 duration=0.0667` at
  // strands=200 and 400 (maximum resident memory 33.0 and 46.7 MB): 1.7 kB per edge, frames
  // included (the Super-Helix measured the same way: 3.5 kB per element).
  return 1750;
}

void DerModel::describe(StateHeader& header) const
{
  const int n = Rods.empty() ? 0 : Rods[0].edgeCount();
  header.model = name();
  header.coordinatesPerStrand = 4 * n + 3;
  header.offsets.assign(1, 0);
  for (const DerRod& r : Rods)
  {
    header.offsets.push_back(header.offsets.back() + r.edgeCount() + 1);
  }
  auto& at = header.attributes;
  const BodyContactParameters& c = Body.parameters();
  at["contact_enabled"] = c.enabled ? 1.0 : 0.0;
  at["contact_stiffness"] = c.stiffness;
  at["contact_damping"] = c.dampingRatio;
  at["contact_thickness"] = c.thickness;
  for (const auto& [key, value] : HairHair.gridAttributes(Grid.cellSize()))
  {
    at[key] = value;
  }
  at["friction_coefficient"] = c.friction;
  at["friction_anisotropy"] = c.anisotropy;
  at["static_friction_coefficient"] = c.staticFriction;
  at["slip_velocity"] = c.slipVelocity;
  at["newton_step_tolerance"] = Solver.stepTolerance;
  at["newton_gradient_tolerance"] = Solver.gradientTolerance;
  at["newton_max_iterations"] = Solver.maxIterations;
  at["der_time_step"] = Step;
}

void DerModel::writeFrame(StateFrame& f) const
{
  f.positions.clear();
  f.velocities.clear();
  f.q.clear();
  f.qdot.clear();
  f.rootFrames.clear();
  f.rootVelocities.clear();
  for (const DerRod& r : Rods)
  {
    const int n = r.edgeCount();
    // The root, at the clamped edge's middle, then nodes 1 … N.
    f.positions.push_back(0.5 * (r.position(0) + r.position(1)));
    f.velocities.push_back(0.5 * (r.velocity(0) + r.velocity(1)));
    for (int k = 1; k <= n; ++k)
    {
      f.positions.push_back(r.position(k));
      f.velocities.push_back(r.velocity(k));
    }
    RootState root = r.rootState(Time);
    const double half = 0.5 * r.spec().edgeLengths[0];
    root.position += half * root.orientation.col(0);
    root.velocity += root.angularVelocity.cross(half * root.orientation.col(0));
    appendRoot(root, f.rootFrames, f.rootVelocities);
    // φ_j: edge j's material director from the frame transported from the root's, summed
    // node by node (each node's share is its twist, well within (−π, π]).
    double phi = 0;
    Eigen::Vector3d carried = r.materialDirector1(0);
    for (int j = 0; j < n; ++j)
    {
      if (j > 0)
      {
        const Eigen::Vector3d t = r.tangent(j);
        carried = parallelTransport(carried, r.tangent(j - 1), t);
        carried = (carried - carried.dot(t) * t).normalized();
        const Eigen::Vector3d m1 = r.materialDirector1(j);
        phi += std::atan2(carried.cross(m1).dot(t), carried.dot(m1));
        carried = m1;
      }
      const Eigen::Vector3d x = r.position(j), v = r.velocity(j);
      f.q.insert(f.q.end(), {x.x(), x.y(), x.z(), phi});
      f.qdot.insert(f.qdot.end(), {v.x(), v.y(), v.z(), r.twistRate(j)});
    }
    const Eigen::Vector3d x = r.position(n), v = r.velocity(n);
    f.q.insert(f.q.end(), {x.x(), x.y(), x.z()});
    f.qdot.insert(f.qdot.end(), {v.x(), v.y(), v.z()});
  }
}

EnergyBudget DerModel::energy() const
{
  DerEnergyReport sum;
  for (const DerRod& r : Rods)
  {
    const DerEnergyReport& e = r.energy();
    sum.kinetic += e.kinetic;
    sum.elastic += e.elastic;
    sum.gravitational += e.gravitational;
    const DerEnergyTerms& t = e.total;
    sum.total.frictionDissipated += t.frictionDissipated;
    sum.total.airDissipated += t.airDissipated;
    sum.total.rootWork += t.rootWork;
    sum.total.windWork += t.windWork;
    sum.total.contactWork += t.contactWork;
    sum.total.fieldWork += t.fieldWork;
    sum.total.fieldDissipated += t.fieldDissipated;
    sum.total.residual += t.residual;
  }
  EnergyBudget b;
  b.add(energy::Kinetic, EnergyKind::State, sum.kinetic);
  b.add(energy::Elastic, EnergyKind::State, sum.elastic);
  b.add(energy::Gravitational, EnergyKind::State, sum.gravitational);
  b.add("friction_dissipated", EnergyKind::Dissipation, sum.total.frictionDissipated);
  b.add("air_dissipated", EnergyKind::Dissipation, sum.total.airDissipated);
  b.add("root_work", EnergyKind::Work, sum.total.rootWork);
  b.add("wind_work", EnergyKind::Work, sum.total.windWork);
  if (HairHair.usesGrid())
  {
    // The rods' contact work holds the grid's drag and push: reported apart, as the work of
    // its forces plus what its drag dissipated, and that dissipation (as the Super-Helix's).
    addGridContactWork(b, sum.total.contactWork, sum.total.fieldWork, sum.total.fieldDissipated);
  }
  else
  {
    b.add("contact_work", EnergyKind::Work, sum.total.contactWork);
  }
  b.add(energy::Residual, EnergyKind::Residual, sum.total.residual);
  return b;
}

void DerModel::groomed(std::vector<GuideStrand>& guides, std::vector<GroomReport>& reports) const
{
  guides = Built;
  reports = Reports;
}

std::size_t DerModel::continuationCapacity(std::size_t k) const
{
  std::vector<double> state;
  Rods[k].saveState(state);
  // Its anchors: one per node and body part (BodyContacts::respond), AnchorValues each.
  return state.size() + 1 +
         AnchorValues * std::size_t(Rods[k].edgeCount() + 1) * World.parts.size();
}

void DerModel::saveContinuation(StateContinuation& out) const
{
  out.strands.resize(Rods.size());
  for (std::size_t k = 0; k < Rods.size(); ++k)
  {
    std::vector<double>& v = out.strands[k];
    v.clear();
    Rods[k].saveState(v);
    // The static-friction anchors: their count, then each one's numbers.
    v.push_back(double(Anchors[k].size()));
    for (const BodyAnchor& a : Anchors[k])
    {
      v.insert(v.end(), {a.set ? 1.0 : 0.0, a.rest.x(), a.rest.y(), a.rest.z(), double(a.flows),
                         a.sliding ? 1.0 : 0.0});
    }
  }
  out.run = {Time, double(Steps)};
}

Status DerModel::restoreContinuation(const StateContinuation& in)
{
  if (in.strands.size() != Rods.size() || in.run.size() != 2 || !std::isfinite(in.run[0]) ||
      !(in.run[1] >= 0))
  {
    return Status::Error("the continuation is of " + std::to_string(in.strands.size()) +
                         " discrete elastic rods and " + std::to_string(in.run.size()) +
                         " model values; this model has " + std::to_string(Rods.size()) +
                         " strands and 2.");
  }
  for (std::size_t k = 0; k < Rods.size(); ++k)
  {
    std::vector<double> state;
    Rods[k].saveState(state); // its size: the rod's own numbers come first
    const std::vector<double>& v = in.strands[k];
    if (v.size() < state.size() + 1)
    {
      return Status::Error("the continuation of strand " + std::to_string(Run.strandId(k)) +
                           " is too short for its rod.");
    }
    if (Status s = Rods[k].restoreState({v.begin(), v.begin() + state.size()}); !s)
    {
      return s;
    }
    const double anchors = v[state.size()];
    if (!(anchors >= 0 && anchors <= 1e8) ||
        v.size() != state.size() + 1 + AnchorValues * std::size_t(anchors))
    {
      return Status::Error("the continuation of strand " + std::to_string(Run.strandId(k)) +
                           ": its static-friction anchors do not add up.");
    }
    Anchors[k].assign(std::size_t(anchors), BodyAnchor());
    for (std::size_t a = 0; a < Anchors[k].size(); ++a)
    {
      const double* p = v.data() + state.size() + 1 + AnchorValues * a;
      BodyAnchor& anchor = Anchors[k][a];
      anchor.set = p[0] != 0;
      anchor.rest = Eigen::Vector3d(p[1], p[2], p[3]);
      anchor.flows = int(p[4]);
      anchor.sliding = p[5] != 0;
    }
  }
  Time = in.run[0];
  Steps = long(in.run[1]);
  return Status::Ok();
}

} // namespace hair
