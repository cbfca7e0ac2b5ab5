// The projective strands' stepper: the explicit angular equations of every joint from the
// tip to the root (forces), the placement of the segments (Projection.cxx), the energy
// budget, and the threads.
#include "projective/ProjectiveStrands.h"

#include "common/Parallel.h"
#include "contact/BodyContacts.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iterator>

namespace hair
{

namespace
{
bool finite(double x)
{
  return std::isfinite(x);
}
} // namespace

Status ProjectiveOptions::validate() const
{
  if (!finite(timeStep) || !(timeStep > 0))
  {
    return Status::Error("options: the time step must be a number > 0 s");
  }
  if (!finite(contact.stiffness) || contact.stiffness < 0 || !finite(contact.damping))
  {
    return Status::Error("options: the contact stiffness must be a number ≥ 0");
  }
  if (!finite(contactMargin) || contactMargin < 0)
  {
    return Status::Error("options: the contact margin must be a number ≥ 0 m");
  }
  if (threads < 1)
  {
    return Status::Error("options: the number of threads must be ≥ 1");
  }
  if (Status s = validateFriction(friction, staticFriction, anisotropy); !s)
  {
    return Status::Error("options: " + s.message());
  }
  return Status::Ok();
}

void ProjectiveStepStats::merge(const ProjectiveStepStats& other)
{
  contacts += other.contacts;
  projections += other.projections;
  stuck += other.stuck;
  sliding += other.sliding;
  maxDepthBefore = std::max(maxDepthBefore, other.maxDepthBefore);
  if (other.maxDepthAfter > maxDepthAfter)
  {
    maxDepthAfter = other.maxDepthAfter;
    deepestPoint = other.deepestPoint;
    deepestPart = other.deepestPart;
  }
}

void ProjectiveStrands::forward(Strand& s, const Eigen::Vector3d& root,
                                const Eigen::Matrix3d& frame) const
{
  s.P[0] = root;
  s.R[0] = frame;
  const std::size_t k = s.q.size();
  for (std::size_t i = 1; i <= k; ++i)
  {
    s.R[i] = s.R[i - 1] * segmentRotation(s.q[i - 1].x(), s.q[i - 1].y());
    s.P[i] = s.P[i - 1] + s.d * s.R[i].col(2);
  }
}

bool ProjectiveStrands::deepest(const std::vector<PosedPart>& parts, const Eigen::Vector3d& p,
                                PartContact& c) const
{
  // Tables culled by the ball or slab that holds them, with room for the contact margin.
  return deepestPart(parts, p, 2 * Options.contactMargin + 1e-6, c);
}

void ProjectiveStrands::nodeVelocities(Strand& s, const RigidRates& roots) const
{
  // Root to tip. The angle θ_i turns segment i about −e2 of the segment itself, φ_i about
  // −e1 of its parent (from A = Rx(−φ) Ry(π/2 − θ)).
  Eigen::Vector3d omega = roots.angularVelocity;
  s.v[0] = roots.velocityAt(s.P[0]);
  for (std::size_t i = 1; i < s.P.size(); ++i)
  {
    omega -= s.R[i].col(1) * s.qd[i - 1].x() + s.R[i - 1].col(0) * s.qd[i - 1].y();
    s.v[i] = s.v[i - 1] + omega.cross(s.P[i] - s.P[i - 1]);
  }
}

void ProjectiveStrands::forces(Strand& s, const StepFrame& f, ProjectiveStepStats& stats,
                               std::vector<Eigen::Vector2d>* moments) const
{
  const std::size_t k = s.q.size();
  const double m = s.mass, d = s.d, h = f.h;
  const Eigen::Vector3d& gravity = World.gravity;

  nodeVelocities(s, f.rootRates);

  // The root's acceleration: the inertial force −m a in the roots' frame.
  const Eigen::Vector3d accel =
      Options.inertialForce ? f.rootRates.accelerationAt(s.P[0]) : Eigen::Vector3d::Zero().eval();

  // Air drag at each segment's centre. A gust reaches a strand all at once: its phase is
  // taken at the root (the gust wavelength U·T is longer than a strand).
  const Eigen::Vector3d air =
      f.stillAir ? Eigen::Vector3d::Zero().eval() : World.air.velocity(s.P[0], f.t0);
  const ProjectiveParameters& par = s.material;
  const double dragCoefficient =
      0.5 * par.airDensity * par.dragCoefficient * par.dragDiameter * d; // segmentDrag's
  auto drag = [&](std::size_t i) -> Eigen::Vector3d
  {
    const Eigen::Vector3d t = s.R[i].col(2);
    Eigen::Vector3d w = air - 0.5 * (s.v[i - 1] + s.v[i]);
    w -= w.dot(t) * t;
    return (dragCoefficient * w.norm()) * w;
  };

  // Tip-to-root: sums of the forces on all that joint i carries and their moments about
  // P_{i−1}, then the update of joint i (each joint's update only needs its own forces).
  const Eigen::Vector3d p0 = s.P[0];
  double massSum = 0;
  Eigen::Vector3d massMoment = Eigen::Vector3d::Zero();
  Eigen::Vector3d sw = Eigen::Vector3d::Zero(), mw = Eigen::Vector3d::Zero();
  Eigen::Vector3d sc = Eigen::Vector3d::Zero(), mc = Eigen::Vector3d::Zero();
  Eigen::Vector3d sd = Eigen::Vector3d::Zero(), md = Eigen::Vector3d::Zero(); // the dampers'
  const Eigen::Vector3d fieldPerMass = gravity - accel;
  Eigen::Vector3d windNext = Eigen::Vector3d::Zero(); // drag on segment i + 1
  bool anyContact = false;
  for (std::size_t i = k; i >= 1; --i)
  {
    const Eigen::Vector3d c = 0.5 * (s.P[i - 1] + s.P[i]) - p0;
    const Eigen::Vector3d fw = dragCoefficient > 0 ? drag(i) : Eigen::Vector3d::Zero();
    massSum += m;
    massMoment += m * c;
    sw += fw;
    mw += c.cross(fw);

    // The reaction constraint at node i (the end of segment i).
    const PartContact& ct = s.contact[i];
    if (ct.part >= 0 && ct.depth > -contactBand())
    {
      ++stats.contacts;
      anyContact = true;
      const double mn = i < k ? m : 0.5 * m;
      const Eigen::Vector3d windNode = 0.5 * (fw + windNext);
      const Eigen::Vector3d fin = fieldPerMass + windNode / mn;
      const Eigen::Vector3d vs = f.parts0[ct.part].velocityAt(s.P[i]);
      const Eigen::Vector3d target = s.P[i] + (ct.depth + Options.contactMargin) * ct.normal;
      // The explicit step holds the constraint only while h²k A < 1 and h c A < 1, A the
      // node's mobility: stiffness and damping are capped there (half of it).
      ReactionConstraintOptions opt = Options.contact;
      const double a = std::max(s.mobility[i], 1e-12);
      opt.stiffness = std::min(opt.stiffness, 0.5 / (h * h * a));
      opt.damping = std::min(Options.contact.criticalDamping(), 0.5 / (h * a));
      Eigen::Vector3d damper;
      const Eigen::Vector3d fout =
          reactionConstraint(fin, s.v[i] - vs, s.P[i], target, ct.normal, opt, &damper);
      const Eigen::Vector3d g = mn * (fout - fin);
      if (!s.load.empty())
      {
        s.load[i] = std::max(0.0, g.dot(ct.normal)); // the normal force, for friction
      }
      sc += g;
      mc += (s.P[i] - p0).cross(g);
      sd += mn * damper;
      md += (s.P[i] - p0).cross(mn * damper);
    }
    windNext = fw;

    const Eigen::Vector3d pivot = s.P[i - 1] - p0;
    const Eigen::Vector3d lever = massMoment - massSum * pivot; // Σ m (c − P_{i−1})
    const Eigen::Vector3d wt = -s.R[i].col(1), wp = -s.R[i - 1].col(0);
    const Eigen::Vector3d tg = lever.cross(gravity);
    const Eigen::Vector3d tb = lever.cross(-accel);
    const Eigen::Vector3d tw = mw - pivot.cross(sw);
    const Eigen::Vector2d qg(wt.dot(tg), wp.dot(tg));
    const Eigen::Vector2d qb(wt.dot(tb), wp.dot(tb));
    const Eigen::Vector2d qw(wt.dot(tw), wp.dot(tw));
    Eigen::Vector2d qc = Eigen::Vector2d::Zero(), qcd = Eigen::Vector2d::Zero();
    if (anyContact)
    {
      const Eigen::Vector3d tc = mc - pivot.cross(sc), td = md - pivot.cross(sd);
      qc = Eigen::Vector2d(wt.dot(tc), wp.dot(tc));
      qcd = Eigen::Vector2d(wt.dot(td), wp.dot(td));
    }

    // Symplectic Euler, damping implicit: I (q̇⁺ − q̇)/h = Q − γ q̇⁺ ; q⁺ = q + h q̇⁺.
    const std::size_t j = i - 1;
    if (moments)
    {
      (*moments)[j] = qg + qb + qw + qc;
      continue;
    }
    const Eigen::Vector2d total = qg - s.kappa * (s.q[j] - s.q0[j]) + qb + qw + qc;
    const Eigen::Vector2d qd = (s.qd[j] + s.gain[j] * total) * s.damper[j];
    s.dissipated += h * s.damping[j] * qd.squaredNorm();
    s.bodyWork += h * qb.dot(qd);
    s.windWork += h * qw.dot(qd);
    // The constraint's share, less what its damper takes (reported as dissipated). Its work
    // is booked on the mean of the rates before and after the step, (q̇ + q̇⁺)/2: the
    // constraint stops a node within a few steps, so the rates jump by O(1) in a step, and
    // booked on q̇⁺ alone (as the smooth forces are) each contact event's work would be off
    // by a fixed share of its energy that does not fall with h (docs/projective-strands.md,
    // "Energy report").
    if (anyContact)
    {
      const Eigen::Vector2d mean = 0.5 * (s.qd[j] + qd);
      s.contactWork += h * (qc - qcd).dot(mean);
      s.constraintDissipated -= h * qcd.dot(mean);
    }
    s.qd[j] = qd;
    s.q[j] += h * qd;
  }

  // Gravitational work of carrying the strand from the roots' pose at t0 to that at t0 + h
  // with its angles held: part of the body's work.
  const Eigen::Matrix3d turn = f.root1.linear() * f.root0.linear().transpose();
  const Eigen::Vector3d r1 = f.root1 * s.rootRest;
  s.bodyWork -=
      gravity.dot(massSum * (r1 - p0) + (turn - Eigen::Matrix3d::Identity()) * massMoment);
}

double ProjectiveStrands::gravitational(const Strand& s) const
{
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t i = 1; i < s.P.size(); ++i)
  {
    sum += 0.5 * (s.P[i - 1] + s.P[i]);
  }
  return -s.mass * World.gravity.dot(sum);
}

double ProjectiveStrands::strandEnergy(const Strand& s) const
{
  double e = gravitational(s);
  for (std::size_t i = 0; i < s.q.size(); ++i)
  {
    e += 0.5 * s.inertia[i] * s.qd[i].squaredNorm() +
         0.5 * s.kappa * (s.q[i] - s.q0[i]).squaredNorm();
  }
  return e;
}

double ProjectiveStrands::unprojectedEnergy(const Strand& s, const Eigen::Vector3d& root,
                                            const Eigen::Matrix3d& rootFrame) const
{
  Eigen::Matrix3d r = rootFrame;
  Eigen::Vector3d p = root, sum = Eigen::Vector3d::Zero();
  double e = 0;
  for (std::size_t i = 0; i < s.q.size(); ++i)
  {
    r = r * segmentRotation(s.q[i].x(), s.q[i].y());
    const Eigen::Vector3d next = p + s.d * r.col(2);
    sum += 0.5 * (p + next);
    p = next;
    e += 0.5 * s.inertia[i] * s.qd[i].squaredNorm() +
         0.5 * s.kappa * (s.q[i] - s.q0[i]).squaredNorm();
  }
  return e - s.mass * World.gravity.dot(sum);
}

void ProjectiveStrands::stepStrand(Strand& s, const StepFrame& f, ProjectiveStepStats& stats) const
{
  s.nodeV = s.P; // the nodes at t0, for their velocities over the step
  if (frictionOn())
  {
    std::fill(s.load.begin(), s.load.end(), 0.0);
  }
  forces(s, f, stats);
  if (frictionOn())
  {
    friction(s, f, stats);
  }
  place(s, f, stats);
  for (std::size_t i = 0; i < s.P.size(); ++i)
  {
    s.nodeV[i] = (s.P[i] - s.nodeV[i]) / f.h;
  }
}

Status ProjectiveStrands::initialize(std::vector<ProjectiveStrand> strands, hair::Scene scene,
                                     const ProjectiveOptions& options)
{
  if (strands.empty())
  {
    return Status::Error("projective strands: no strands; give at least one guide strand");
  }
  if (Status st = options.validate(); !st)
  {
    return Status::Error("projective strands: " + st.message());
  }
  for (std::size_t s = 0; s < strands.size(); ++s)
  {
    const ProjectiveStrand& st = strands[s];
    const std::string name = "projective strands: strand " + std::to_string(s);
    if (st.restAngles.empty())
    {
      return Status::Error(name + " has zero segments; give at least one rest angle pair");
    }
    if (!finite(st.segmentLength) || !(st.segmentLength > 0))
    {
      return Status::Error(name + ": the segment length must be a number > 0 m");
    }
    if (!st.root.allFinite() || !st.rootFrame.allFinite())
    {
      return Status::Error(name + ": the root or its frame holds NaN or infinite entries");
    }
    if (!(st.rootFrame.transpose() * st.rootFrame).isIdentity(1e-9) ||
        st.rootFrame.determinant() < 0)
    {
      return Status::Error(name + ": the root frame is not a rotation (orthonormal, "
                                  "right-handed)");
    }
    for (const auto& a : st.restAngles)
    {
      if (!a.allFinite())
      {
        return Status::Error(name + ": a rest angle is NaN or infinite");
      }
    }
    if (!st.angles.empty() && st.angles.size() != st.restAngles.size())
    {
      return Status::Error(name + ": it has " + std::to_string(st.angles.size()) +
                           " starting angles for " + std::to_string(st.restAngles.size()) +
                           " segments; give one pair per segment, or none");
    }
    for (const auto& a : st.angles)
    {
      if (!a.allFinite())
      {
        return Status::Error(name + ": a starting angle is NaN or infinite");
      }
    }
    if (Status m = st.parameters.validate(); !m)
    {
      return Status::Error(name + ": " + m.message());
    }
  }
  if (Status st = scene.validate(); !st)
  {
    return Status::Error("projective strands: " + st.message());
  }

  World = std::move(scene);
  Options = options;
  Strands.clear();
  Strands.resize(strands.size());
  for (std::size_t n = 0; n < strands.size(); ++n)
  {
    Strand& s = Strands[n];
    const ProjectiveStrand& in = strands[n];
    const ProjectiveParameters& par = in.parameters;
    const std::size_t k = in.restAngles.size();
    s.material = par;
    s.d = in.segmentLength;
    s.mass = par.linearDensity * s.d;
    s.kappa = par.bendingStiffness / s.d;
    s.rootRest = in.root;
    s.frameRest = in.rootFrame;
    s.q0 = in.restAngles;
    s.q = in.angles.empty() ? in.restAngles : in.angles;
    s.qd.assign(k, Eigen::Vector2d::Zero());
    s.inertia.resize(k);
    s.damping.resize(k);
    s.gain.resize(k);
    s.damper.resize(k);
    for (std::size_t i = 0; i < k; ++i)
    {
      const double carried = static_cast<double>(k - i) * s.d;
      s.inertia[i] = par.linearDensity * carried * carried * carried / 3.0;
      s.damping[i] = par.dampingRate * s.inertia[i] + par.stiffnessDamping * s.kappa;
      s.gain[i] = Options.timeStep / s.inertia[i];
      s.damper[i] = 1.0 / (1.0 + s.gain[i] * s.damping[i]);
    }
    s.mobility.assign(k + 1, 0);
    for (std::size_t j = 1; j <= k; ++j)
    {
      double sum = 0;
      for (std::size_t l = 1; l <= k; ++l)
      {
        const double ml = l < k ? s.mass : 0.5 * s.mass;
        for (std::size_t i = 1; i <= std::min(j, l); ++i)
        {
          sum += ml * static_cast<double>(j - i + 1) * static_cast<double>(l - i + 1) * s.d * s.d /
                 s.inertia[i - 1];
        }
      }
      s.mobility[j] = sum;
    }
    s.P.resize(k + 1);
    s.R.resize(k + 1);
    s.contact.assign(k + 1, PartContact());
    s.nodeV.assign(k + 1, Eigen::Vector3d::Zero());
    if (frictionOn())
    {
      s.anchors.assign(k + 1, Strand::Anchor());
      s.load.assign(k + 1, 0.0);
    }
    s.v.resize(k + 1);
  }
  Time = 0;
  Steps = 0;
  StepSeconds = 0;
  std::vector<PosedPart> parts;
  World.posedParts(0, parts);
  const Eigen::Isometry3d root0 = World.rootMotion.pose(0);
  for (Strand& s : Strands)
  {
    forward(s, root0 * s.rootRest, root0.linear() * s.frameRest);
    for (std::size_t i = 1; i < s.P.size(); ++i)
    {
      deepest(parts, s.P[i], s.contact[i]);
    }
  }
  InitialEnergy = 0;
  InitialEnergy = energy().total();
  return Status::Ok();
}

Status ProjectiveStrands::setState(int s, const std::vector<Eigen::Vector2d>& angles,
                                   const std::vector<Eigen::Vector2d>& rates)
{
  if (s < 0 || s >= numberOfStrands())
  {
    return Status::Error("projective strands: no strand " + std::to_string(s));
  }
  Strand& st = Strands[s];
  if (angles.size() != st.q.size() || rates.size() != st.q.size())
  {
    return Status::Error("projective strands: strand " + std::to_string(s) + " has " +
                         std::to_string(st.q.size()) + " segments; give as many angles and rates");
  }
  for (std::size_t i = 0; i < angles.size(); ++i)
  {
    if (!angles[i].allFinite() || !rates[i].allFinite())
    {
      return Status::Error("projective strands: NaN or infinite angle or rate");
    }
  }
  st.q = angles;
  st.qd = rates;
  std::fill(st.anchors.begin(), st.anchors.end(), Strand::Anchor()); // touches anew
  const Eigen::Isometry3d root = World.rootMotion.pose(Time);
  forward(st, root * st.rootRest, root.linear() * st.frameRest);
  std::vector<PosedPart> parts;
  World.posedParts(Time, parts);
  for (std::size_t i = 1; i < st.P.size(); ++i)
  {
    deepest(parts, st.P[i], st.contact[i]);
  }
  for (Strand& other : Strands)
  {
    other.dissipated = other.bodyWork = other.windWork = other.contactWork = other.projectionWork =
        other.constraintDissipated = other.inelasticDissipated = other.frictionDissipated = 0;
  }
  InitialEnergy = 0;
  InitialEnergy = energy().total();
  return Status::Ok();
}

Status ProjectiveStrands::setRestAngles(int s, const std::vector<Eigen::Vector2d>& restAngles)
{
  if (s < 0 || s >= numberOfStrands())
  {
    return Status::Error("projective strands: no strand " + std::to_string(s));
  }
  Strand& st = Strands[s];
  if (restAngles.size() != st.q0.size())
  {
    return Status::Error("projective strands: strand " + std::to_string(s) + " has " +
                         std::to_string(st.q0.size()) + " segments; give as many rest angles");
  }
  for (const Eigen::Vector2d& a : restAngles)
  {
    if (!a.allFinite())
    {
      return Status::Error("projective strands: NaN or infinite rest angle");
    }
  }
  st.q0 = restAngles;
  for (Strand& other : Strands)
  {
    other.dissipated = other.bodyWork = other.windWork = other.contactWork = other.projectionWork =
        other.constraintDissipated = other.inelasticDissipated = other.frictionDissipated = 0;
  }
  InitialEnergy = 0;
  InitialEnergy = energy().total();
  return Status::Ok();
}

void ProjectiveStrands::restMoments(int s, std::vector<Eigen::Vector2d>& moments) const
{
  Strand copy = Strands[s];
  std::fill(copy.qd.begin(), copy.qd.end(), Eigen::Vector2d::Zero());
  StepFrame f;
  f.t0 = Time;
  f.h = Options.timeStep;
  World.posedParts(Time, f.parts0);
  for (PosedPart& p : f.parts0)
  {
    p.velocity.setZero();
    p.angularVelocity.setZero();
  }
  f.root0 = f.root1 = World.rootMotion.pose(Time);
  f.rootRates = RigidRates();
  f.rootRates.reference = copy.P[0];
  f.stillAir = true;
  ProjectiveStepStats stats;
  moments.assign(copy.q.size(), Eigen::Vector2d::Zero());
  forces(copy, f, stats, &moments);
}

Status ProjectiveStrands::step(ProjectiveStepStats* statsOut)
{
  if (Strands.empty())
  {
    return Status::Error("projective strands: not initialized");
  }
  const auto start = std::chrono::steady_clock::now();
  const double h = Options.timeStep;
  StepFrame f;
  f.t0 = Time;
  f.h = h;
  // The force pass uses the contacts found at the end of the previous step and the parts'
  // velocities at t0; the placement pass looks up the parts at t0 + h.
  World.posedParts(Time, f.parts0);
  World.posedParts(Time + h, f.parts1);
  f.root0 = World.rootMotion.pose(Time);
  f.root1 = World.rootMotion.pose(Time + h);
  f.rootRates = World.rootMotion.rates(Time);

  // Strands in contact cost more than free ones: blocks of 16 strands go to whichever
  // thread is free. Each strand's result does not depend on which thread steps it, and the
  // statistics are merged in block order.
  const std::int64_t block = 16;
  std::vector<ProjectiveStepStats> stats(
      std::max<std::int64_t>(1, blockCount(numberOfStrands(), block)));
  parallelBlocks(numberOfStrands(), block, Options.threads,
                 [&](std::int64_t begin, std::int64_t end)
                 {
                   for (std::int64_t s = begin; s < end; ++s)
                   {
                     stepStrand(Strands[s], f, stats[begin / block]);
                   }
                 });
  const int nthreads = std::max(1, std::min(Options.threads, numberOfStrands()));
  Time += h;
  ++Steps;
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  StepSeconds += seconds;
  if (statsOut)
  {
    ProjectiveStepStats total;
    for (const auto& st : stats)
    {
      total.merge(st);
    }
    total.seconds = seconds;
    total.threads = nthreads;
    *statsOut = total;
  }
  // A NaN angle anywhere reaches the tip node, so the tips tell.
  for (const Strand& s : Strands)
  {
    if (!s.P.back().allFinite())
    {
      return Status::Error(
          "projective strands: the angles became NaN at t = " + std::to_string(Time) +
          " s; reduce the time step or the contact stiffness");
    }
  }
  return Status::Ok();
}

Status ProjectiveStrands::advance(double duration, const Progress& progress)
{
  const long n = std::lround(duration / Options.timeStep);
  for (long i = 0; i < n; ++i)
  {
    if (Status st = step(); !st)
    {
      return st;
    }
    if (progress && !progress(double(i + 1) / double(n)))
    {
      return Status::Error("projective strands: aborted at t = " + std::to_string(Time) + " s");
    }
  }
  return Status::Ok();
}

ProjectiveEnergy ProjectiveStrands::energy() const
{
  ProjectiveEnergy e;
  e.time = Time;
  const double h = Options.timeStep;
  for (const Strand& s : Strands)
  {
    const std::size_t k = s.q.size();
    e.gravitational += gravitational(s);
    double massSum = 0;
    Eigen::Vector3d massMoment = Eigen::Vector3d::Zero();
    for (std::size_t i = k; i >= 1; --i)
    {
      e.kinetic += 0.5 * s.inertia[i - 1] * s.qd[i - 1].squaredNorm();
      e.elastic += 0.5 * s.kappa * (s.q[i - 1] - s.q0[i - 1]).squaredNorm();
      // Shadow term: (h/2) q̇·Q_cons with Q_cons from gravity and springs.
      massSum += s.mass;
      massMoment += s.mass * (0.5 * (s.P[i - 1] + s.P[i]) - s.P[0]);
      const Eigen::Vector3d lever = massMoment - massSum * (s.P[i - 1] - s.P[0]);
      const Eigen::Vector3d tg = lever.cross(World.gravity);
      const Eigen::Vector3d wp = -s.R[i - 1].col(0);
      const Eigen::Vector3d wt = -s.R[i].col(1);
      const Eigen::Vector2d q =
          Eigen::Vector2d(wt.dot(tg), wp.dot(tg)) - s.kappa * (s.q[i - 1] - s.q0[i - 1]);
      e.shadow += 0.5 * h * s.qd[i - 1].dot(q);
    }
    e.dissipated += s.dissipated;
    e.bodyWork += s.bodyWork;
    e.windWork += s.windWork;
    e.contactWork += s.contactWork;
    e.projectionWork += s.projectionWork;
    e.contactDissipated += s.constraintDissipated + s.inelasticDissipated;
    e.inelasticDissipated += s.inelasticDissipated;
    e.frictionDissipated += s.frictionDissipated;
  }
  e.residual = e.total() - InitialEnergy -
               (e.bodyWork + e.windWork + e.contactWork - e.dissipated - e.contactDissipated -
                e.frictionDissipated);
  return e;
}

std::string ProjectiveStrands::summary() const
{
  long segments = 0;
  for (const Strand& s : Strands)
  {
    segments += static_cast<long>(s.q.size());
  }
  char line[256];
  std::snprintf(
      line, sizeof line,
      "projective strands: %d strands, %ld segments, %zu body parts, %ld steps, %.3f ms/step, "
      "%d threads",
      numberOfStrands(), segments, World.parts.size(), Steps,
      Steps ? 1e3 * StepSeconds / Steps : 0.0, Options.threads);
  return line;
}

} // namespace hair

namespace hair
{

namespace
{
// A strand's continuation: each part a count followed by its numbers, so that a layout that
// does not match is refused rather than read askew.
struct Numbers
{
  std::vector<double>& out;
  void add(const double* v, std::size_t n)
  {
    out.push_back(double(n));
    out.insert(out.end(), v, v + n);
  }
  template <class T>
  void vectors(const std::vector<T>& v)
  {
    add(v.empty() ? nullptr : v[0].data(), v.size() * std::size_t(T::SizeAtCompileTime));
  }
};

struct Reader
{
  const std::vector<double>& in;
  std::size_t at = 0;
  bool ok = true;
  /// The next part: `n` numbers expected (any when n is SIZE_MAX); null when it does not fit.
  const double* take(std::size_t n, std::size_t& got)
  {
    if (!ok || at >= in.size() || !(in[at] >= 0 && in[at] <= double(in.size())))
    {
      ok = false;
      return nullptr;
    }
    got = std::size_t(in[at]);
    if ((n != SIZE_MAX && got != n) || at + 1 + got > in.size())
    {
      ok = false;
      return nullptr;
    }
    const double* p = in.data() + at + 1;
    at += 1 + got;
    return p;
  }
  template <class T>
  void vectors(std::vector<T>& v)
  {
    std::size_t got = 0;
    const std::size_t width = std::size_t(T::SizeAtCompileTime);
    if (const double* p = take(v.size() * width, got))
    {
      std::copy(p, p + got, v.empty() ? nullptr : v[0].data());
    }
  }
};
} // namespace

void ProjectiveStrands::saveContinuation(int index, std::vector<double>& out) const
{
  const Strand& s = Strands[index];
  Numbers n{out};
  n.vectors(s.q);
  n.vectors(s.qd);
  n.vectors(s.P);
  n.vectors(s.R);
  n.vectors(s.nodeV);
  std::vector<double> contact;
  for (const PartContact& c : s.contact)
  {
    contact.insert(contact.end(), {double(c.part), c.depth, c.normal.x(), c.normal.y(),
                                   c.normal.z(), c.surface.x(), c.surface.y(), c.surface.z()});
  }
  n.add(contact.data(), contact.size());
  std::vector<double> anchors;
  for (const Strand::Anchor& a : s.anchors)
  {
    anchors.insert(anchors.end(), {double(a.part), a.placed ? 1.0 : 0.0, a.sliding ? 1.0 : 0.0,
                                   a.rest.x(), a.rest.y(), a.rest.z()});
  }
  n.add(anchors.data(), anchors.size());
  n.add(s.load.data(), s.load.size());
  const double works[] = {s.dissipated,          s.bodyWork,          s.windWork,
                          s.contactWork,         s.projectionWork,    s.constraintDissipated,
                          s.inelasticDissipated, s.frictionDissipated};
  n.add(works, std::size(works));
}

std::size_t ProjectiveStrands::continuationSize(int index) const
{
  std::vector<double> v;
  saveContinuation(index, v);
  return v.size();
}

Status ProjectiveStrands::restoreContinuation(int index, const std::vector<double>& values)
{
  Strand& s = Strands[index];
  Strand r = s;
  Reader in{values};
  in.vectors(r.q);
  in.vectors(r.qd);
  in.vectors(r.P);
  in.vectors(r.R);
  in.vectors(r.nodeV);
  std::size_t got = 0;
  if (const double* c = in.take(8 * r.contact.size(), got))
  {
    for (PartContact& p : r.contact)
    {
      p.part = int(c[0]);
      p.depth = c[1];
      p.normal = Eigen::Vector3d(c[2], c[3], c[4]);
      p.surface = Eigen::Vector3d(c[5], c[6], c[7]);
      c += 8;
    }
  }
  if (const double* a = in.take(6 * r.anchors.size(), got))
  {
    for (Strand::Anchor& p : r.anchors)
    {
      p.part = int(a[0]);
      p.placed = a[1] != 0;
      p.sliding = a[2] != 0;
      p.rest = Eigen::Vector3d(a[3], a[4], a[5]);
      a += 6;
    }
  }
  if (const double* l = in.take(r.load.size(), got))
  {
    std::copy(l, l + got, r.load.begin());
  }
  double* works[] = {&r.dissipated,          &r.bodyWork,          &r.windWork,
                     &r.contactWork,         &r.projectionWork,    &r.constraintDissipated,
                     &r.inelasticDissipated, &r.frictionDissipated};
  if (const double* w = in.take(std::size(works), got))
  {
    for (double* x : works)
    {
      *x = *w++;
    }
  }
  if (!in.ok || in.at != values.size() ||
      !std::all_of(values.begin(), values.end(), [](double x) { return std::isfinite(x); }))
  {
    return Status::Error("projective strand " + std::to_string(index) +
                         ": its continuation does not fit a strand of " +
                         std::to_string(s.q.size()) + " segments (" +
                         std::to_string(values.size()) + " numbers) or is not finite.");
  }
  s = std::move(r);
  return Status::Ok();
}

} // namespace hair
