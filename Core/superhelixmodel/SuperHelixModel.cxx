#include "superhelixmodel/SuperHelixModel.h"
#include "superhelix/SubstepControl.h"

#include "common/Parallel.h"
#include "groom/CurveFit.h"
#include "groom/SagFree.h"
#include "helix/Centerline.h"

#include <algorithm>
#include <cmath>
#include <limits>
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
  if (Status st = checkIntegrator(integrator); !st)
  {
    return st;
  }
  if (!(std::isfinite(tolerance) && tolerance >= 0))
  {
    std::ostringstream s;
    s << "the tolerance " << tolerance
      << " m/s is not a distance per second >= 0; give 0 for fixed steps or the error the "
         "steps may add per second of simulated time, e.g. 5e-3.";
    return Status::Error(s.str());
  }
  if (Status s = contacts.validate(); !s)
  {
    return Status::Error("hair–body contacts: " + s.message());
  }
  if (Status s = hairHair.validate(); !s)
  {
    return s;
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
  HairHairWork = HairHairDissipated = 0;
  Options.contacts.lookAhead = run.timeStep;
  if (Status s = Body.setParameters(Options.contacts); !s)
  {
    return Status::Error("hair–body contacts: " + s.message());
  }
  if (Options.hairHair.enabled && Options.hairHair.solver != HairHairSolver::Grid &&
      run.ranks.parallel())
  {
    // The pairs would be found among each rank's own strands only: a run that silently
    // differs from the same run on one rank. The grid is summed over the ranks; the pairs
    // do not use the ghost strands yet (docs/mpi.md, "Hair–hair interaction across ranks").
    return Status::Error(std::string("hair–hair interaction: the ") +
                         toString(Options.hairHair.solver) +
                         " solver is not available under "
                         "MPI yet (" +
                         std::to_string(run.ranks.size()) +
                         " ranks): each rank would only see pairs among its own strands. Choose "
                         "the grid (Hair Hair Contacts = Grid), or run on one rank.");
  }
  if (Options.hairHair.enabled)
  {
    HairHairParameters hh = Options.hairHair.pairs;
    hh.threads = std::max(1, run.threads);
    // The run's guides (every rank's share) and their mean fibre radius: a guide stands for
    // HeadFibres / guides fibres.
    double count = static_cast<double>(guides.size()), radiusSum = 0;
    for (const GuideStrand& g : guides)
      radiusSum += g.hair.radius;
    count = run.ranks.sum(count);
    radiusSum = run.ranks.sum(radiusSum);
    if (hh.thickness == 0 && count > 0)
    {
      // Automatic: the clump of the head's fibres each guide stands for (their mean radius).
      hh.thickness =
          HairHairParameters::automaticThickness(radiusSum / count, static_cast<int>(count));
    }
    HairHairThickness = hh.thickness; // as used (the state file records it)
    if (Status s = HairHair.setParameters(hh); !s)
    {
      return Status::Error("hair–hair contacts: " + s.message());
    }
    if (Options.hairHair.solver == HairHairSolver::GridAndNearField)
    {
      // The near field keeps guides from crossing, not apart by their clumps' width (the
      // grid's volume does that): its automatic distance is a quarter of the clump's.
      NearFieldParameters nf = Options.hairHair.nearField;
      nf.thickness = Options.hairHair.pairs.thickness > 0 ? hh.thickness : 0.25 * hh.thickness;
      nf.threads = std::max(1, run.threads);
      if (Status s = Near.setParameters(nf); !s)
      {
        return Status::Error("hair–hair interaction: " + s.message());
      }
      Near.reset();
    }
    if (Options.hairHair.solver != HairHairSolver::Coupled)
    {
      if (Status s = Grid.setParameters(Options.hairHair.grid); !s)
      {
        return Status::Error("hair–hair interaction: " + s.message());
      }
      // A guide stands for a head's fibres shared among the guides (HeadFibres / guides,
      // as the automatic thickness): their cross-section is its volume per unit length.
      ClumpArea.resize(guides.size());
      for (std::size_t k = 0; k < guides.size(); ++k)
      {
        ClumpArea[k] = guideClumpArea(guides[k].hair.radius, count);
      }
    }
  }
  // The wind: the fast uniform path when the air is steady and uniform, the field otherwise.
  const bool uniformAir = World.air.isSteadyAndUniform();
  const Eigen::Vector3d uniformWind = World.air.velocity(Eigen::Vector3d::Zero(), 0);
  // The body's contacts as a sag-free rest shape balances them: the parts where they are at
  // t = 0, held still (no hair–hair contacts: each strand is balanced on its own).
  std::vector<PosedPart> still;
  World.posedParts(0, still);
  for (PosedPart& p : still)
  {
    p.velocity.setZero();
    p.angularVelocity.setZero();
  }
  ContactForces restContacts;
  // With static friction, each strand's anchors where it rests on the body: a shape held at
  // rest is held against sliding too, so its stability (the Hessian, and the settling run
  // that checks it) counts the anchors' tangential springs at the samples that touch; the
  // balance itself is unchanged (the springs pull nothing at zero stretch).
  std::vector<std::vector<BodyAnchor>> restAnchors(guides.size());
  if (Options.contacts.enabled && !still.empty())
  {
    // Called by buildStrand's wrapper with the strand's place k here (the strand itself
    // would give its id, its number in the run, which under MPI is not its place).
    restContacts = [this, &still, &guides, &restAnchors](int k, double,
                                                         const std::vector<StrandSample>& samples,
                                                         std::vector<ContactResponse>& response)
    {
      Body.respond(samples, guides[k].hair.linearDensity(), still.data(),
                   static_cast<int>(still.size()), response, nullptr, &restAnchors[k]);
    };
  }
  Helices.assign(guides.size(), SuperHelix());
  Anchors.assign(guides.size(), {});
  Built = guides;
  Reports.assign(guides.size(), GroomReport());
  // Strand by strand on the run's threads: a groom's fit and a sag-free rest shape cost
  // milliseconds each (docs/benchmarks.md).
  const Status built = parallelEach(static_cast<std::int64_t>(guides.size()), Run.threads,
                                    [&](std::int64_t k) {
                                      return buildStrand(static_cast<int>(k), guides[k], uniformAir,
                                                         uniformWind, restContacts);
                                    });
  if (!built)
  {
    return built;
  }
  for (std::size_t k = 0; k < Helices.size(); ++k)
  {
    // The model lives on the heap and owns the strands: `this` outlives the hook. The hook
    // is told the strand's id (its number in the run); k is its place here.
    Helices[k].setContactForces(
        [this, k](int id, double t, const std::vector<StrandSample>& samples,
                  std::vector<ContactResponse>& response)
        { respond(k, id, t, samples, response); });
  }
  return Status::Ok();
}

Status SuperHelixModel::buildStrand(int k, const GuideStrand& g, bool uniformAir,
                                    const Eigen::Vector3d& uniformWind,
                                    const ContactForces& restContacts)
{
  // The run's number of the strand (under MPI this rank has a share of the guides).
  const int id = Run.strandId(k);
  const std::string name = "strand " + std::to_string(id);
  // A groom: the Super-Helix fitted to its curve gives the length, the root frame and q.
  SuperHelixFit fit;
  Eigen::Matrix3d frame = g.rootFrame();
  double length = g.length;
  if (!g.curve.empty())
  {
    if (Status s = fitSuperHelix(g.curve, g.normal, g.elements, fit); !s)
    {
      return Status::Error(name + ": " + s.message());
    }
    // Where the curve leaves an element's twist free (it hardly bends there), the fit can end
    // at twists no step can take (measured: 1e3–1e7 1/m on a settled smooth groom, which blew
    // the first step up). A fit that twists an element more than half a turn away from the
    // hair's natural twist is done again with the twist held towards it: a radian an element
    // costs as much as 1 µm at one point (ℓ from the curve itself, so that a run of the guides
    // read back from its state file, whose length is the fit's, fits the same).
    const double natural = g.hair.naturalCurvature()[0];
    double element = 0;
    for (std::size_t i = 1; i < g.curve.size(); ++i)
    {
      element += (g.curve[i] - g.curve[i - 1]).norm() / g.elements;
    }
    double turned = 0;
    for (int e = 0; e < g.elements; ++e)
    {
      turned = std::max(turned, std::abs(fit.q(3 * e) - natural) * element);
    }
    if (turned > M_PI)
    {
      if (Status s =
              fitSuperHelix(g.curve, g.normal, g.elements, fit, 1e-12 * element * element, natural);
          !s)
      {
        return Status::Error(name + ": " + s.message());
      }
    }
    frame = fit.rootFrame;
    length = fit.length;
    Built[k].length = length;
    Built[k].growth = frame.col(0);
    Reports[k].fitError = fit.maxError;
  }
  StrandSpec spec = StrandSpec::uniform(length, g.elements, g.hair);
  spec.name = name;
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
  spec.root = World.rootMotion.carriedRoot(g.root, frame);
  SuperHelix& h = Helices[k];
  if (Status s = h.initialize(spec, 0.0); !s)
  {
    return s;
  }
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(3 * g.elements);
  if (!g.curve.empty())
  {
    if (Status s = h.setState(fit.q, zero); !s)
    {
      return s;
    }
  }
  if (g.restShape != RestShape::SagFree)
  {
    return Status::Ok();
  }
  // Sag-free: the natural shape that holds the shape at t = 0 (the groom, or the grown
  // natural helix), or the closest stable shape where none can.
  ContactForces contacts;
  if (restContacts)
  {
    contacts = [&restContacts, k](int, double t, const std::vector<StrandSample>& samples,
                                  std::vector<ContactResponse>& response)
    { restContacts(k, t, samples, response); };
  }
  SagFreeResult r;
  if (Status s = sagFree(spec, h.q(), contacts, Options.sagFree, r); !s)
  {
    return Status::Error(name + ": " + s.message());
  }
  spec.restCurvature.assign(r.rest.data(), r.rest.data() + r.rest.size());
  if (Status s = h.initialize(spec, 0.0); !s)
  {
    return s;
  }
  if (Status s = h.setState(r.start, zero); !s)
  {
    return s;
  }
  GroomReport& report = Reports[k];
  report.outcome = r.outcome;
  report.deviation = r.deviation;
  report.stability = r.stability;
  report.reason = r.reason;
  return Status::Ok();
}

void SuperHelixModel::groomed(std::vector<GuideStrand>& guides,
                              std::vector<GroomReport>& reports) const
{
  guides = Built;
  reports = Reports;
}

void SuperHelixModel::restCoordinates(std::vector<double>& values) const
{
  values.clear();
  for (const SuperHelix& h : Helices)
  {
    values.insert(values.end(), h.restCurvature().data(),
                  h.restCurvature().data() + h.restCurvature().size());
  }
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
                 static_cast<int>(parts.size()), response, nullptr, &Anchors[strand]);
  }
  if (usesGrid())
  {
    const double rhoS = Helices[strand].spec().hair.linearDensity();
    for (std::size_t j = 0; j < samples.size(); ++j)
    {
      Grid.respond(samples[j].position, rhoS, ClumpArea[strand], response[j]);
    }
  }
  if (Options.additionalContacts)
  {
    Options.additionalContacts(id, t, samples, response);
  }
}

void SuperHelixModel::buildGrid(double h)
{
  // Each strand's polyline from the root through its samples (on the run's threads), and
  // the hair's bounds.
  GridPoints.resize(Helices.size());
  GridVelocities.resize(Helices.size());
  parallelBlocks(static_cast<std::int64_t>(Helices.size()), 16, std::max(1, Run.threads),
                 [&](std::int64_t b0, std::int64_t b1)
                 {
                   for (std::int64_t k = b0; k < b1; ++k)
                   {
                     const SuperHelix& helix = Helices[k];
                     const std::vector<StrandSample>& s = helix.samples();
                     const RootState root = helix.rootState(helix.time());
                     std::vector<Eigen::Vector3d>& x = GridPoints[k];
                     std::vector<Eigen::Vector3d>& v = GridVelocities[k];
                     x.resize(s.size() + 1);
                     v.resize(s.size() + 1);
                     x[0] = root.position;
                     v[0] = root.velocity;
                     for (std::size_t j = 0; j < s.size(); ++j)
                     {
                       x[j + 1] = s[j].position;
                       v[j + 1] = s[j].velocity;
                     }
                   }
                 });
  std::vector<HairGrid::Strand> strands(Helices.size());
  for (std::size_t k = 0; k < Helices.size(); ++k)
  {
    strands[k] = {GridPoints[k].data(), GridVelocities[k].data(),
                  static_cast<int>(GridPoints[k].size()), ClumpArea[k], Helices[k].length()};
  }
  Grid.build(strands, h, Run.ranks, Run.threads);
}

Status SuperHelixModel::coupledStep(double t0, double h)
{
  if (Options.hairHair.solver == HairHairSolver::Coupled)
  {
    if (Status s = stepStrandsWithContacts(Helices, HairHair, h, Run.threads); !s)
    {
      return s;
    }
    HairHairWork += HairHair.stats().work;
    HairHairDissipated += HairHair.stats().dissipated;
    return Status::Ok();
  }
  // The grid and the near field (the grid alone is stepped in advanceTo, each strand on its
  // own sub-steps through it).
  buildGrid(h);
  // The roots' rigid motion over the step, end to start: pieces moving with the head are
  // boxed by their motion relative to it (NearFieldContacts::detect).
  const Eigen::Isometry3d carry =
      World.rootMotion.pose(t0) * World.rootMotion.pose(t0 + h).inverse();
  if (Status s = stepStrandsWithNearField(Helices, Near, h, Run.threads, carry); !s)
  {
    return s;
  }
  HairHairWork += Near.stats().work;
  return Status::Ok();
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
  Substeps = Rejected = FirstOrder = 0;
  FrameError.assign(Helices.size(), 0.0);
  for (int i = 0; i < steps; ++i)
  {
    if (!Options.hairHair.enabled || Options.hairHair.solver == HairHairSolver::Grid)
    {
      // The grid, when on, is built once per step: each strand takes its own sub-steps
      // through it. The tolerance is per second of simulated time: each step gets its share.
      if (Options.hairHair.enabled)
      {
        buildGrid(dt);
      }
      // With the grid (built by every rank at every step, collectively), when a strand
      // failed on any rank all stop at this step, the others with Ok, so that the run
      // reports the failure's own rank and message (Simulation::advanceTo agrees on it).
      const Status s = stepStrands(Helices, dt, Run.threads, Options.tolerance * dt);
      if (Options.hairHair.enabled ? Run.ranks.any(!s) : !s)
      {
        return s;
      }
      tally();
      continue;
    }
    // Hair–hair: the pairs that may touch within the step are found before it and solved
    // together with it (docs/hair-hair-contacts.md). The coupled step advances all strands
    // together, so with a tolerance the sub-steps are common to all strands: each one's size
    // comes from the largest error estimate of the previous one (as SuperHelix::advance
    // chooses its next sub-step, e ∝ h²), and none is taken again (a coupled step is not
    // undone): the estimates reported may exceed the tolerance where the motion changes
    // abruptly.
    double remaining = dt;
    while (remaining > 1e-12 * dt)
    {
      double h = remaining;
      if (Options.tolerance > 0)
      {
        h = substeps::land(std::max(NextCoupledStep > 0 ? std::min(NextCoupledStep, dt) : dt,
                                    dt / SuperHelix::MaxSubsteps),
                           remaining);
      }
      const double t0 = Time + i * dt + (dt - remaining);
      if (Status s = coupledStep(t0, h); !s)
      {
        return Status::Error("hair–hair contacts, step from t = " + std::to_string(t0) +
                             " s: " + s.message());
      }
      tally();
      remaining -= h;
      if (Options.tolerance > 0)
      {
        // The largest ratio, each strand's estimate of its own order in h (BDF2's O(h³)).
        double grow = substeps::Growth;
        for (const SuperHelix& helix : Helices)
        {
          grow =
              std::min(grow, substeps::factor(helix.lastErrorEstimate() / (Options.tolerance * h),
                                              helix.lastErrorPower()));
        }
        NextCoupledStep = substeps::afterAccepted(h, grow, h);
      }
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

std::vector<StepStatisticRule> SuperHelixModel::stepStatisticRules() const
{
  // Means over the strands, the share of first-order steps weighted by its sub-steps, the
  // largest error estimate.
  using R = StepStatisticRule::Reduction;
  return {{"substeps", R::StrandMean, ""},
          {"rejected_substeps", R::StrandMean, ""},
          {"first_order_share", R::StrandMean, "substeps"},
          {"error_estimate", R::Max, ""}};
}

double SuperHelixModel::bytesPerElement() const
{
  // Measured with hair_study scene (200 and 400 wavy strands of 10, 50 and 100 elements, two
  // frames, maximum resident memory): about 2.6 kB per element.
  return 2600;
}

void SuperHelixModel::describe(StateHeader& header) const
{
  const int n = Helices.empty() ? 0 : Helices[0].elementCount();
  header.model = name();
  header.coordinatesPerStrand = 3 * n;
  // The frame's points are the elements' ends; every other point is drawn from q and the
  // root when asked (simulation/GuideDrawing.h), so the file keeps these as a view.
  header.singlePrecisionPoints = true;
  header.offsets.clear();
  std::int64_t first = 0;
  header.offsets.push_back(first);
  for (const SuperHelix& h : Helices)
  {
    first += h.elementCount() + 1;
    header.offsets.push_back(first);
  }
  auto& at = header.attributes;
  at["quadrature_tolerance"] = Options.quadratureTolerance;
  at["integrator"] = static_cast<int>(Options.integrator);
  at["tolerance"] = Options.tolerance;
  const BodyContactParameters& c = Options.contacts;
  at["contacts"] = c.enabled ? 1 : 0;
  at["contact_stiffness"] = c.stiffness;
  at["contact_damping_ratio"] = c.dampingRatio;
  at["friction_coefficient"] = c.friction;
  at["friction_anisotropy"] = c.anisotropy;
  at["static_friction_coefficient"] = c.staticFriction;
  at["contact_thickness"] = c.thickness;
  at["slip_velocity"] = c.slipVelocity;
  for (const auto& [key, value] : Options.hairHair.gridAttributes(Grid.cellSize()))
  {
    at[key] = value;
  }
  if (Options.hairHair.enabled && Options.hairHair.solver == HairHairSolver::GridAndNearField)
  {
    at["hair_hair_thickness"] = Near.parameters().thickness;
    at["hair_near_field_margin"] = Options.hairHair.nearField.margin;
    at["hair_near_field_sweeps"] = Options.hairHair.nearField.sweeps;
  }
  else if (Options.hairHair.enabled && Options.hairHair.solver == HairHairSolver::Coupled)
  {
    const HairHairParameters& h = Options.hairHair.pairs;
    at["hair_hair_thickness"] = HairHairThickness;
    at["hair_hair_stiffness"] = h.stiffness;
    at["hair_hair_damping"] = h.damping;
    at["hair_hair_friction_coefficient"] = h.friction;
    at["hair_hair_margin"] = h.margin;
    at["hair_hair_head_fibres"] = HairHairParameters::HeadFibres;
    at["hair_hair_per_length"] = h.perLength ? 1 : 0;
    at["hair_hair_reference_length"] = h.referenceLength;
    at["hair_hair_iterations"] = h.iterations;
    at["hair_hair_tolerance"] = h.tolerance;
  }
}

void SuperHelixModel::writeFrame(StateFrame& f) const
{
  // The state (q, q̇, the root's pose and rates) and the elements' ends with their
  // velocities, drawn from it as a state file's frame is drawn again (drawSuperHelix at one
  // point per element), strand by strand on the run's threads into the frame's arrays
  // (resized, not reallocated, when the frame is reused; each strand alone: the same values
  // on any number of threads).
  std::vector<std::size_t> first(Helices.size() + 1, 0), qFirst(Helices.size() + 1, 0);
  for (std::size_t k = 0; k < Helices.size(); ++k)
  {
    first[k + 1] = first[k] + Helices[k].elementCount() + 1;
    qFirst[k + 1] = qFirst[k] + std::size_t(Helices[k].q().size());
  }
  const std::size_t strands = Helices.size();
  f.positions.resize(first.back());
  f.velocities.resize(first.back());
  f.q.resize(qFirst.back());
  f.qdot.resize(qFirst.back());
  f.rootFrames.resize(strands * RootFrameValues);
  f.rootVelocities.resize(strands * RootVelocityValues);
  parallelBlocks(
      static_cast<std::int64_t>(strands), 16, Run.threads,
      [&](std::int64_t begin, std::int64_t end)
      {
        StrandPoints drawn;
        std::vector<double> pose, rates;
        for (std::int64_t k = begin; k < end; ++k)
        {
          const SuperHelix& h = Helices[k];
          const RootState root = h.rootState(h.time());
          drawSuperHelix(h.spec().elementLengths, h.q().data(), h.qdot().data(), root, 1, drawn);
          std::copy(drawn.positions.begin(), drawn.positions.end(), f.positions.begin() + first[k]);
          std::copy(drawn.velocities.begin(), drawn.velocities.end(),
                    f.velocities.begin() + first[k]);
          std::copy(h.q().data(), h.q().data() + h.q().size(), f.q.begin() + qFirst[k]);
          std::copy(h.qdot().data(), h.qdot().data() + h.qdot().size(), f.qdot.begin() + qFirst[k]);
          pose.clear();
          rates.clear();
          appendRoot(root, pose, rates);
          std::copy(pose.begin(), pose.end(), f.rootFrames.begin() + k * RootFrameValues);
          std::copy(rates.begin(), rates.end(), f.rootVelocities.begin() + k * RootVelocityValues);
        }
      });
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
    sum.total.fieldWork += e.total.fieldWork;
    sum.total.fieldDissipated += e.total.fieldDissipated;
  }
  EnergyBudget b;
  b.add(energy::Kinetic, EnergyKind::State, sum.kinetic);
  b.add(energy::Elastic, EnergyKind::State, sum.elastic);
  b.add(energy::Gravitational, EnergyKind::State, sum.gravitational);
  b.add("friction_dissipated", EnergyKind::Dissipation, sum.total.frictionDissipated);
  b.add("air_dissipated", EnergyKind::Dissipation, sum.total.airDissipated);
  b.add("root_work", EnergyKind::Work, sum.total.rootWork);
  b.add("wind_work", EnergyKind::Work, sum.total.windWork);
  if (usesGrid())
  {
    // The strands' contact work holds the far field's (the grid's drag and push) and the
    // near field's pairs: reported apart. The grid's as the work of its forces plus what
    // its drag dissipated, and that dissipation (the drag relative to the hair around);
    // the pairs' as their work. Works − dissipations is unchanged.
    addGridContactWork(b, sum.total.contactWork - HairHairWork, sum.total.fieldWork,
                       sum.total.fieldDissipated);
    if (Options.hairHair.solver == HairHairSolver::GridAndNearField)
    {
      b.add("hair_hair_work", EnergyKind::Work, HairHairWork);
    }
  }
  else if (Options.hairHair.enabled)
  {
    // The strands' contact work holds the hair–hair forces' work too: reported apart, as
    // the work of the penalty (what the pairs' forces did, less what their damping and
    // friction dissipated) and that dissipation, so that works − dissipations is unchanged.
    b.add("contact_work", EnergyKind::Work, sum.total.contactWork - HairHairWork);
    b.add("hair_hair_work", EnergyKind::Work, HairHairWork + HairHairDissipated);
    b.add("hair_hair_dissipated", EnergyKind::Dissipation, HairHairDissipated);
  }
  else
  {
    b.add("contact_work", EnergyKind::Work, sum.total.contactWork);
  }
  b.add(energy::Residual, EnergyKind::Residual, sum.total.residual);
  return b;
}

} // namespace hair

namespace hair
{

// A strand's continuation: the rod's (SuperHelix::saveContinuation), then its static-friction
// anchors: their count L (samples × parts), the number m of those not at rest, and m groups
// of (index, rest x y z, flows, sliding).
namespace
{
constexpr std::size_t AnchorValues = 6;
}

std::string SuperHelixModel::continuationRefusal() const
{
  if (Options.hairHair.enabled && Options.hairHair.solver != HairHairSolver::Grid)
  {
    return std::string("its hair–hair interaction (the ") + toString(Options.hairHair.solver) +
           " solver) keeps the pairs of the last step, which the state file does not hold: "
           "only runs with the grid or without hair–hair interaction are resumed";
  }
  return {};
}

std::size_t SuperHelixModel::continuationCapacity(std::size_t k) const
{
  // With static friction, every (sample, part) pair anchored, at the samples of the strand
  // at rest (a strand bent further takes more samples: the file then keeps no continuation
  // for that frame, StateFileWriter::append); without, no anchor is ever set.
  const SuperHelix& h = Helices[k];
  const bool anchors = Options.contacts.enabled && Options.contacts.staticFriction > 0;
  const std::size_t pairs = anchors ? h.samples().size() * World.parts.size() : 0;
  return SuperHelix::continuationSize(h.elementCount()) + 2 + AnchorValues * pairs;
}

void SuperHelixModel::saveContinuation(StateContinuation& out) const
{
  out.strands.resize(Helices.size());
  for (std::size_t k = 0; k < Helices.size(); ++k)
  {
    std::vector<double>& v = out.strands[k];
    v.clear();
    Helices[k].saveContinuation(v);
    const std::vector<BodyAnchor>& anchors = Anchors[k];
    v.push_back(double(anchors.size()));
    const std::size_t count = v.size();
    v.push_back(0);
    for (std::size_t i = 0; i < anchors.size(); ++i)
    {
      const BodyAnchor& a = anchors[i];
      if (a.set || a.flows != 0 || a.sliding || a.rest != Eigen::Vector3d::Zero())
      {
        v.insert(v.end(), {double(i), a.rest.x(), a.rest.y(), a.rest.z(), double(a.flows),
                           a.set ? (a.sliding ? 3.0 : 1.0) : (a.sliding ? 2.0 : 0.0)});
        v[count] += 1;
      }
    }
  }
  out.run = {Time, NextCoupledStep};
}

Status SuperHelixModel::restoreContinuation(const StateContinuation& in)
{
  if (in.strands.size() != Helices.size() || in.run.size() != 2)
  {
    return Status::Error("the continuation is of " + std::to_string(in.strands.size()) +
                         " Super-Helix strands and " + std::to_string(in.run.size()) +
                         " model values; this model has " + std::to_string(Helices.size()) +
                         " strands and 2.");
  }
  for (std::size_t k = 0; k < Helices.size(); ++k)
  {
    const std::vector<double>& v = in.strands[k];
    std::size_t used = 0;
    if (Status s = Helices[k].restoreContinuation(v.data(), v.size(), used); !s)
    {
      return s;
    }
    const auto bad = [&](const char* what)
    {
      return Status::Error("strand " + std::to_string(Run.strandId(k)) +
                           ": its continuation's static-friction anchors " + what + ".");
    };
    if (v.size() < used + 2)
    {
      return bad("are missing");
    }
    const double size = v[used], count = v[used + 1];
    if (!(size >= 0 && size <= 1e8 && count >= 0 && count <= size &&
          v.size() == used + 2 + AnchorValues * std::size_t(count)))
    {
      return bad("do not add up");
    }
    std::vector<BodyAnchor>& anchors = Anchors[k];
    anchors.assign(std::size_t(size), BodyAnchor());
    for (std::size_t j = 0; j < std::size_t(count); ++j)
    {
      const double* a = &v[used + 2 + AnchorValues * j];
      if (!(a[0] >= 0 && a[0] < size) || !std::isfinite(a[1] + a[2] + a[3]))
      {
        return bad("name a sample that does not exist or a point that is not finite");
      }
      BodyAnchor& b = anchors[std::size_t(a[0])];
      b.rest = Eigen::Vector3d(a[1], a[2], a[3]);
      b.flows = int(a[4]);
      b.set = a[5] == 1 || a[5] == 3;
      b.sliding = a[5] >= 2;
    }
  }
  Time = in.run[0];
  NextCoupledStep = in.run[1];
  return Status::Ok();
}

} // namespace hair
