// The helpers several studies share (Tools/studies/Studies.h).
#include "Studies.h"

namespace hair::tools
{

/// The round, straight hair of the Euler–Bernoulli comparisons (smooth preset, no natural
/// curvature); friction and drag are off unless asked for.
HairParameters roundHair(bool dissipation)
{
  HairParameters p = HairParameters::roundStraight();
  if (!dissipation)
  {
    p.internalFriction = 0;
    p.airFriction = 0;
  }
  return p;
}

Status openOutput(const Arguments& args, std::ofstream& out)
{
  if (!args.has("out"))
    return Status::Error("give the output file: out=<path>.");
  out.open(args.text("out"));
  if (!out)
    return Status::Error("cannot write '" + args.text("out") +
                         "': check that its directory exists and is writable.");
  out.precision(17);
  return Status::Ok();
}

Status presetByName(const std::string& name, HairType& type)
{
  const std::map<std::string, HairType> names = {{"smooth", HairType::Smooth},
                                                 {"wavy", HairType::Wavy},
                                                 {"curly", HairType::Curly},
                                                 {"fuzzy", HairType::Fuzzy}};
  const auto it = names.find(name);
  if (it == names.end())
    return Status::Error("preset=" + name + " is not one of smooth, wavy, curly, fuzzy.");
  type = it->second;
  return Status::Ok();
}

void energyRow(std::ostream& out, const SuperHelix& h)
{
  const EnergyReport& e = h.energy();
  const EnergyTerms& t = e.total;
  out << e.time << "," << e.kinetic << "," << e.elastic << "," << e.gravitational << ","
      << t.frictionDissipated << "," << t.airDissipated << "," << t.rootWork << "," << t.windWork
      << "," << t.contactWork << "," << t.loadWork << "," << t.residual << "," << h.lastSubsteps()
      << "\n";
}

/// The time step the study's strands take, by its name (toString).
Status integratorByName(const std::string& name, Integrator& integrator)
{
  for (Integrator i : {Integrator::SemiImplicit, Integrator::Midpoint, Integrator::Bdf2})
    if (name == toString(i))
    {
      integrator = i;
      return Status::Ok();
    }
  return Status::Error("integrator=" + name + " is unknown; give semi-implicit (the paper's " +
                       "step), midpoint or bdf2 (the second-order steps).");
}

/// The root frame of a hanging strand: tangent −y (gravity −y), n1 = +x.
Eigen::Matrix3d hangingFrame()
{
  Eigen::Matrix3d frame;
  frame.col(0) = -Eigen::Vector3d::UnitY();
  frame.col(1) = Eigen::Vector3d::UnitX();
  frame.col(2) = frame.col(0).cross(frame.col(1));
  return frame;
}

/// A strand hanging from a root at the origin carried by `motion`, in its natural shape.
StrandSpec hangingStrand(double length, int n, const HairParameters& hair,
                         const RigidMotion& motion)
{
  StrandSpec spec = StrandSpec::uniform(length, n, hair);
  spec.root = motion.carriedRoot(Eigen::Vector3d::Zero(), hangingFrame());
  return spec;
}

/// The static equilibrium of `spec`'s strand under gravity: the semi-implicit step's fixed
/// point, reached with steps of 1 s (much longer than the strand's periods, so the step is a
/// damped fixed-point iteration; as in the buckling study) until the tip moves by less than
/// 1e-12 m in a step. Returns q.
Status hangAtRest(const StrandSpec& spec, Eigen::VectorXd& q, int& steps)
{
  SuperHelix h;
  if (Status s = h.initialize(spec); !s)
    return s;
  Eigen::Vector3d tip = h.position(h.length());
  for (steps = 1; steps <= 5000; ++steps)
  {
    if (Status s = h.step(1.0); !s)
      return s;
    const Eigen::Vector3d next = h.position(h.length());
    const double change = (next - tip).norm();
    tip = next;
    if (change < 1e-12)
    {
      q = h.q();
      return Status::Ok();
    }
  }
  return Status::Error("the hanging strand did not reach its static equilibrium in 5000 steps "
                       "of 1 s; give a stiffer or shorter strand.");
}

IntegratorRun releasedStrand(Integrator integrator, double air, double seconds, int perFrame,
                             double tolerance, Status& st, int elements)
{
  HairParameters p = HairParameters::preset(HairType::Smooth);
  p.curvatureVariation = 0;
  p.internalFriction = 0;
  p.airFriction = air;
  StrandSpec spec = StrandSpec::uniform(0.3, elements, p);
  spec.integrator = integrator;
  SuperHelix h;
  IntegratorRun r;
  if (st = h.initialize(spec); !st)
    return r;
  const double g0 = h.energy().gravitational;
  const double dt = 1.0 / (30 * perFrame);
  r.tips.push_back(h.position(0.3));
  const auto start = std::chrono::steady_clock::now();
  const long frames = std::lround(seconds * 30);
  for (long f = 0; f < frames; ++f)
  {
    for (int k = 0; k < perFrame; ++k)
    {
      if (st = h.advance(dt, tolerance * dt); !st)
        return r;
      r.steps += h.lastSubsteps();
      r.rejected += h.lastRejected();
      r.firstOrder += h.lastFirstOrder();
    }
    r.tips.push_back(h.position(0.3));
  }
  r.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.residualShare = h.energy().total.residual / (g0 - h.energy().gravitational);
  return r;
}

} // namespace hair::tools
