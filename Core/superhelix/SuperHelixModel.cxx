#include "superhelix/SuperHelixModel.h"

#include "common/Parallel.h"
#include "superhelix/Centerline.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace hair
{

Status SuperHelixOptions::validate() const
{
  // The strands check the same range (StrandSpec::validate); this message names the
  // model's option instead of a strand's field.
  if (!(quadratureTolerance >= QuadratureChooser::MinTolerance &&
        quadratureTolerance <= QuadratureChooser::MaxTolerance))
  {
    std::ostringstream s;
    s << "the quadrature tolerance " << quadratureTolerance << " is outside ["
      << QuadratureChooser::MinTolerance << ", " << QuadratureChooser::MaxTolerance
      << "]; the default " << QuadratureChooser::defaultTolerance()
      << " keeps the quadrature error far below the time step's, "
      << QuadratureChooser::MaxTolerance << " is the fastest.";
    return Status::Error(s.str());
  }
  if (integrator != Integrator::SemiImplicit && integrator != Integrator::Midpoint)
  {
    return Status::Error("the integrator " + std::to_string(static_cast<int>(integrator)) +
                         " is not a time step: give 0 (semi-implicit, the paper's) or 1 "
                         "(second order, midpoint).");
  }
  if (!(std::isfinite(tolerance) && tolerance >= 0))
  {
    std::ostringstream s;
    s << "the tolerance " << tolerance
      << " m/s is not a distance per second >= 0; give 0 for fixed steps or the error the "
         "steps may add per second of simulated time, e.g. 5e-3.";
    return Status::Error(s.str());
  }
  if (pointsPerElement < 1)
  {
    return Status::Error("at least one display point per element is needed.");
  }
  if (Status s = contacts.validate(); !s)
  {
    return Status::Error("hair–body contacts: " + s.message());
  }
  if (hairHairEnabled)
  {
    if (Status s = hairHair.validate(); !s)
    {
      return Status::Error("hair–hair contacts: " + s.message());
    }
    if (hairHairMaxUpdates < 1 || hairHairMaxUpdates > 64)
    {
      return Status::Error(
          "hair–hair contacts: hairHairMaxUpdates = " + std::to_string(hairHairMaxUpdates) +
          " is out of range; give 1 to 64 searches per step.");
    }
  }
  return Status::Ok();
}

SuperHelixModel::SuperHelixModel(const SuperHelixOptions& options) : Options(options) {}

Status SuperHelixModel::initialize(const std::vector<GuideStrand>& guides, const Scene& scene,
                                   const RunSettings& run)
{
  if (Status s = Options.validate(); !s)
  {
    return s;
  }
  Run = run;
  Time = 0;
  World = scene;
  Options.contacts.lookAhead = run.timeStep;
  if (Status s = Body.setParameters(Options.contacts); !s)
  {
    return Status::Error("hair–body contacts: " + s.message());
  }
  if (Options.hairHairEnabled && run.ranks.parallel())
  {
    // Each rank would find contacts among its own strands only: a run that silently differs
    // from the same run on one rank. The ghost strands of the neighbouring ranks
    // (simulation/GhostStrands.h) are there, but the contacts do not use them yet
    // (docs/mpi.md, "Hair–hair contacts across ranks").
    return Status::Error(
        "hair–hair contacts: not available under MPI yet (" + std::to_string(run.ranks.size()) +
        " ranks): each rank would only see contacts among its own strands. Run on one rank "
        "(without mpirun, or mpirun -np 1), or turn hair–hair contacts off.");
  }
  if (Options.hairHairEnabled)
  {
    HairHairParameters hh = Options.hairHair;
    hh.threads = std::max(1, run.threads);
    if (Status s = HairHair.setParameters(hh); !s)
    {
      return Status::Error("hair–hair contacts: " + s.message());
    }
  }
  // The wind: the fast uniform path when the air is steady and uniform, the field otherwise.
  const bool uniformAir = World.air.isSteadyAndUniform();
  const Eigen::Vector3d uniformWind = World.air.velocity(Eigen::Vector3d::Zero(), 0);
  Helices.assign(guides.size(), SuperHelix());
  for (std::size_t k = 0; k < guides.size(); ++k)
  {
    const GuideStrand& g = guides[k];
    // The run's number of the strand (under MPI this rank has a share of the guides).
    const int id = run.strandId(k);
    StrandSpec spec = StrandSpec::uniform(g.length, g.elements, g.hair);
    spec.name = "strand " + std::to_string(id);
    spec.id = id;
    spec.seed = g.seed + static_cast<std::uint32_t>(id);
    spec.gravity = World.gravity;
    if (uniformAir)
    {
      spec.wind = uniformWind;
    }
    else
    {
      spec.windField = World.air.field();
    }
    spec.quadratureTolerance = Options.quadratureTolerance;
    spec.integrator = Options.integrator;
    spec.root = World.rootMotion.carriedRoot(g.root, g.rootFrame());
    if (Status s = Helices[k].initialize(spec, 0.0); !s)
    {
      return s;
    }
    // The model lives on the heap and owns the strands: `this` outlives the hook. The hook
    // is told the strand's id (its number in the run); k is its place here.
    Helices[k].setContactForces(
        [this, k](int id, double t, const std::vector<StrandSample>& samples,
                  std::vector<ContactResponse>& response)
        { respond(k, id, t, samples, response); });
  }
  return Status::Ok();
}

void SuperHelixModel::respond(std::size_t strand, int id, double t,
                              const std::vector<StrandSample>& samples,
                              std::vector<ContactResponse>& response) const
{
  if (Options.contacts.enabled && !World.parts.empty())
  {
    thread_local std::vector<PosedPart> parts; // no allocation after the first call
    World.posedParts(t, parts);
    Body.respond(samples, Helices[strand].spec().hair.linearDensity(), parts.data(),
                 static_cast<int>(parts.size()), response);
  }
  if (Options.hairHairEnabled)
  {
    HairHair.addResponses(id, samples, response); // found by the strands' ids
  }
  if (Options.additionalContacts)
  {
    Options.additionalContacts(id, t, samples, response);
  }
}

double SuperHelixModel::time() const
{
  return Time;
}

Status SuperHelixModel::advanceTo(double target)
{
  const int steps =
      std::max(1, static_cast<int>(std::ceil(Run.frameInterval / Run.timeStep - 1e-9)));
  const double dt = (target - Time) / steps;
  auto findContacts = [&]() -> Status
  {
    if (Status s = findHairHairContacts(Helices, HairHair); !s)
    {
      return Status::Error("hair–hair contacts at t = " + std::to_string(time()) +
                           " s: " + s.message());
    }
    return Status::Ok();
  };
  Substeps = Rejected = FirstOrder = 0;
  FrameError.assign(Helices.size(), 0.0);
  for (int i = 0; i < steps; ++i)
  {
    // Hair–hair: a search before each step; when pairs close fast, the step is cut into
    // pieces that each start with a new search (HairHairContacts::updatesPerStep).
    int pieces = 1;
    if (Options.hairHairEnabled)
    {
      if (Status s = findContacts(); !s)
      {
        return s;
      }
      pieces = HairHair.updatesPerStep(dt, Options.hairHairMaxUpdates);
    }
    for (int k = 0; k < pieces; ++k)
    {
      if (k > 0)
      {
        if (Status s = findContacts(); !s)
        {
          return s;
        }
      }
      // The tolerance is per second of simulated time: each piece of a step gets its share.
      const double tolerance = Options.tolerance * (dt / pieces);
      if (Status s = stepStrands(Helices, dt / pieces, Run.threads, tolerance); !s)
      {
        return s;
      }
      tally();
    }
  }
  Time = target;
  return Status::Ok();
}

void SuperHelixModel::tally()
{
  for (std::size_t k = 0; k < Helices.size(); ++k)
  {
    const SuperHelix& h = Helices[k];
    Substeps += h.lastSubsteps();
    Rejected += h.lastRejected();
    FirstOrder += h.lastFirstOrder();
    FrameError[k] += h.lastErrorEstimate();
  }
}

std::map<std::string, double> SuperHelixModel::stepStatistics() const
{
  const double strands = std::max<std::size_t>(1, Helices.size());
  double error = 0;
  for (double e : FrameError)
  {
    error = std::max(error, e);
  }
  return {{"substeps", Substeps / strands},
          {"rejected_substeps", Rejected / strands},
          {"first_order_share", Substeps > 0 ? FirstOrder / Substeps : 0.0},
          {"error_estimate", error}};
}

void SuperHelixModel::describe(StateHeader& header) const
{
  const int n = Helices.empty() ? 0 : Helices[0].elementCount();
  header.model = name();
  header.coordinatesPerStrand = 3 * n;
  header.offsets.clear();
  std::int64_t first = 0;
  header.offsets.push_back(first);
  for (const SuperHelix& h : Helices)
  {
    first += h.elementCount() * Options.pointsPerElement + 1;
    header.offsets.push_back(first);
  }
  auto& at = header.attributes;
  at["points_per_element"] = Options.pointsPerElement;
  at["quadrature_tolerance"] = Options.quadratureTolerance;
  at["integrator"] = static_cast<int>(Options.integrator);
  at["tolerance"] = Options.tolerance;
  const BodyContactParameters& c = Options.contacts;
  at["contacts"] = c.enabled ? 1 : 0;
  at["contact_stiffness"] = c.stiffness;
  at["contact_damping_ratio"] = c.dampingRatio;
  at["friction_coefficient"] = c.friction;
  at["friction_anisotropy"] = c.anisotropy;
  at["contact_thickness"] = c.thickness;
  at["slip_velocity"] = c.slipVelocity;
  at["hair_hair_contacts"] = Options.hairHairEnabled ? 1 : 0;
  if (Options.hairHairEnabled)
  {
    const HairHairParameters& h = Options.hairHair;
    at["hair_hair_thickness"] = h.thickness;
    at["hair_hair_stiffness"] = h.stiffness;
    at["hair_hair_damping"] = h.damping;
    at["hair_hair_friction"] = h.friction;
    at["hair_hair_per_length"] = h.perLength ? 1 : 0;
    at["hair_hair_reference_length"] = h.referenceLength;
    at["hair_hair_max_updates"] = Options.hairHairMaxUpdates;
  }
}

void SuperHelixModel::writeFrame(StateFrame& f) const
{
  // Display points, their velocities, curvature and twist, drawn from q, q̇ and the root as
  // a state file's frame is drawn again (drawSuperHelix), strand by strand on the run's
  // threads into pre-sized arrays (each strand alone: the same values on any number of
  // threads).
  const int per = Options.pointsPerElement;
  std::vector<std::size_t> first(Helices.size() + 1, 0);
  std::size_t qSize = 0;
  for (std::size_t k = 0; k < Helices.size(); ++k)
  {
    first[k + 1] = first[k] + Helices[k].elementCount() * per + 1;
    qSize += Helices[k].q().size();
  }
  const std::size_t points = first.back();
  f.positions.resize(points);
  f.velocities.resize(points);
  std::vector<double>& curvature = f.pointData["curvature"];
  std::vector<double>& twist = f.pointData["twist"];
  curvature.resize(points);
  twist.resize(points);
  std::vector<RootState> roots(Helices.size());
  parallelBlocks(
      static_cast<std::int64_t>(Helices.size()), 16, Run.threads,
      [&](std::int64_t begin, std::int64_t end)
      {
        StrandPoints drawn;
        for (std::int64_t k = begin; k < end; ++k)
        {
          const SuperHelix& h = Helices[k];
          roots[k] = h.rootState(h.time());
          drawSuperHelix(h.spec().elementLengths, h.q().data(), h.qdot().data(), roots[k], per,
                         drawn);
          std::copy(drawn.positions.begin(), drawn.positions.end(), f.positions.begin() + first[k]);
          std::copy(drawn.velocities.begin(), drawn.velocities.end(),
                    f.velocities.begin() + first[k]);
          std::copy(drawn.curvature.begin(), drawn.curvature.end(), curvature.begin() + first[k]);
          std::copy(drawn.twist.begin(), drawn.twist.end(), twist.begin() + first[k]);
        }
      });
  f.q.clear();
  f.qdot.clear();
  f.rootFrames.clear();
  f.rootVelocities.clear();
  f.q.reserve(qSize);
  f.qdot.reserve(qSize);
  for (std::size_t k = 0; k < Helices.size(); ++k)
  {
    const SuperHelix& h = Helices[k];
    f.q.insert(f.q.end(), h.q().data(), h.q().data() + h.q().size());
    f.qdot.insert(f.qdot.end(), h.qdot().data(), h.qdot().data() + h.qdot().size());
    appendRoot(roots[k], f.rootFrames, f.rootVelocities);
  }
}

double SuperHelixModel::stepCost(const GuideStrand& g) const
{
  // A step costs about Element per element plus Sample per quadrature sample: the line
  // through the four presets' steps at N = 10 (bench_superhelix BM_Step and its samples
  // counter, docs/benchmarks.md "Cost of a strand"). The samples are those the quadrature
  // takes for the guide's natural curl, as at rest.
  constexpr double Element = 1.43, Sample = 0.108; // µs
  const QuadratureChooser chooser(Options.quadratureTolerance);
  const double turning = g.hair.naturalCurvature().norm() * g.length / g.elements;
  const int samples = g.elements * chooser.choose(turning).samples();
  return Element * g.elements + Sample * samples;
}

EnergyBudget SuperHelixModel::energy() const
{
  EnergyReport sum;
  for (const SuperHelix& h : Helices)
  {
    const EnergyReport& e = h.energy();
    sum.kinetic += e.kinetic;
    sum.elastic += e.elastic;
    sum.gravitational += e.gravitational;
    sum.total.frictionDissipated += e.total.frictionDissipated;
    sum.total.airDissipated += e.total.airDissipated;
    sum.total.rootWork += e.total.rootWork;
    sum.total.windWork += e.total.windWork;
    sum.total.contactWork += e.total.contactWork;
    sum.total.loadWork += e.total.loadWork;
    sum.total.residual += e.total.residual;
  }
  EnergyBudget b;
  b.add(energy::Kinetic, EnergyKind::State, sum.kinetic);
  b.add(energy::Elastic, EnergyKind::State, sum.elastic);
  b.add(energy::Gravitational, EnergyKind::State, sum.gravitational);
  b.add("friction_dissipated", EnergyKind::Dissipation, sum.total.frictionDissipated);
  b.add("air_dissipated", EnergyKind::Dissipation, sum.total.airDissipated);
  b.add("root_work", EnergyKind::Work, sum.total.rootWork);
  b.add("wind_work", EnergyKind::Work, sum.total.windWork);
  b.add("contact_work", EnergyKind::Work, sum.total.contactWork);
  b.add(energy::Residual, EnergyKind::Residual, sum.total.residual);
  return b;
}

} // namespace hair
