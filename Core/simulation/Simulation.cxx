#include "simulation/Simulation.h"

#include "common/Parallel.h"
#include "projective/ProjectiveStrands.h"
#include "superhelix/SuperHelix.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace hair
{

namespace
{
constexpr double TwoPi = 6.283185307179586476925286766559;

bool finite(const Eigen::Vector3d& v)
{
  return v.allFinite();
}

/// fn(begin, end) over [0, count) on the simulation's threads, in blocks of `grain`.
template <class Fn>
void parallelRanges(std::size_t count, int threads, const Fn& fn, std::int64_t grain = 16)
{
  parallelBlocks(static_cast<std::int64_t>(count), grain, threads,
                 [&](std::int64_t begin, std::int64_t end)
                 { fn(static_cast<std::size_t>(begin), static_cast<std::size_t>(end)); });
}

/// Orthonormal root frame: n0 along the growth, n1 as close as possible to the scalp normal
/// made perpendicular (any perpendicular when they are parallel), n2 = n0 × n1.
Eigen::Matrix3d rootFrame(const GuideStrand& g)
{
  const Eigen::Vector3d n0 = g.growth.normalized();
  Eigen::Vector3d n1 = g.normal - g.normal.dot(n0) * n0;
  if (n1.norm() < 1e-6)
  {
    n1 = n0.unitOrthogonal();
  }
  n1.normalize();
  Eigen::Matrix3d f;
  f.col(0) = n0;
  f.col(1) = n1;
  f.col(2) = n0.cross(n1);
  return f;
}
} // namespace

Status HeadMotion::validate() const
{
  if (kind == Kind::None)
  {
    return Status::Ok();
  }
  if (!std::isfinite(amplitude) || !std::isfinite(frequency) || frequency <= 0 || !finite(axis) ||
      axis.norm() < 1e-12 || !finite(pivot))
  {
    return Status::Error("the body motion needs a finite amplitude, a frequency > 0 Hz, a "
                         "non-zero axis and a finite pivot.");
  }
  return Status::Ok();
}

Eigen::Isometry3d HeadMotion::pose(double t) const
{
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  const double s = amplitude * std::sin(TwoPi * frequency * t);
  const Eigen::Vector3d a = axis.normalized();
  if (kind == Kind::Shake || kind == Kind::Nod)
  {
    p.linear() = Eigen::AngleAxisd(s, a).toRotationMatrix();
    p.translation() = pivot - p.linear() * pivot;
  }
  else if (kind == Kind::Vertical)
  {
    p.translation() = s * a;
  }
  return p;
}

RootMotion HeadMotion::carriedRoot(const Eigen::Vector3d& root, const Eigen::Matrix3d& frame) const
{
  const HeadMotion motion = *this;
  return [root, frame, motion](double t)
  {
    RootState s;
    const Eigen::Isometry3d pose = motion.pose(t);
    Eigen::Vector3d v0, w, a0, al;
    motion.rates(t, v0, w, a0, al);
    s.position = pose * root;
    s.orientation = pose.linear() * frame;
    s.angularVelocity = w;
    s.angularAcceleration = al;
    s.velocity = v0 + w.cross(s.position);
    s.acceleration = a0 + al.cross(s.position) + w.cross(w.cross(s.position));
    return s;
  };
}

void HeadMotion::rates(double t, Eigen::Vector3d& v0, Eigen::Vector3d& omega, Eigen::Vector3d& a0,
                       Eigen::Vector3d& alpha) const
{
  const double w = TwoPi * frequency;
  const double sd = amplitude * w * std::cos(w * t), sdd = -amplitude * w * w * std::sin(w * t);
  const Eigen::Vector3d a = axis.normalized();
  v0.setZero();
  omega.setZero();
  a0.setZero();
  alpha.setZero();
  if (kind == Kind::Shake || kind == Kind::Nod)
  {
    // Rotation about the line through the pivot: v(x) = ω × (x − pivot) = −ω × pivot + ω × x.
    omega = sd * a;
    alpha = sdd * a;
    v0 = -omega.cross(pivot);
    // a(x) = α × (x − p) + ω × (ω × (x − p)); the x-independent part is what remains at x = 0.
    a0 = -alpha.cross(pivot) - omega.cross(omega.cross(pivot));
  }
  else if (kind == Kind::Vertical)
  {
    v0 = sd * a;
    a0 = sdd * a;
  }
}

Status SimulationOptions::validate() const
{
  if (!(timeStep > 0) || !std::isfinite(timeStep))
  {
    return Status::Error("the time step must be a positive number of seconds (1/30 s is the "
                         "Super-Helix paper's).");
  }
  if (!(frameInterval > 0) || !std::isfinite(frameInterval))
  {
    return Status::Error("the frame rate must be positive.");
  }
  if (!finite(gravity) || !finite(wind))
  {
    return Status::Error("gravity and wind must be finite vectors.");
  }
  // The strands check the same range (StrandSpec::validate); this message names the
  // simulation's option instead of a strand's field.
  if (model == StrandModel::SuperHelix &&
      !(quadratureTolerance >= QuadratureChooser::MinTolerance &&
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
  if (threads < 1)
  {
    return Status::Error("at least one thread is needed.");
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
  return motion.validate();
}

struct Simulation::Impl
{
  SimulationOptions Options;
  std::vector<GuideStrand> Guides;
  std::vector<SimulationPart> Parts;
  std::vector<SuperHelix> Helices;
  std::unique_ptr<ProjectiveStrands> Projective;
  StateHeader Header;
  std::vector<std::string> Extra;
  std::vector<StateFrame> Frames;
  std::vector<long> Contacts;
  std::vector<double> Depth;
  std::vector<std::vector<Eigen::Vector3d>> Previous; // projective: nodes one step before
  Status Failed; ///< set when a step failed: the strands may then be at different times
  BodyContacts Body;
  HairHairContacts HairHair; ///< used when Options.hairHairEnabled
  ContactForces Additional;  ///< the seam for other contacts (setAdditionalContacts)

  /// The parts at time t, as the contact response needs them (pose and rigid velocity).
  void bodiesAt(double t, std::vector<ContactBody>& out) const
  {
    out.resize(Parts.size());
    const Eigen::Isometry3d head = Options.motion.pose(t);
    Eigen::Vector3d v0, w, a0, al;
    Options.motion.rates(t, v0, w, a0, al);
    for (std::size_t k = 0; k < Parts.size(); ++k)
    {
      ContactBody& b = out[k];
      b.table = &Parts[k].part.table;
      const bool moves = Parts[k].movesWithHead;
      b.pose = moves ? head : Eigen::Isometry3d::Identity();
      b.velocity = moves ? v0 : Eigen::Vector3d::Zero();
      b.angularVelocity = moves ? w : Eigen::Vector3d::Zero();
    }
  }
  /// The contact hook of every Super-Helix strand: the body's response, then the seam's.
  void contactResponse(int strand, double t, const std::vector<StrandSample>& samples,
                       std::vector<ContactResponse>& response) const
  {
    if (Options.contacts.enabled && !Parts.empty())
    {
      thread_local std::vector<ContactBody> bodies; // no allocation after the first call
      bodiesAt(t, bodies);
      Body.respond(samples, Helices[strand].spec().hair.linearDensity(), bodies.data(),
                   static_cast<int>(bodies.size()), response);
    }
    if (Options.hairHairEnabled)
    {
      HairHair.addResponses(strand, samples, response); // strand ids are their indices
    }
    if (Additional)
    {
      Additional(strand, t, samples, response);
    }
  }

  double time() const
  {
    return Options.model == StrandModel::SuperHelix ? (Helices.empty() ? 0 : Helices[0].time())
                                                    : Projective->time();
  }
  void posesAt(double t)
  {
    const Eigen::Isometry3d head = Options.motion.pose(t);
    for (SimulationPart& p : Parts)
    {
      p.part.pose = p.movesWithHead ? head : Eigen::Isometry3d::Identity();
    }
  }
  void record();
};

void Simulation::Impl::record()
{
  StateFrame f;
  f.time = time();
  long contacts = 0;
  double deepest = 0;
  posesAt(f.time);
  if (Options.model == StrandModel::SuperHelix)
  {
    // Display points, their velocities, curvature and twist, strand by strand on the
    // simulation's threads into pre-sized arrays (the same values in the same places as one
    // thread would give: each point is computed alone).
    std::vector<std::size_t> first(Helices.size() + 1, 0);
    std::size_t qSize = 0;
    for (std::size_t k = 0; k < Helices.size(); ++k)
    {
      first[k + 1] = first[k] + Helices[k].elementCount() * Options.pointsPerElement + 1;
      qSize += Helices[k].q().size();
    }
    const std::size_t points = first.back();
    f.positions.resize(points);
    f.velocities.resize(points);
    std::vector<double>& curvature = f.pointData["curvature"];
    std::vector<double>& twist = f.pointData["twist"];
    curvature.resize(points);
    twist.resize(points);
    parallelRanges(Helices.size(), Options.threads,
                   [&](std::size_t begin, std::size_t end)
                   {
                     for (std::size_t k = begin; k < end; ++k)
                     {
                       const SuperHelix& h = Helices[k];
                       const int n = h.elementCount() * Options.pointsPerElement;
                       for (int i = 0; i <= n; ++i)
                       {
                         const std::size_t j = first[k] + i;
                         h.positionAndVelocity(h.length() * i / n, f.positions[j], f.velocities[j]);
                         // Curvature |κ| and twist τ of the element the point lies on
                         // (q = (τ, κ1, κ2) per element).
                         const int e = std::min(i / Options.pointsPerElement, h.elementCount() - 1);
                         const Eigen::Vector3d q = h.q().segment<3>(3 * e);
                         curvature[j] = std::hypot(q.y(), q.z());
                         twist[j] = q.x();
                       }
                     }
                   });
    f.q.reserve(qSize);
    f.qdot.reserve(qSize);
    for (const SuperHelix& h : Helices)
    {
      f.q.insert(f.q.end(), h.q().data(), h.q().data() + h.q().size());
      f.qdot.insert(f.qdot.end(), h.qdot().data(), h.qdot().data() + h.qdot().size());
    }
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
    f.energy = {{"kinetic", sum.kinetic},
                {"elastic", sum.elastic},
                {"gravitational", sum.gravitational},
                {"dissipated", sum.total.frictionDissipated + sum.total.airDissipated},
                {"external_work", sum.total.rootWork + sum.total.windWork + sum.total.contactWork +
                                      sum.total.loadWork},
                {"friction_dissipated", sum.total.frictionDissipated},
                {"air_dissipated", sum.total.airDissipated},
                {"root_work", sum.total.rootWork},
                {"wind_work", sum.total.windWork},
                {"contact_work", sum.total.contactWork},
                {"residual", sum.total.residual}};
  }
  else
  {
    const ProjectiveStrands& ps = *Projective;
    const double h = ps.options().timeStep;
    for (int s = 0; s < ps.numberOfStrands(); ++s)
    {
      const auto& nodes = ps.nodes(s);
      for (std::size_t i = 0; i < nodes.size(); ++i)
      {
        f.positions.push_back(nodes[i]);
        f.velocities.push_back(Previous.empty() ? Eigen::Vector3d::Zero().eval()
                                                : Eigen::Vector3d((nodes[i] - Previous[s][i]) / h));
      }
      // Discrete curvature: the turning angle at a node over the segment length; the
      // projective model has no twist.
      for (std::size_t i = 0; i < nodes.size(); ++i)
      {
        double kappa = 0;
        if (i > 0 && i + 1 < nodes.size())
        {
          const Eigen::Vector3d a = (nodes[i] - nodes[i - 1]).normalized();
          const Eigen::Vector3d b = (nodes[i + 1] - nodes[i]).normalized();
          kappa = std::atan2(a.cross(b).norm(), a.dot(b)) / ps.segmentLength(s);
        }
        f.pointData["curvature"].push_back(kappa);
        f.pointData["twist"].push_back(0.0);
      }
      for (std::size_t k = 0; k < ps.angles(s).size(); ++k)
      {
        f.q.push_back(ps.angles(s)[k].x());
        f.q.push_back(ps.angles(s)[k].y());
        f.qdot.push_back(ps.rates(s)[k].x());
        f.qdot.push_back(ps.rates(s)[k].y());
      }
    }
    const ProjectiveEnergy e = ps.energy();
    f.energy = {{"kinetic", e.kinetic},
                {"elastic", e.elastic},
                {"gravitational", e.gravitational},
                {"dissipated", e.dissipated},
                {"external_work", e.bodyWork + e.windWork + e.contactWork},
                {"body_work", e.bodyWork},
                {"wind_work", e.windWork},
                {"contact_work", e.contactWork},
                {"residual", e.residual}};
  }
  // Penetration, measured the same way for both models: nodes inside a part (point by
  // point on the simulation's threads; counts and maximum reduced after).
  std::vector<double>& depthOf = f.pointData["contact_depth"];
  depthOf.assign(f.positions.size(), 0.0);
  std::vector<char> insideAny(f.positions.size(), 0);
  parallelRanges(
      f.positions.size(), Options.threads,
      [&](std::size_t begin, std::size_t end)
      {
        for (std::size_t i = begin; i < end; ++i)
          for (const SimulationPart& p : Parts)
          {
            const TableQuery q = p.part.query(f.positions[i]);
            if (q.inside)
            {
              insideAny[i] = 1;
              depthOf[i] = std::max(depthOf[i], std::max(q.depth, 0.0));
            }
          }
      },
      4096);
  for (std::size_t i = 0; i < f.positions.size(); ++i)
  {
    contacts += insideAny[i];
    deepest = std::max(deepest, depthOf[i]);
  }
  Frames.push_back(std::move(f));
  Contacts.push_back(contacts);
  Depth.push_back(deepest);
}

Simulation::Simulation() : P(std::make_unique<Impl>()) {}
Simulation::~Simulation() = default;

double Simulation::bytesPerFrame() const
{
  if (P->Frames.empty())
  {
    return 0;
  }
  const StateFrame& f = P->Frames.back();
  double bytes = sizeof(StateFrame) +
                 sizeof(Eigen::Vector3d) * double(f.positions.size() + f.velocities.size()) +
                 sizeof(double) * double(f.q.size() + f.qdot.size());
  for (const auto& [name, values] : f.pointData)
  {
    bytes += name.size() + sizeof(double) * double(values.size());
  }
  for (const auto& [name, value] : f.energy)
  {
    bytes += name.size() + sizeof(value);
  }
  return bytes;
}

Status Simulation::checkMemory(int frames, double availableBytes) const
{
  const double perFrame = bytesPerFrame();
  const double need = perFrame * std::max(frames, 0);
  if (need <= availableBytes)
  {
    return Status::Ok();
  }
  auto gib = [](double b)
  {
    char s[32];
    if (b >= 1024.0 * 1024 * 1024)
      std::snprintf(s, sizeof s, "%.1f GiB", b / (1024.0 * 1024 * 1024));
    else
      std::snprintf(s, sizeof s, "%.1f MiB", b / (1024.0 * 1024));
    return std::string(s);
  };
  char per[32];
  std::snprintf(per, sizeof per, "%.2f MiB", perFrame / (1024.0 * 1024));
  return Status::Error("the run's " + std::to_string(frames) +
                       " frames (Duration × Frame Rate + 1) of " +
                       std::to_string(P->Frames.back().positions.size()) + " points would need " +
                       gib(need) + " of memory (" + per +
                       " per frame, all kept in memory), more than the " + gib(availableBytes) +
                       " allowed; shorten Duration, lower Frame Rate or use "
                       "fewer strands or elements.");
}

int Simulation::numberOfFrames() const
{
  return static_cast<int>(P->Frames.size());
}
const StateFrame& Simulation::frame(int index) const
{
  return P->Frames.at(index);
}

void Simulation::releaseFrameData(int index)
{
  if (index < 0 || index + 1 >= numberOfFrames())
  {
    return; // unknown, or the newest frame
  }
  StateFrame& f = P->Frames[index];
  // Swapped with empty containers, so that the memory is returned (clear() keeps capacity).
  std::vector<Eigen::Vector3d>().swap(f.positions);
  std::vector<Eigen::Vector3d>().swap(f.velocities);
  std::vector<double>().swap(f.q);
  std::vector<double>().swap(f.qdot);
  f.pointData.clear();
}

bool Simulation::hasFrameData(int index) const
{
  const StateFrame& f = P->Frames.at(index);
  return !f.positions.empty() || P->Header.numberOfPoints() == 0;
}
const StateHeader& Simulation::header() const
{
  return P->Header;
}
const std::vector<std::string>& Simulation::extraEnergyTerms() const
{
  return P->Extra;
}
const std::vector<long>& Simulation::contacts() const
{
  return P->Contacts;
}
const std::vector<double>& Simulation::maxDepth() const
{
  return P->Depth;
}
void Simulation::setAdditionalContacts(ContactForces hook)
{
  P->Additional = std::move(hook);
  // A running simulation's strands already have their hook; it reads Additional then.
}

Status Simulation::initialize(const std::vector<GuideStrand>& strands,
                              const std::vector<SimulationPart>& parts,
                              const SimulationOptions& options)
{
  auto r = std::make_unique<Impl>();
  if (strands.empty())
  {
    return Status::Error("there are no strands to simulate: connect Hair Strands (or polylines "
                         "with its cell arrays) to the first input.");
  }
  if (Status s = options.validate(); !s)
  {
    return s;
  }
  for (std::size_t k = 0; k < parts.size(); ++k)
  {
    if (parts[k].part.table.empty() || parts[k].part.table.numberOfHits() == 0)
    {
      return Status::Error(
          "body part " + std::to_string(k) + " ('" + parts[k].part.name +
          "') has an empty collision table: rebuild it with Cylindrical Collision Map.");
    }
  }
  for (std::size_t k = 0; k < strands.size(); ++k)
  {
    const GuideStrand& g = strands[k];
    if (!finite(g.root) || !finite(g.growth) || g.growth.norm() < 1e-12 || !finite(g.normal))
    {
      return Status::Error("strand " + std::to_string(k) +
                           " has a NaN root or a zero or NaN growth direction.");
    }
    if (g.elements < 1 || !(g.length > 0))
    {
      return Status::Error("strand " + std::to_string(k) + " has " + std::to_string(g.elements) +
                           " elements and length " + std::to_string(g.length) +
                           ": give at least one element and a positive length.");
    }
    if (g.elements != strands[0].elements)
    {
      return Status::Error("strand " + std::to_string(k) + " has " + std::to_string(g.elements) +
                           " elements, strand 0 has " + std::to_string(strands[0].elements) +
                           ": all strands of a run need the same number.");
    }
    if (Status s = g.hair.validate(); !s)
    {
      return Status::Error("strand " + std::to_string(k) + ": " + s.message());
    }
  }
  r->Options = options;
  r->Options.contacts.lookAhead = options.timeStep;
  r->Guides = strands;
  r->Parts = parts;
  r->Additional = P->Additional;
  if (Status s = r->Body.setParameters(r->Options.contacts); !s)
  {
    return Status::Error("hair–body contacts: " + s.message());
  }
  if (options.hairHairEnabled)
  {
    HairHairParameters hh = options.hairHair;
    hh.threads = std::max(1, options.threads);
    if (Status s = r->HairHair.setParameters(hh); !s)
    {
      return Status::Error("hair–hair contacts: " + s.message());
    }
  }
  const int n = strands[0].elements;

  if (options.model == StrandModel::SuperHelix)
  {
    r->Helices.resize(strands.size());
    for (std::size_t k = 0; k < strands.size(); ++k)
    {
      const GuideStrand& g = strands[k];
      StrandSpec spec = StrandSpec::uniform(g.length, g.elements, g.hair);
      spec.name = "strand " + std::to_string(k);
      spec.id = static_cast<int>(k);
      spec.seed = g.seed + static_cast<std::uint32_t>(k);
      spec.gravity = options.gravity;
      spec.wind = options.wind;
      spec.quadratureTolerance = options.quadratureTolerance;
      spec.root = options.motion.carriedRoot(g.root, rootFrame(g));
      if (Status s = r->Helices[k].initialize(spec, 0.0); !s)
      {
        return s;
      }
      // Impl lives on the heap and owns the strands: the pointer outlives the hook.
      const Impl* impl = r.get();
      r->Helices[k].setContactForces(
          [impl](int strand, double t, const std::vector<StrandSample>& samples,
                 std::vector<ContactResponse>& response)
          { impl->contactResponse(strand, t, samples, response); });
    }
    r->Header.model = "super-helix";
    r->Header.coordinatesPerStrand = 3 * n;
    r->Extra = {"friction_dissipated", "air_dissipated", "root_work",
                "wind_work",           "contact_work",   "residual"};
    for (std::size_t k = 0; k <= strands.size(); ++k)
    {
      r->Header.offsets.push_back(std::int64_t(k) * (n * options.pointsPerElement + 1));
    }
  }
  else
  {
    std::vector<ProjectiveStrand> ps(strands.size());
    for (std::size_t k = 0; k < strands.size(); ++k)
    {
      const GuideStrand& g = strands[k];
      std::vector<Eigen::Vector3d> points;
      for (int i = 0; i <= n; ++i)
      {
        points.push_back(g.root + (g.length * i / n) * g.growth.normalized());
      }
      if (Status s = strandFromPolyline(points, rootFrame(g).col(1), ps[k]); !s)
      {
        return Status::Error("strand " + std::to_string(k) + ": " + s.message());
      }
    }
    ProjectiveScene scene;
    BodyMotion head = BodyMotion::still();
    const HeadMotion& m = options.motion;
    // BodyMotion's oscillations fade in over their first quarter period; enough cycles to
    // last any run.
    const double period = 1 / m.frequency, cycles = 1e6;
    if (m.kind == HeadMotion::Kind::Shake)
    {
      head = BodyMotion::shake(m.pivot, m.axis, m.amplitude, period, 0, cycles);
    }
    else if (m.kind == HeadMotion::Kind::Nod)
    {
      head = BodyMotion::nod(m.pivot, m.axis, m.amplitude, period, 0, cycles);
    }
    else if (m.kind == HeadMotion::Kind::Vertical)
    {
      head = BodyMotion::verticalOscillation(m.axis, m.amplitude, period, 0, cycles);
    }
    for (const SimulationPart& p : parts)
    {
      scene.parts.push_back(p.part);
      scene.motions.push_back(p.movesWithHead ? head : BodyMotion::still());
    }
    scene.rootMotion = head;
    scene.wind.speed = options.wind.norm();
    scene.wind.direction = scene.wind.speed > 0 ? Eigen::Vector3d(options.wind / scene.wind.speed)
                                                : Eigen::Vector3d::UnitZ();
    ProjectiveOptions po;
    // The explicit scheme steps at most 1 ms, in whole steps per frame so that frames fall
    // on their times.
    po.timeStep = options.frameInterval /
                  std::ceil(options.frameInterval / std::min(options.timeStep, 1e-3) - 1e-9);
    po.gravity = options.gravity;
    po.threads = options.threads;
    const HairParameters& hp = strands[0].hair;
    po.parameters.linearDensity = hp.linearDensity();
    po.parameters.bendingStiffness = 0.5 * (hp.stiffness()[1] + hp.stiffness()[2]);
    po.parameters.dragDiameter = 2 * hp.radius;
    r->Projective = std::make_unique<ProjectiveStrands>();
    if (Status s = r->Projective->initialize(std::move(ps), std::move(scene), po); !s)
    {
      return s;
    }
    r->Header.model = "projective";
    r->Header.coordinatesPerStrand = 2 * n;
    r->Extra = {"body_work", "wind_work", "contact_work", "residual"};
    for (std::size_t k = 0; k <= strands.size(); ++k)
    {
      r->Header.offsets.push_back(std::int64_t(k) * (n + 1));
    }
  }
  auto& sp = r->Header.strandParameters;
  for (const GuideStrand& g : strands)
  {
    sp["length"].push_back(g.length);
    sp["elements"].push_back(g.elements);
    sp["radius"].push_back(g.hair.radius);
    sp["ellipticity"].push_back(g.hair.ellipticity);
    sp["young_modulus"].push_back(g.hair.youngModulus);
    sp["poisson_ratio"].push_back(g.hair.poissonRatio);
    sp["density"].push_back(g.hair.density);
    sp["helix_radius"].push_back(g.hair.helixRadius);
    sp["helix_step"].push_back(g.hair.helixStep);
    sp["internal_friction"].push_back(g.hair.internalFriction);
    sp["air_friction"].push_back(g.hair.airFriction);
  }
  r->Header.pointData = {"curvature", "twist", "contact_depth"};
  auto& at = r->Header.attributes;
  at["time_step"] = options.timeStep;
  at["frame_interval"] = options.frameInterval;
  for (int c = 0; c < 3; ++c)
  {
    at[std::string("gravity_") + "xyz"[c]] = options.gravity[c];
    at[std::string("wind_") + "xyz"[c]] = options.wind[c];
  }
  at["motion_kind"] = static_cast<int>(options.motion.kind);
  at["motion_amplitude"] = options.motion.amplitude;
  at["motion_frequency"] = options.motion.frequency;
  if (options.model == StrandModel::SuperHelix)
  {
    at["quadrature_tolerance"] = options.quadratureTolerance;
    const BodyContactParameters& c = options.contacts;
    at["contacts"] = c.enabled ? 1 : 0;
    at["contact_stiffness"] = c.stiffness;
    at["contact_damping_ratio"] = c.dampingRatio;
    at["friction_coefficient"] = c.friction;
    at["friction_anisotropy"] = c.anisotropy;
    at["contact_thickness"] = c.thickness;
    at["slip_velocity"] = c.slipVelocity;
    at["hair_hair_contacts"] = options.hairHairEnabled ? 1 : 0;
    if (options.hairHairEnabled)
    {
      const HairHairParameters& h = options.hairHair;
      at["hair_hair_thickness"] = h.thickness;
      at["hair_hair_stiffness"] = h.stiffness;
      at["hair_hair_damping"] = h.damping;
      at["hair_hair_friction"] = h.friction;
      at["hair_hair_per_length"] = h.perLength ? 1 : 0;
      at["hair_hair_reference_length"] = h.referenceLength;
      at["hair_hair_max_updates"] = options.hairHairMaxUpdates;
    }
  }
  r->record();
  P = std::move(r);
  return Status::Ok();
}

Status Simulation::advanceTo(int frames, const Progress& progress)
{
  if (P->Frames.empty())
  {
    return Status::Error("the simulation is not initialized.");
  }
  if (!P->Failed)
  {
    return P->Failed; // a failed step leaves strands at different times: stay stopped
  }
  const int first = numberOfFrames();
  for (int f = first; f < frames; ++f)
  {
    const double target = f * P->Options.frameInterval;
    if (P->Options.model == StrandModel::SuperHelix)
    {
      const int steps = std::max(
          1, static_cast<int>(std::ceil(P->Options.frameInterval / P->Options.timeStep - 1e-9)));
      const double dt = (target - P->time()) / steps;
      for (int i = 0; i < steps; ++i)
      {
        // Hair–hair: a search before each step; when pairs close fast, the step is cut
        // into pieces that each start with a new search (HairHairContacts::updatesPerStep).
        int pieces = 1;
        if (P->Options.hairHairEnabled)
        {
          if (Status s = findHairHairContacts(P->Helices, P->HairHair); !s)
          {
            P->Failed = Status::Error("hair–hair contacts at t = " + std::to_string(P->time()) +
                                      " s: " + s.message());
            return P->Failed;
          }
          pieces = P->HairHair.updatesPerStep(dt, P->Options.hairHairMaxUpdates);
        }
        for (int k = 0; k < pieces; ++k)
        {
          if (k > 0)
          {
            if (Status s = findHairHairContacts(P->Helices, P->HairHair); !s)
            {
              P->Failed = Status::Error("hair–hair contacts at t = " + std::to_string(P->time()) +
                                        " s: " + s.message());
              return P->Failed;
            }
          }
          if (Status s = stepStrands(P->Helices, dt / pieces, P->Options.threads); !s)
          {
            P->Failed = s;
            return s;
          }
        }
      }
    }
    else
    {
      ProjectiveStrands& ps = *P->Projective;
      const double h = ps.options().timeStep;
      const int steps = std::max(1, static_cast<int>(std::lround((target - ps.time()) / h)));
      for (int i = 0; i < steps; ++i)
      {
        if (i == steps - 1)
        {
          P->Previous.resize(ps.numberOfStrands());
          for (int s = 0; s < ps.numberOfStrands(); ++s)
          {
            P->Previous[s] = ps.nodes(s);
          }
        }
        if (Status s = ps.step(); !s)
        {
          P->Failed = s;
          return s;
        }
      }
    }
    P->record();
    if (progress && !progress(double(f - first + 1) / (frames - first)))
    {
      return Status::Error("the simulation was aborted at t = " + std::to_string(P->time()) +
                           " s; the frames computed so far are kept.");
    }
  }
  return Status::Ok();
}

} // namespace hair
