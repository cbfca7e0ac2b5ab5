// hair_study: the numerics of the ready-made studies of issue 6, run from Core through its
// public API and written as CSV (or as a state file), for Scripts/study_*.py to plot.
//
//   hair_study convergence out=<csv> [ns=1,2,...] [length=0.1]
//   hair_study buckling    out=<csv> [n=10] [loads=0.1,...] [tilt=1e-3] [length=0.1] [dt=100]
//                          [maxsteps=20000] [tol=1e-13]
//   hair_study release     out=<csv> [n=10] [dt=1/30] [duration=2] [length=0.3] [preset=wavy]
//   hair_study scene       out=<h5>  [strands=6] [n=10] [duration=1] [dt=1/30]
//                          [model=super-helix|projective]
//   hair_study integrator  out=<csv> [quick=0|1] [demo=0|1] [guides=200] [seconds=5]
//   hair_study clump       out=<csv> [quick=0|1] [strands=50] [duration=6] [ramp=3]
//                          [updates=1] [gammas=5e-11,1e-10,2e-10,5e-10] [thickness=1.2e-3]
//                          [contacts=1] [amplitude=0.01] [frequency=3]
//   hair_study demo        out=<h5>  [model=projective|super-helix] [strands=200] [n=40|10]
//                          [duration=5] [dt=1/30] [threads=2] [data=<Data dir>]
//   hair_study oscillation out=<csv> [summary=<csv>] [shapes=<csv>] [preset=curly]
//                          [length=0.3] [n=40] [gammas=5e-11,1e-10,5e-10] [frequencies=3]
//                          [amplitude=0.01] [nu=<preset's>] [duration=8] [fade=1] [window=2]
//                          [dt=1/2000] [rate=200] [integrator=semi-implicit]
//   hair_study pendulum    out=<csv> [presets=smooth,fuzzy] [nus=0,5e-6,1e-5,2e-5,5e-5]
//                          [length=0.3] [n=10] [duration=8] [dt=1/2000] [push=0.02]
//                          [frequency=1] [rate=200] [integrator=semi-implicit]
//   hair_study hairhair    out=<csv> [scene=demo|clump] [contacts=1] [body=1] [guides=200]
//                          [threads=2] [duration=5|6] [thickness=0|1.2e-3] [stiffness=1]
//                          [friction=0.3] [margin=0.25] [iterations=10]
//
// Every study is described in docs/study-*.md. Bad input: a message on stderr naming the
// argument and what to do, exit status 2; a failed computation: exit status 1.
#include "AnalyticBodies.h"
#include "ClumpScene.h"
#include "DemoScene.h"
#include "analysis/StrandAnalysis.h"
#include "contact/BodyContacts.h"
#include "contact/HairHairContacts.h"
#include "contact/PassThrough.h"
#include "io/StateFile.h"
#include "simulation/Simulation.h"
#include "strands/BundledBody.h"
#include "superhelix/SuperHelix.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

using namespace hair;

namespace
{

constexpr double Beta1L = 1.8751041, Beta2L = 4.6940911; // clamped–free beam (Rao §11.5)

/// key=value arguments, each key allowed once and known to the study.
class Arguments
{
public:
  Status parse(int argc, char** argv, const std::set<std::string>& known)
  {
    for (int i = 2; i < argc; ++i)
    {
      const std::string a = argv[i];
      const auto eq = a.find('=');
      if (eq == std::string::npos || eq == 0)
        return Status::Error("argument '" + a + "' is not of the form key=value.");
      const std::string key = a.substr(0, eq);
      if (!known.count(key))
      {
        std::string list;
        for (const std::string& k : known)
          list += (list.empty() ? "" : ", ") + k;
        return Status::Error("unknown argument '" + key + "' (this study takes " + list + ").");
      }
      if (Values.count(key))
        return Status::Error("argument '" + key + "' is given twice.");
      Values[key] = a.substr(eq + 1);
    }
    return Status::Ok();
  }

  bool has(const std::string& key) const { return Values.count(key) > 0; }
  std::string text(const std::string& key, const std::string& fallback) const
  {
    const auto it = Values.find(key);
    return it == Values.end() ? fallback : it->second;
  }

  /// A number; "a/b" is accepted (dt=1/30). Must be finite and within [lo, hi].
  Status number(const std::string& key, double fallback, double lo, double hi, double& out) const
  {
    if (!has(key))
    {
      out = fallback;
      return Status::Ok();
    }
    if (!toNumber(Values.at(key), out) || !(out >= lo && out <= hi))
    {
      std::ostringstream s;
      s << "argument " << key << "=" << Values.at(key) << " must be a number in [" << lo << ", "
        << hi << "].";
      return Status::Error(s.str());
    }
    return Status::Ok();
  }

  Status integer(const std::string& key, int fallback, int lo, int hi, int& out) const
  {
    double v = 0;
    if (Status s = number(key, fallback, lo, hi, v); !s)
      return s;
    if (v != std::floor(v))
      return Status::Error("argument " + key + "=" + Values.at(key) + " must be a whole number.");
    out = static_cast<int>(v);
    return Status::Ok();
  }

  /// A comma-separated list of numbers within [lo, hi].
  Status list(const std::string& key, const std::vector<double>& fallback, double lo, double hi,
              std::vector<double>& out) const
  {
    if (!has(key))
    {
      out = fallback;
      return Status::Ok();
    }
    out.clear();
    std::stringstream ss(Values.at(key));
    std::string item;
    while (std::getline(ss, item, ','))
    {
      double v = 0;
      if (!toNumber(item, v) || !(v >= lo && v <= hi))
      {
        std::ostringstream s;
        s << "argument " << key << ": '" << item << "' is not a number in [" << lo << ", " << hi
          << "].";
        return Status::Error(s.str());
      }
      out.push_back(v);
    }
    if (out.empty())
      return Status::Error("argument " + key + " is an empty list.");
    return Status::Ok();
  }

private:
  static bool toNumber(const std::string& t, double& v)
  {
    const auto slash = t.find('/');
    if (slash != std::string::npos)
    {
      double a = 0, b = 0;
      if (!toNumber(t.substr(0, slash), a) || !toNumber(t.substr(slash + 1), b) || b == 0)
        return false;
      v = a / b;
      return std::isfinite(v);
    }
    try
    {
      std::size_t used = 0;
      v = std::stod(t, &used);
      return used == t.size() && std::isfinite(v);
    }
    catch (const std::exception&)
    {
      return false;
    }
  }
  std::map<std::string, std::string> Values;
};

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
  out.open(args.text("out", ""));
  if (!out)
    return Status::Error("cannot write '" + args.text("out", "") +
                         "': check that its directory exists and is writable.");
  out.precision(17);
  return Status::Ok();
}

// ---------------------------------------------------------------------------------------
// Study 1: a straight clamped cantilever against Euler–Bernoulli as N grows.

/// Bending frequencies of the linearization about the straight clamped rod: M(0) ẍ + 𝕂 x = 0
/// restricted to κ1 (which decouples from τ and κ2 there), solved as M x = λ 𝕂 x, ω² = 1/λ.
/// Ascending; fewer than two when N < 2.
Status bendingFrequencies(double length, int n, std::vector<double>& f)
{
  StrandSpec spec = StrandSpec::uniform(length, n, roundHair(false));
  spec.gravity.setZero();
  SuperHelix h;
  if (Status s = h.initialize(spec); !s)
    return s;
  h.reconstruct();
  h.assemble();
  Eigen::MatrixXd mb(n, n), kb = Eigen::MatrixXd::Zero(n, n);
  for (int a = 0; a < n; ++a)
  {
    for (int b = 0; b < n; ++b)
      mb(a, b) = h.massMatrix()(3 * a + 1, 3 * b + 1);
    kb(a, a) = h.stiffnessDiagonal()[3 * a + 1];
  }
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(mb, kb);
  if (es.info() != Eigen::Success)
    return Status::Error("N = " + std::to_string(n) + ": the generalized eigenproblem failed.");
  f.clear();
  for (int i = n - 1; i >= 0; --i)
    f.push_back(1.0 / std::sqrt(es.eigenvalues()[i]) / (2 * M_PI));
  return Status::Ok();
}

/// Static tip deflection under gravity of the horizontal cantilever (tangent +x, gravity −y),
/// with E raised so that δ/L = 1e-3 (linear regime: the nonlinearity is O((δ/L)²) = 1e-6).
/// The semi-implicit step's fixed point (q̇ = 0) is the static equilibrium: steps of 1 s,
/// much longer than the rod's period, damp the motion numerically and reach it.
Status staticDeflection(double length, int n, double& delta, double& expected, int& steps,
                        double& velocity)
{
  HairParameters p = roundHair(false);
  const double g = 9.81, ratio = 1e-3;
  const double inertia = p.stiffness()[2] / p.youngModulus; // I [m⁴]
  p.youngModulus = p.linearDensity() * g * std::pow(length, 3) / (8 * ratio * inertia);
  expected = p.linearDensity() * g * std::pow(length, 4) / (8 * p.stiffness()[2]);
  StrandSpec spec = StrandSpec::uniform(length, n, p);
  spec.gravity = Eigen::Vector3d(0, -g, 0);
  SuperHelix h;
  if (Status s = h.initialize(spec); !s)
    return s;
  for (steps = 0; steps < 500; ++steps)
  {
    if (Status s = h.step(1.0); !s)
      return s;
    if (steps >= 5 && h.qdot().norm() <= 1e-13 * h.q().norm())
      break;
  }
  velocity = h.qdot().norm() / std::max(h.q().norm(), 1e-300);
  delta = -h.position(length).y();
  return Status::Ok();
}

int convergence(const Arguments& args)
{
  std::vector<double> ns;
  double length = 0;
  std::ofstream out;
  Status s = args.list("ns", {1, 2, 3, 4, 5, 6, 8, 10, 13, 16, 20, 25, 32, 40}, 1, 400, ns);
  if (s)
    s = args.number("length", 0.1, 1e-3, 10, length);
  if (s)
    s = openOutput(args, out);
  if (!s)
  {
    std::cerr << "hair_study convergence: " << s.message() << "\n";
    return 2;
  }
  const HairParameters p = roundHair(false);
  const double c = std::sqrt(p.stiffness()[1] / p.linearDensity()) / (2 * M_PI * length * length);
  const double f1eb = Beta1L * Beta1L * c, f2eb = Beta2L * Beta2L * c;
  out << "N,f1_hz,f2_hz,f1_eb_hz,f2_eb_hz,deflection_m,deflection_eb_m,static_steps,"
         "static_relative_velocity\n";
  for (double nd : ns)
  {
    const int n = static_cast<int>(nd);
    std::vector<double> f;
    double delta = 0, expected = 0, velocity = 0;
    int steps = 0;
    s = bendingFrequencies(length, n, f);
    if (s)
      s = staticDeflection(length, n, delta, expected, steps, velocity);
    if (!s)
    {
      std::cerr << "hair_study convergence, N = " << n << ": " << s.message() << "\n";
      return 1;
    }
    const double nan = std::numeric_limits<double>::quiet_NaN();
    out << n << "," << f[0] << "," << (f.size() > 1 ? f[1] : nan) << "," << f1eb << "," << f2eb
        << "," << delta << "," << expected << "," << steps << "," << velocity << "\n";
  }
  return 0;
}

// ---------------------------------------------------------------------------------------
// Study 3: Euler buckling of a clamped–free column under a dead axial tip load.

int buckling(const Arguments& args)
{
  int n = 0, maxSteps = 0;
  double tilt = 0, length = 0, dt = 0, tol = 0;
  std::vector<double> loads;
  std::ofstream out;
  Status s = args.integer("n", 10, 1, 400, n);
  if (s)
    s = args.list(
        "loads",
        {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.85, 0.9, 0.95, 1.0, 1.05, 1.1, 1.2, 1.3, 1.5}, 0,
        10, loads);
  if (s)
    s = args.number("tilt", 1e-3, 0, 0.1, tilt);
  if (s)
    s = args.number("length", 0.1, 1e-3, 10, length);
  if (s)
    s = args.number("dt", 100, 1e-6, 1e6, dt);
  if (s)
    s = args.integer("maxsteps", 20000, 1, 10000000, maxSteps);
  if (s)
    s = args.number("tol", 1e-13, 0, 1, tol);
  if (s)
    s = openOutput(args, out);
  if (!s)
  {
    std::cerr << "hair_study buckling: " << s.message() << "\n";
    return 2;
  }
  // Clamped at the origin, tangent +x, no gravity. The dead load at the tip pushes along −x
  // and is tilted by `tilt` radians towards +y: a transverse component tilt·P, the
  // imperfection that picks the buckling direction (it grows with P, as Southwell's
  // construction assumes of an imperfection's effect).
  const HairParameters p = roundHair(true);
  const double ei = p.stiffness()[2];
  const double pcr = M_PI * M_PI * ei / (4 * length * length); // clamped–free (Euler)
  StrandSpec spec = StrandSpec::uniform(length, n, p);
  spec.gravity.setZero();
  SuperHelix h;
  if (s = h.initialize(spec); !s)
  {
    std::cerr << "hair_study buckling: " << s.message() << "\n";
    return 1;
  }
  out << "N,load_ratio,P_N,Pcr_N,tip_x_m,tip_y_m,tip_z_m,steps,converged,change_m\n";
  for (double ratio : loads)
  {
    const double load = ratio * pcr;
    spec.tipForce = load * Eigen::Vector3d(-std::cos(tilt), std::sin(tilt), 0);
    // Continuation: the new load starts from the previous equilibrium. initialize() would
    // reset the shape, so the state is carried over with setState().
    const Eigen::VectorXd q = h.q();
    if (s = h.initialize(spec); s)
      s = h.setState(q, Eigen::VectorXd::Zero(q.size()));
    int steps = 0;
    bool converged = false;
    double change = 0;
    Eigen::Vector3d tip = h.position(length);
    while (s && steps < maxSteps)
    {
      s = h.step(dt);
      ++steps;
      const Eigen::Vector3d next = h.position(length);
      change = (next - tip).norm();
      tip = next;
      // Fixed-point iteration: the change per step shrinks geometrically (ratio about
      // P/P_cr below the critical load); stop when it is below tol·L.
      if (change <= tol * length)
      {
        converged = true;
        break;
      }
    }
    if (!s)
    {
      std::cerr << "hair_study buckling, P/P_cr = " << ratio << ": " << s.message() << "\n";
      return 1;
    }
    out << n << "," << ratio << "," << load << "," << pcr << "," << tip.x() << "," << tip.y() << ","
        << tip.z() << "," << steps << "," << (converged ? 1 : 0) << "," << change << "\n";
  }
  return 0;
}

// ---------------------------------------------------------------------------------------
// Study 4a: the energy budget of a strand released horizontally under gravity.

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

int release(const Arguments& args)
{
  int n = 0;
  double dt = 0, duration = 0, length = 0;
  HairType type = HairType::Wavy;
  std::ofstream out;
  Status s = args.integer("n", 10, 1, 400, n);
  if (s)
    s = args.number("dt", 1.0 / 30, 1e-6, 1, dt);
  if (s)
    s = args.number("duration", 2, 0, 1000, duration);
  if (s)
    s = args.number("length", 0.3, 1e-3, 10, length);
  if (s)
    s = presetByName(args.text("preset", "wavy"), type);
  if (s)
    s = openOutput(args, out);
  if (!s)
  {
    std::cerr << "hair_study release: " << s.message() << "\n";
    return 2;
  }
  // Clamped at the origin with tangent +x (horizontal), gravity −y, in its natural
  // (wavy) shape and at rest: released at t = 0. The preset's internal friction and air
  // drag act; there is no wind, the root does not move, no contact, no tip load.
  StrandSpec spec = StrandSpec::uniform(length, n, HairParameters::preset(type));
  SuperHelix h;
  if (s = h.initialize(spec); !s)
  {
    std::cerr << "hair_study release: " << s.message() << "\n";
    return 1;
  }
  out << "time_s,kinetic,elastic,gravitational,friction_dissipated,air_dissipated,root_work,"
         "wind_work,contact_work,load_work,residual,substeps\n";
  energyRow(out, h);
  const long steps = std::lround(duration / dt);
  for (long i = 0; i < steps; ++i)
  {
    if (s = h.step(dt); !s)
    {
      std::cerr << "hair_study release: " << s.message() << "\n";
      return 1;
    }
    energyRow(out, h);
  }
  return 0;
}

// ---------------------------------------------------------------------------------------
// Study 4b, CI size: a small scene through Core's Simulation, stored as a state file with
// the layout of docs/state-file.md (the demo's own output is much larger).

int scene(const Arguments& args)
{
  int strands = 0, n = 0;
  double duration = 0, dt = 0;
  Status s = args.integer("strands", 6, 1, 10000, strands);
  if (s)
    s = args.integer("n", 10, 1, 400, n);
  if (s)
    s = args.number("duration", 1, 1.0 / 30, 1000, duration);
  if (s)
    s = args.number("dt", 1.0 / 30, 1e-6, 1.0 / 30, dt);
  const std::string model = args.text("model", "super-helix");
  ModelType type = ModelType::SuperHelix;
  if (s)
    s = parseModel(model, "model=", type);
  if (s && !args.has("out"))
    s = Status::Error("give the output file: out=<path>.h5.");
  if (!s)
  {
    std::cerr << "hair_study scene: " << s.message() << "\n";
    return 2;
  }
  // Wavy strands (Super-Helix or projective) of 30 cm on a ring of radius 8 cm around the demo's
  // neck pivot, grown outwards and 30° down; the head shakes ±0.5 rad at 1 Hz as in the demo, with
  // a 0.5 m/s wind from the front. No body parts (the demo's contact needs the bundled body's
  // tables).
  std::vector<GuideStrand> guides;
  SimulationOptions o;
  o.model = type;
  o.timeStep = dt; // the projective model steps at most 1 ms (explicit)
  o.frameInterval = 1.0 / 30;
  Scene scene;
  scene.air = AirField::uniform(Eigen::Vector3d(0, 0, -0.5));
  scene.rootMotion = RigidMotion::shake(bundled::neckPivot(), Eigen::Vector3d::UnitY(), 0.5, 1.0);
  const Eigen::Vector3d centre(0, 1.6, 0.02);
  for (int k = 0; k < strands; ++k)
  {
    const double a = 2 * M_PI * k / strands;
    const Eigen::Vector3d radial(std::cos(a), 0, std::sin(a));
    GuideStrand g;
    g.root = centre + 0.08 * radial;
    g.normal = radial;
    g.growth = (radial * std::cos(M_PI / 6) - Eigen::Vector3d::UnitY() * std::sin(M_PI / 6));
    g.length = 0.3;
    g.elements = n;
    g.hair = HairParameters::preset(HairType::Wavy);
    g.seed = static_cast<std::uint32_t>(k + 1);
    guides.push_back(g);
  }
  Simulation sim;
  StorageOptions storage;
  storage.stateFile = args.text("out", "");
  storage.replaceStateFile = true; // a study run again writes its own output again
  const int frames = static_cast<int>(std::lround(duration * 30)) + 1;
  if (s = sim.initialize(guides, scene, o, storage); s)
    s = sim.advanceTo(frames);
  if (!s)
  {
    std::cerr << "hair_study scene: " << s.message() << "\n";
    return 1;
  }
  return 0;
}

// ---------------------------------------------------------------------------------------
// Study 3, clump part: a clump of guides, squeezed by a converging air flow and held apart
// by hair–hair contacts, whose root disc then oscillates vertically (Super-Helices paper,
// Bertails et al. 2006, figs. 6–7), for several internal frictions γ.

struct ClumpConfig
{
  /// Smooth, round, straight hair (the Euler–Bernoulli strand of the other studies) with an
  /// air friction 20 × the preset's: the converging flow's grip, strong enough to gather
  /// the strands within the ramp. γ is set per run.
  ClumpSpec scene = []
  {
    ClumpSpec c;
    c.hair.airFriction = 2e-4;
    return c;
  }();
  double duration = 6;
  int updatesPerFrame = 1;
  double frame = 1.0 / 30;
  bool contacts = true; ///< false: the same run without hair–hair contacts (the reference)
  HairHairParameters contact;
};

/// One run at internal friction γ; writes its rows (gamma, time, …) to `out`.
Status runClump(const ClumpConfig& c, double gamma, std::ostream& out)
{
  ClumpSpec spec = c.scene;
  spec.hair.internalFriction = gamma;
  std::vector<SuperHelix> strands;
  if (Status st = initializeClump(spec, strands); !st)
    return st;
  HairHairContacts contacts;
  if (Status st = contacts.setParameters(c.contact); !st)
    return st;

  double deepest = 0;
  long lastContacts = 0;
  auto record = [&]()
  {
    // Span ℓ_A as docs/hair-analysis.md defines it: the largest distance between two tips
    // projected on the horizontal plane (vertical = +y); and the mean distance of the tips
    // to the clump's axis (the vertical through the tips' centroid).
    std::vector<Eigen::Vector2d> tips;
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    for (const SuperHelix& h : strands)
    {
      const Eigen::Vector3d p = h.position(spec.length);
      tips.emplace_back(p.x(), p.z());
      centre += tips.back();
    }
    centre /= spec.count;
    double mean = 0, span = 0;
    for (size_t i = 0; i < tips.size(); ++i)
    {
      mean += (tips[i] - centre).norm();
      for (size_t j = 0; j < i; ++j)
        span = std::max(span, (tips[i] - tips[j]).norm());
    }
    const double t = strands[0].time();
    out << gamma << "," << t << "," << clumpRootOffset(spec, t) << "," << span << ","
        << mean / spec.count << "," << lastContacts << "," << deepest << "\n";
    deepest = 0;
  };
  record();
  const long frames = std::lround(c.duration / c.frame);
  for (long f = 0; f < frames; ++f)
  {
    // updatesPerFrame steps per frame, each solving the contacts that may arise within it
    // together with the strands' steps (docs/hair-hair-contacts.md; one per 1/30 s frame is
    // enough for the shaken clump).
    double remaining = c.frame;
    for (int u = 0; u < c.updatesPerFrame; ++u)
    {
      const double h = u + 1 == c.updatesPerFrame ? remaining : c.frame / c.updatesPerFrame;
      const Status st = c.contacts ? stepStrandsWithContacts(strands, contacts, h, 2)
                                   : stepStrands(strands, h, 2);
      if (!st)
      {
        std::ostringstream m;
        m << "gamma = " << gamma << " kg m^3/s, t = " << strands[0].time()
          << " s: " << st.message();
        return Status::Error(m.str());
      }
      if (c.contacts)
      {
        deepest = std::max(deepest, contacts.stats().maxPenetration);
        lastContacts = contacts.stats().active;
      }
      remaining -= h;
    }
    record();
  }
  return Status::Ok();
}

int clump(const Arguments& args)
{
  int quick = 0, withContacts = 1, perLength = 0;
  ClumpConfig c;
  std::vector<double> gammas;
  std::ofstream out;
  Status s = args.integer("quick", 0, 0, 1, quick);
  // Quick (CI): 20 strands on a disc of the same density (ρ0 √(20/50)), the flow ramped over
  // 1.5 s, the oscillation from 1.5 s to 3 s.
  const int count = quick ? 20 : 50;
  const double ramp = quick ? 1.5 : 3, duration = quick ? 3 : 6;
  if (s)
    s = args.integer("strands", count, 2, 2000, c.scene.count);
  if (s)
    s = args.number("duration", duration, 1.0 / 30, 1000, c.duration);
  if (s)
    s = args.number("ramp", ramp, 1.0 / 30, 1000, c.scene.rampTime);
  if (s)
    s = args.list("gammas", {5e-11, 1e-10, 2e-10, 5e-10}, 0, 1e-6, gammas);
  if (s)
    s = args.integer("updates", 1, 1, 64, c.updatesPerFrame);
  if (s)
    s = args.number("thickness", 1.2e-3, 1e-5, 0.1, c.contact.thickness);
  if (s)
    s = args.integer("contacts", 1, 0, 1, withContacts);
  if (s)
    s = args.integer("perlength", 0, 0, 1, perLength);
  if (s)
    s = args.number("reflength", 0.01, 1e-4, 1, c.contact.referenceLength);
  if (s)
    s = args.number("amplitude", 0.01, 0, 1, c.scene.amplitude);
  if (s)
    s = args.number("frequency", 3, 0, 100, c.scene.frequency);
  if (s)
    s = openOutput(args, out);
  if (!s)
  {
    std::cerr << "hair_study clump: " << s.message() << "\n";
    return 2;
  }
  // 50 strands on 12 mm: the density of the test.
  c.scene.discRadius = 0.012 * std::sqrt(c.scene.count / 50.0);
  c.scene.startOscillation = c.scene.rampTime;
  c.contacts = withContacts == 1;
  c.contact.perLength = perLength == 1; // the per-length penalty (docs/hair-hair-contacts.md)
  out << "gamma,time_s,root_y_m,span_m,mean_radius_m,contacts,max_penetration_m\n";
  for (double g : gammas)
    if (s = runClump(c, g, out); !s)
    {
      std::cerr << "hair_study clump: " << s.message() << "\n";
      return 1;
    }
  return 0;
}

// ---------------------------------------------------------------------------------------
// Study 4b, the demo's scene with its body: the guides, head and trunk tables, shake and
// wind of Scripts/demo.sh (Testing/Fixtures/DemoScene) through Core's Simulation, stored as
// a state file, at a chosen step: the projective model's contact budget against its step.

int demo(const Arguments& args)
{
  int strands = 0, n = 0, threads = 0;
  double duration = 0, dt = 0;
  Status s = args.integer("strands", 200, 1, 10000, strands);
  const std::string model = args.text("model", "projective");
  ModelType type = ModelType::Projective;
  if (s)
    s = parseModel(model, "model=", type);
  if (s)
    s = args.integer("n", type == ModelType::Projective ? 40 : 10, 1, 400, n);
  if (s)
    s = args.number("duration", 5, 1.0 / 30, 1000, duration);
  if (s)
    s = args.number("dt", 1.0 / 30, 1e-6, 1.0 / 30, dt);
  if (s)
    s = args.integer("threads", 2, 1, 256, threads);
  if (s && !args.has("out"))
    s = Status::Error("give the output file: out=<path>.h5.");
  if (!s)
  {
    std::cerr << "hair_study demo: " << s.message() << "\n";
    return 2;
  }
  BundledBody body;
  std::vector<GuideStrand> guides;
  s = loadBundledBody(args.text("data", HAIR_DATA_DIR), body);
  if (s)
    s = demoGuides(body, strands, n, guides);
  if (!s)
  {
    std::cerr << "hair_study demo: " << s.message() << "\n";
    return 1;
  }
  SimulationOptions o;
  o.model = type;
  o.timeStep = dt; // the projective model steps at most 1 ms, a whole number per frame
  o.frameInterval = 1.0 / 30;
  o.threads = threads;
  Simulation sim;
  StorageOptions storage;
  storage.stateFile = args.text("out", "");
  storage.replaceStateFile = true; // a study run again writes its own output again
  const int frames = static_cast<int>(std::lround(duration * 30)) + 1;
  if (s = sim.initialize(guides, demoScene(body), o, storage); s)
    s = sim.advanceTo(frames);
  if (!s)
  {
    std::cerr << "hair_study demo: " << s.message() << "\n";
    return 1;
  }
  return 0;
}

// ---------------------------------------------------------------------------------------
// Study 5 (issue 23): the Super-Helices paper's own experiments (Bertails et al. 2006, §4.2,
// figs. 6 and 7), one Super-Helix standing for a clump: (a) the root oscillated vertically,
// the clump's extent ℓ_A over time for several internal frictions γ; (b) its shape over a
// period; (c) a pendulum released from a push, its damping time against the air friction ν.
// docs/study-oscillation.md.

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
                         const RigidMotion& motion = RigidMotion::still())
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

/// The clump's shape on the polyline drawn at `perElement` points per element: its extent
/// ℓ_A, from the root down to its lowest point along the vertical (+y); its width, the
/// largest horizontal distance between two of its points; and its lean, the horizontal
/// distance of the points' centroid from the vertical through the root.
struct ClumpShape
{
  double extent = 0, width = 0, lean = 0;
};

ClumpShape clumpShape(const SuperHelix& h, int perElement)
{
  std::vector<Eigen::Vector3d> points;
  h.polyline(perElement, points);
  ClumpShape c;
  double lowest = points.front().y();
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points)
  {
    lowest = std::min(lowest, p.y());
    centroid += p;
  }
  centroid /= static_cast<double>(points.size());
  c.extent = points.front().y() - lowest;
  c.width = horizontalDiameter(points, Eigen::Vector3d::UnitY());
  c.lean = std::hypot(centroid.x() - points.front().x(), centroid.z() - points.front().z());
  return c;
}

/// The clump as a uniform linear spring hanging under its own weight: its static elongation
/// is m g / (2k), so the compliance dℓ_A/dg = m / (2k) (measured by two static equilibria at
/// g (1 ± 1 %)) gives its first axial mode, the fixed–free heavy spring's
/// ω1 = (π/2) √(k/m) (the wave equation along the spring), f1 = 1 / (4 √(2 dℓ_A/dg)).
Status springFrequency(StrandSpec spec, int perElement, double& frequency)
{
  double extent[2];
  const Eigen::Vector3d g = spec.gravity;
  for (int k = 0; k < 2; ++k)
  {
    spec.gravity = g * (k == 0 ? 0.99 : 1.01);
    Eigen::VectorXd q;
    int steps = 0;
    SuperHelix h;
    Status s = hangAtRest(spec, q, steps);
    if (s)
      s = h.initialize(spec);
    if (s)
      s = h.setState(q, Eigen::VectorXd::Zero(q.size()));
    if (!s)
      return s;
    extent[k] = clumpShape(h, perElement).extent;
  }
  const double compliance = (extent[1] - extent[0]) / (0.02 * g.norm());
  frequency = compliance > 0 ? 0.25 / std::sqrt(2 * compliance) : 0;
  return Status::Ok();
}

int oscillation(const Arguments& args)
{
  int n = 0;
  double length = 0, amplitude = 0, duration = 0, dt = 0, fade = 0, rate = 0, window = 0, nu = -1;
  std::vector<double> gammas, frequencies;
  HairType type = HairType::Curly;
  Integrator integrator = Integrator::SemiImplicit;
  std::ofstream out;
  Status s = presetByName(args.text("preset", "curly"), type);
  if (s)
    s = integratorByName(args.text("integrator", "semi-implicit"), integrator);
  if (s)
    s = args.number("length", 0.3, 1e-3, 10, length);
  if (s)
    s = args.integer("n", 40, 1, 400, n);
  if (s)
    s = args.list("gammas", {5e-11, 1e-10, 5e-10}, 0, 1e-6, gammas);
  if (s)
    s = args.list("frequencies", {3}, 0.01, 1000, frequencies);
  if (s)
    s = args.number("amplitude", 0.01, 0, 1, amplitude);
  if (s && args.has("nu")) // otherwise the preset's
    s = args.number("nu", 0, 0, 1, nu);
  if (s)
    s = args.number("duration", 8, 0.1, 1000, duration);
  if (s)
    s = args.number("fade", 1, 0, 100, fade);
  if (s)
    s = args.number("window", 2, 0.01, 1000, window);
  if (s)
    s = args.number("dt", 1.0 / 2000, 1e-6, 1.0 / 30, dt);
  if (s)
    s = args.number("rate", 200, 1, 1e6, rate);
  if (s && window > duration - fade)
    s = Status::Error("window=" + args.text("window", "") +
                      " is longer than the steady part of the run (duration - fade).");
  if (s && 2 * fade > duration)
    s = Status::Error("fade is more than half the duration.");
  if (s)
    s = openOutput(args, out);
  std::ofstream summary, shapes;
  if (s && args.has("summary"))
  {
    summary.open(args.text("summary", ""));
    if (!summary)
      s = Status::Error("cannot write '" + args.text("summary", "") + "'.");
    summary.precision(17);
  }
  if (s && args.has("shapes"))
  {
    shapes.open(args.text("shapes", ""));
    if (!shapes)
      s = Status::Error("cannot write '" + args.text("shapes", "") + "'.");
    shapes.precision(17);
  }
  if (!s)
  {
    std::cerr << "hair_study oscillation: " << s.message() << "\n";
    return 2;
  }
  constexpr int perElement = 8; // polyline points per element for ℓ_A and the shapes
  out << "gamma,frequency_hz,time_s,root_y_m,extent_m,width_m,lean_m,tip_x_m,tip_y_m,tip_z_m\n";
  if (summary)
    summary << "gamma,frequency_hz,amplitude_m,nu,extent_rest_m,extent_min_m,extent_max_m,"
               "extent_amplitude_m,width_rest_m,width_max_m,lean_rest_m,lean_max_m,static_steps,"
               "spring_frequency_hz\n";
  if (shapes)
    shapes << "gamma,frequency_hz,time_s,point,x_m,y_m,z_m\n";
  for (double f : frequencies)
    for (double gamma : gammas)
    {
      HairParameters hair = HairParameters::preset(type);
      hair.internalFriction = gamma;
      if (nu >= 0)
        hair.airFriction = nu;
      // At rest in its static equilibrium, then the root oscillates vertically,
      // d(t) = amplitude · sin(2π f t), grown from rest over `fade` seconds.
      Eigen::VectorXd q;
      int staticSteps = 0;
      SuperHelix h;
      const RigidMotion drive =
          RigidMotion::vertical(Eigen::Vector3d::UnitY(), amplitude, f).during(0).fading(fade);
      StrandSpec spec = hangingStrand(length, n, hair);
      double spring = 0;
      s = hangAtRest(spec, q, staticSteps);
      if (s && summary)
        s = springFrequency(spec, perElement, spring);
      if (s)
      {
        spec.root = drive.carriedRoot(Eigen::Vector3d::Zero(), hangingFrame());
        spec.integrator = integrator;
        s = h.initialize(spec);
      }
      if (s)
        s = h.setState(q, Eigen::VectorXd::Zero(q.size()));
      if (!s)
      {
        std::cerr << "hair_study oscillation, gamma = " << gamma << ": " << s.message() << "\n";
        return 1;
      }
      const ClumpShape rest = clumpShape(h, perElement);
      double lo = std::numeric_limits<double>::infinity(), hi = -lo, widest = 0, leanest = 0;
      const long steps = std::lround(duration / dt);
      const long every = std::max(1L, std::lround(1 / (rate * dt)));
      // Shapes: 12 instants over the last period of the run (and the end).
      const long perPeriod = std::lround(1 / (f * dt));
      for (long i = 0; i <= steps; ++i)
      {
        if (i > 0)
          if (s = h.step(dt); !s)
          {
            std::cerr << "hair_study oscillation, gamma = " << gamma << ": " << s.message() << "\n";
            return 1;
          }
        const double t = h.time();
        const ClumpShape c = clumpShape(h, perElement);
        if (t >= duration - window - 1e-9)
        {
          lo = std::min(lo, c.extent);
          hi = std::max(hi, c.extent);
          widest = std::max(widest, c.width);
          leanest = std::max(leanest, c.lean);
        }
        if (i % every == 0)
        {
          const Eigen::Vector3d tip = h.position(h.length());
          out << gamma << "," << f << "," << t << "," << h.rootState(t).position.y() << ","
              << c.extent << "," << c.width << "," << c.lean << "," << tip.x() << "," << tip.y()
              << "," << tip.z() << "\n";
        }
        if (shapes && i >= steps - perPeriod && (steps - i) % std::max(1L, perPeriod / 12) == 0)
        {
          std::vector<Eigen::Vector3d> points;
          h.polyline(perElement, points);
          for (std::size_t k = 0; k < points.size(); ++k)
            shapes << gamma << "," << f << "," << t << "," << k << "," << points[k].x() << ","
                   << points[k].y() << "," << points[k].z() << "\n";
        }
      }
      if (summary)
        summary << gamma << "," << f << "," << amplitude << "," << hair.airFriction << ","
                << rest.extent << "," << lo << "," << hi << "," << 0.5 * (hi - lo) << ","
                << rest.width << "," << widest << "," << rest.lean << "," << leanest << ","
                << staticSteps << "," << spring << "\n";
    }
  return 0;
}

int pendulum(const Arguments& args)
{
  int n = 0;
  double length = 0, duration = 0, dt = 0, push = 0, frequency = 0, rate = 0;
  std::vector<double> nus;
  std::vector<std::string> presets;
  std::ofstream out;
  Integrator integrator = Integrator::SemiImplicit;
  Status s = integratorByName(args.text("integrator", "semi-implicit"), integrator);
  if (s)
  {
    std::stringstream ss(args.text("presets", "smooth,fuzzy"));
    std::string item;
    HairType type;
    while (s && std::getline(ss, item, ','))
      if (s = presetByName(item, type); s)
        presets.push_back(item);
  }
  if (s)
    s = args.number("length", 0.3, 1e-3, 10, length);
  if (s)
    s = args.integer("n", 10, 1, 400, n);
  if (s)
    s = args.list("nus", {0, 5e-6, 1e-5, 2e-5, 5e-5}, 0, 1, nus);
  if (s)
    s = args.number("duration", 8, 0.1, 1000, duration);
  if (s)
    s = args.number("dt", 1.0 / 2000, 1e-6, 1.0 / 30, dt);
  if (s)
    s = args.number("push", 0.02, 0, 1, push);
  if (s)
    s = args.number("frequency", 1, 0.01, 100, frequency);
  if (s)
    s = args.number("rate", 200, 1, 1e6, rate);
  if (s)
    s = openOutput(args, out);
  if (!s)
  {
    std::cerr << "hair_study pendulum: " << s.message() << "\n";
    return 2;
  }
  out << "preset,nu,gamma,linear_density,time_s,root_x_m,tip_x_m,tip_y_m,tip_z_m,energy_j\n";
  for (const std::string& name : presets)
    for (double nu : nus)
    {
      HairType type;
      presetByName(name, type);
      HairParameters hair = HairParameters::preset(type);
      hair.airFriction = nu;
      // At rest in its static equilibrium; then one period of a horizontal push of the root,
      // x(t) = push · sin(2π f t) grown and ended by a quarter-period smoothstep, sets it
      // swinging; afterwards the root is still and the strand swings freely.
      Eigen::VectorXd q;
      int staticSteps = 0;
      StrandSpec spec = hangingStrand(length, n, hair);
      s = hangAtRest(spec, q, staticSteps);
      SuperHelix h;
      if (s)
      {
        const RigidMotion drive = RigidMotion::vertical(Eigen::Vector3d::UnitX(), push, frequency)
                                      .during(0, 1)
                                      .fading(0.25 / frequency);
        spec.root = drive.carriedRoot(Eigen::Vector3d::Zero(), hangingFrame());
        spec.integrator = integrator;
        s = h.initialize(spec);
      }
      if (s)
        s = h.setState(q, Eigen::VectorXd::Zero(q.size()));
      const long steps = std::lround(duration / dt);
      const long every = std::max(1L, std::lround(1 / (rate * dt)));
      // The swing's energy: the strand's mechanical energy above its static equilibrium (the
      // root is back at rest after the push, so the equilibrium is the one it started from).
      const double rest = h.energy().mechanical();
      for (long i = 0; s && i <= steps; ++i)
      {
        if (i > 0)
          s = h.step(dt);
        if (s && i % every == 0)
        {
          const double t = h.time();
          const Eigen::Vector3d tip = h.position(h.length());
          out << name << "," << nu << "," << hair.internalFriction << "," << hair.linearDensity()
              << "," << t << "," << h.rootState(t).position.x() << "," << tip.x() << "," << tip.y()
              << "," << tip.z() << "," << h.energy().mechanical() - rest << "\n";
        }
      }
      if (!s)
      {
        std::cerr << "hair_study pendulum, " << name << ", nu = " << nu << ": " << s.message()
                  << "\n";
        return 1;
      }
    }
  return 0;
}

// ---------------------------------------------------------------------------------------
// Issue 23: the two time steps measured side by side (docs/super-helix.md, "The
// second-order step", "Accuracy on request"). One CSV row per run:
//   case, integrator, dt_s, tolerance_m_per_s, figure, value, steps, rejected, first_order,
//   wall_s
// release: a 30 cm smooth strand clamped horizontally, no friction, no air, 2 s; figure
//   residual_share = residual / gravitational energy released at 2 s.
// tip: the same strand with air drag 1e-5 kg/(m·s), 1 s, frames of 1/30 s; figure
//   tip_error_m = the largest distance of its tip from that of the second-order step at
//   1/7680 s over the frames (the reference, itself within 2.8e-5 m of 1/15360 s).
// tolerance: the tip's strand in frames of 1/30 s with advance(1/30, tolerance/30).
// demo (demo=1): the demo scene (Testing/Fixtures/DemoScene: wavy guides on the bundled
//   body's scalp, head and trunk tables, ±0.5 rad 1 Hz shake, 0.5 m/s wind) through
//   Simulation, `seconds` long, with and without contacts; figure closure = max |residual| /
//   max |work done on the hair|, and the cost per simulated second.
// quick=1: fewer step sizes and tolerances (seconds of run time).

struct IntegratorRun
{
  std::vector<Eigen::Vector3d> tips;
  double residualShare = 0, wall = 0;
  long steps = 0, rejected = 0, firstOrder = 0;
};

IntegratorRun releasedStrand(Integrator integrator, double air, double seconds, int perFrame,
                             double tolerance, Status& st, int elements = 10)
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

int integrator(const Arguments& args)
{
  int quick = 0, demo = 0, guides = 0;
  double seconds = 0;
  std::ofstream out;
  Status s = args.integer("quick", 0, 0, 1, quick);
  if (s)
    s = args.integer("demo", 0, 0, 1, demo);
  if (s)
    s = args.integer("guides", 200, 1, 10000, guides);
  if (s)
    s = args.number("seconds", 5, 1.0 / 30, 100, seconds);
  if (s)
    s = openOutput(args, out);
  if (!s)
  {
    std::cerr << "hair_study integrator: " << s.message() << "\n";
    return 2;
  }
  out << "case,integrator,dt_s,tolerance_m_per_s,figure,value,steps,rejected,first_order,wall_s\n";
  const Integrator both[] = {Integrator::SemiImplicit, Integrator::Midpoint, Integrator::Bdf2};
  auto row = [&](const char* what, Integrator in, double dt, double tol, const char* figure,
                 double value, const IntegratorRun& r)
  {
    out << what << "," << toString(in) << "," << dt << "," << tol << "," << figure << "," << value
        << "," << r.steps << "," << r.rejected << "," << r.firstOrder << "," << r.wall << "\n";
  };
  auto fail = [&](const Status& st)
  {
    std::cerr << "hair_study integrator: " << st.message() << "\n";
    return 1;
  };
  const std::vector<int> perFrame =
      quick ? std::vector<int>{1, 4, 16} : std::vector<int>{1, 2, 4, 8, 16, 32, 64, 128};
  for (Integrator in : both)
    for (int per : perFrame)
    {
      Status st;
      const IntegratorRun r = releasedStrand(in, 0, 2, per, 0, st);
      if (!st)
        return fail(st);
      row("release", in, 1.0 / (30 * per), 0, "residual_share", r.residualShare, r);
    }
  Status st;
  const IntegratorRun ref = releasedStrand(Integrator::Midpoint, 1e-5, 1, 256, 0, st);
  if (!st)
    return fail(st);
  auto tipError = [&](const IntegratorRun& r)
  {
    double e = 0;
    for (size_t i = 0; i < r.tips.size() && i < ref.tips.size(); ++i)
      e = std::max(e, (r.tips[i] - ref.tips[i]).norm());
    return e;
  };
  for (Integrator in : both)
    for (int per : perFrame)
    {
      if (per > 64)
        continue;
      const IntegratorRun r = releasedStrand(in, 1e-5, 1, per, 0, st);
      if (!st)
        return fail(st);
      row("tip", in, 1.0 / (30 * per), 0, "tip_error_m", tipError(r), r);
    }
  const std::vector<double> tolerances = quick
                                             ? std::vector<double>{0.05, 0.005}
                                             : std::vector<double>{0.05, 0.02, 0.01, 0.005, 0.002};
  for (Integrator in : both)
    for (double tol : tolerances)
    {
      const IntegratorRun r = releasedStrand(in, 1e-5, 1, 1, tol, st);
      if (!st)
        return fail(st);
      row("tolerance", in, 1.0 / 30, tol, "tip_error_m", tipError(r), r);
    }
  if (!demo)
    return 0;
  BundledBody body;
  if (st = loadBundledBody(HAIR_DATA_DIR, body); !st)
    return fail(st);
  std::vector<GuideStrand> demoStrands;
  if (st = demoGuides(body, guides, 10, demoStrands); !st)
    return fail(st);
  for (int contacts : {1, 0})
    for (Integrator in : both)
      for (double tol : {0.0, 0.005})
      {
        SimulationOptions o;
        o.threads = 1;
        o.superHelix.integrator = in;
        o.superHelix.tolerance = tol;
        o.contacts.enabled = contacts != 0;
        Simulation sim;
        if (st = sim.initialize(demoStrands, demoScene(body), o); !st)
          return fail(st);
        const auto start = std::chrono::steady_clock::now();
        if (st = sim.advanceTo(static_cast<int>(std::lround(seconds * 30)) + 1); !st)
          return fail(st);
        IntegratorRun r;
        r.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::vector<double> times;
        std::map<std::string, std::vector<double>> c;
        sim.energyTable(times, c);
        double residual = 0, work = 0, substeps = 0, rejected = 0, firstOrder = 0;
        for (size_t i = 0; i < times.size(); ++i)
        {
          const double w = -(c["gravitational"][i] - c["gravitational"][0]) + c["root_work"][i] +
                           c["wind_work"][i] + c["contact_work"][i];
          residual = std::max(residual, std::abs(c["residual"][i]));
          work = std::max(work, std::abs(w));
          substeps += c["substeps"][i];
          rejected += c["rejected_substeps"][i];
          firstOrder += c["first_order_share"][i] * c["substeps"][i];
        }
        // Per strand and simulated second.
        r.steps = std::lround(substeps / seconds);
        r.rejected = std::lround(rejected / seconds);
        r.firstOrder = std::lround(firstOrder / seconds);
        r.wall /= seconds;
        row(contacts ? "demo_contacts" : "demo_no_contacts", in, 1.0 / 30, tol, "closure",
            residual / work, r);
      }
  return 0;
}

// ---------------------------------------------------------------------------------------
// Work against precision over N (docs/study-accuracy.md): the released strand of `integrator`
// (30 cm, smooth, air drag 1e-5, no internal friction, 1 s in frames of 1/30 s) with N
// elements, each step and tolerance, against the midpoint step at 1/7680 s with the same N:
// the tip's largest distance over the frames, the steps (accepted and rejected) and the
// wall time for the simulated second. One CSV row per run.

int workPrecision(const Arguments& args)
{
  std::vector<double> ns, tolerances;
  std::ofstream out;
  Status s = args.list("ns", {5, 10, 20, 40}, 1, 400, ns);
  if (s)
    s = args.list("tolerances", {0.05, 0.02, 0.01, 0.005}, 1e-6, 1, tolerances);
  if (s)
    s = openOutput(args, out);
  if (!s)
  {
    std::cerr << "hair_study workprecision: " << s.message() << "\n";
    return 2;
  }
  out << "n,integrator,tolerance_m_per_s,tip_error_m,steps,rejected,first_order,wall_s\n";
  for (double nd : ns)
  {
    const int n = static_cast<int>(std::lround(nd));
    Status st;
    const IntegratorRun ref = releasedStrand(Integrator::Midpoint, 1e-5, 1, 256, 0, st, n);
    for (Integrator in : {Integrator::SemiImplicit, Integrator::Midpoint, Integrator::Bdf2})
      for (double tol : tolerances)
      {
        if (!st)
          break;
        const IntegratorRun r = releasedStrand(in, 1e-5, 1, 1, tol, st, n);
        double e = 0;
        for (size_t i = 0; i < r.tips.size() && i < ref.tips.size(); ++i)
          e = std::max(e, (r.tips[i] - ref.tips[i]).norm());
        if (st)
          out << n << "," << toString(in) << "," << tol << "," << e << "," << r.steps << ","
              << r.rejected << "," << r.firstOrder << "," << r.wall << std::endl;
      }
    if (!st)
    {
      std::cerr << "hair_study workprecision, N = " << n << ": " << st.message() << "\n";
      return 1;
    }
  }
  return 0;
}

// ---------------------------------------------------------------------------------------
// The order of the time step in contact (docs/study-accuracy.md): a smooth 25 cm strand rooted
// on the crown of the bundled head, growing sideways, falls onto the head table and slides
// over it (body contacts with friction `friction`, 0.3 by default); the tip's largest
// distance over [0, `seconds`] (sampled every 1/30 s) from a run at 1/(30·`reference`) s of
// the same integrator, for steps of 1/(30 k) s, k = 1, 2, 4, …, `finest`; the observed order
// between consecutive k.

Status contactStrandRun(const std::vector<PosedPart>& bodies, const Eigen::Vector3d& above,
                        Integrator integrator, int perFrame, double friction, double lookAhead,
                        double seconds, std::vector<Eigen::Vector3d>& tips, long& firstOrder)
{
  const TableQuery top = bodies[0].query(above);
  if (!top.covered)
    return Status::Error("the first table does not cover the top.");
  HairParameters hp = HairParameters::preset(HairType::Smooth);
  hp.curvatureVariation = 0;
  StrandSpec s = StrandSpec::uniform(0.25, 10, hp);
  s.integrator = integrator;
  const Eigen::Vector3d root = top.surfacePoint + 0.002 * top.normal;
  s.root = [root](double)
  {
    RootState r;
    r.position = root;
    r.orientation = Eigen::Matrix3d::Identity(); // tangent +x: sideways over the head
    return r;
  };
  SuperHelix h;
  if (Status st = h.initialize(s); !st)
    return st;
  BodyContactParameters prm;
  prm.friction = friction;
  prm.lookAhead = lookAhead;
  BodyContacts contacts;
  if (Status st = contacts.setParameters(prm); !st)
    return st;
  const double rhoS = hp.linearDensity();
  h.setContactForces(
      [&](int, double, const std::vector<StrandSample>& smp, std::vector<ContactResponse>& r)
      { contacts.respond(smp, rhoS, bodies.data(), static_cast<int>(bodies.size()), r); });
  tips.assign(1, h.position(h.length()));
  firstOrder = 0;
  const long frames = std::lround(seconds * 30);
  for (long f = 0; f < frames; ++f)
  {
    for (int k = 0; k < perFrame; ++k)
    {
      if (Status st = h.step(1.0 / (30 * perFrame)); !st)
        return st;
      firstOrder += h.lastFirstOrder();
    }
    tips.push_back(h.position(h.length()));
  }
  return Status::Ok();
}

int order(const Arguments& args)
{
  int finest = 0, referenceSteps = 0;
  double seconds = 0, friction = 0, lookAhead = 0;
  std::ofstream out;
  Status s = args.integer("finest", 64, 1, 4096, finest);
  if (s)
    s = args.integer("reference", 2048, 2, 100000, referenceSteps);
  if (s)
    s = args.number("seconds", 1, 1.0 / 30, 100, seconds);
  if (s)
    s = args.number("friction", 0.3, 0, 10, friction);
  if (s)
    s = args.number("lookahead", 1.0 / 30, 0, 1, lookAhead);
  std::vector<Integrator> integrators;
  {
    std::stringstream list(args.text("integrators", "semi-implicit,bdf2"));
    std::string item;
    Integrator in;
    while (s && std::getline(list, item, ','))
      if (s = integratorByName(item, in); s)
        integrators.push_back(in);
  }
  if (s)
    s = openOutput(args, out);
  if (!s)
  {
    std::cerr << "hair_study order: " << s.message() << "\n";
    return 2;
  }
  // The head and trunk tables of the bundled body, or a sphere of radius 0.1 m (its table
  // cast on the exact sphere).
  const std::string bodyName = args.text("body", "head");
  std::vector<PosedPart> bodies;
  Eigen::Vector3d above;
  BundledBody b;
  CollisionTable sphereTable;
  if (bodyName == "head")
  {
    if (s = loadBundledBody(HAIR_DATA_DIR, b); s)
    {
      bodies = {PosedPart::still(b.parts[b.head].table), PosedPart::still(b.parts[b.trunk].table)};
      above = b.headCentre + Eigen::Vector3d(0, 0.2, 0);
    }
  }
  else if (bodyName == "sphere")
  {
    const hairtest::Ellipsoid sphere(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(0.1));
    TableSpec t;
    t.projection = Projection::Spherical;
    if (s = sphereTable.build(t, sphere); s)
    {
      bodies = {PosedPart::still(sphereTable)};
      above = Eigen::Vector3d(0, 0.2, 0);
    }
  }
  else
    s = Status::Error("body=" + bodyName + " is not one of head, sphere.");
  if (!s)
  {
    std::cerr << "hair_study order: " << s.message() << "\n";
    return 1;
  }
  out << "integrator,friction,steps_per_frame,dt_s,tip_error_m,order,first_order_steps\n";
  for (Integrator in : integrators)
  {
    std::vector<Eigen::Vector3d> ref, tips;
    long firstOrder = 0;
    if (s = contactStrandRun(bodies, above, in, referenceSteps, friction, lookAhead, seconds, ref,
                             firstOrder);
        !s)
      break;
    double previous = 0;
    for (int k = 1; k <= finest; k *= 2)
    {
      if (s = contactStrandRun(bodies, above, in, k, friction, lookAhead, seconds, tips,
                               firstOrder);
          !s)
        break;
      double e = 0;
      for (size_t i = 0; i < tips.size(); ++i)
        e = std::max(e, (tips[i] - ref[i]).norm());
      out << toString(in) << "," << friction << "," << k << "," << 1.0 / (30 * k) << "," << e
          << ",";
      if (previous > 0)
        out << std::log2(previous / e);
      out << "," << firstOrder << std::endl;
      previous = e;
    }
    if (!s)
      break;
  }
  if (!s)
  {
    std::cerr << "hair_study order: " << s.message() << "\n";
    return 1;
  }
  return 0;
}

// ---------------------------------------------------------------------------------------
// Accuracy on the demo scene (docs/study-accuracy.md): the demo's guides on the bundled body
// (head and trunk tables, the default hair–hair grid, the head's shake and the wind) run with
// each of `runs` (integrator:tolerance, comma-separated) and with `reference`; per run the
// wall time of the simulation (threads as given), each strand's largest tip distance from the
// reference's over the frames (median and 95th percentile over the strands), the energy
// closure |residual| / (|work done on the hair| + |dissipated|) at the end (the demo's
// summary), the sub-steps and the share taken first order. The reference's tips are kept in
// `cache` and reused when it was made with the same guides, seconds and reference.

struct SceneRun
{
  std::vector<std::vector<Eigen::Vector3d>> tips; // per frame, per strand
  double wall = 0, closure = 0, substeps = 0, rejected = 0, firstOrder = 0;
};

Status runAccuracyScene(const BundledBody& body, const std::vector<GuideStrand>& guides,
                        Integrator integrator, double tolerance, int perFrame, int threads,
                        int frames, bool bodyContacts, bool grid, SceneRun& r)
{
  SimulationOptions o;
  o.threads = threads;
  o.timeStep = o.frameInterval / perFrame;
  o.contacts.enabled = bodyContacts;
  o.superHelix.hairHairEnabled = grid;
  o.superHelix.integrator = integrator;
  o.superHelix.tolerance = tolerance;
  Simulation sim;
  if (Status s = sim.initialize(guides, demoScene(body), o); !s)
    return s;
  const auto start = std::chrono::steady_clock::now();
  if (Status s = sim.advanceTo(frames); !s)
    return s;
  r.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.tips.assign(frames, {});
  for (int f = 0; f < frames; ++f)
  {
    GuideDrawing drawn;
    if (Status s = sim.drawFrame(f, 1, drawn); !s)
      return s;
    const auto& offsets = drawn.header.offsets;
    for (size_t k = 0; k + 1 < offsets.size(); ++k)
      r.tips[f].push_back(drawn.frame.positions[offsets[k + 1] - 1]);
  }
  std::vector<double> times;
  std::map<std::string, std::vector<double>> c;
  sim.energyTable(times, c);
  const size_t last = times.size() - 1;
  r.closure = std::abs(c["residual"][last]) / std::max(1e-300, std::abs(c["external_work"][last]) +
                                                                   std::abs(c["dissipated"][last]));
  for (size_t i = 1; i < times.size(); ++i)
  {
    r.substeps += c["substeps"][i];
    r.rejected += c["rejected_substeps"][i];
    r.firstOrder += c["first_order_share"][i] * c["substeps"][i];
  }
  r.firstOrder /= std::max(1e-300, r.substeps);
  r.substeps /= std::max<size_t>(1, last);
  r.rejected /= std::max<size_t>(1, last);
  return Status::Ok();
}

// integrator[:tolerance[:steps per frame]]
struct AccuracyRun
{
  Integrator integrator = Integrator::SemiImplicit;
  double tolerance = 0;
  int perFrame = 1;
};

Status parseRun(const std::string& text, AccuracyRun& run)
{
  const size_t colon = text.find(':');
  if (Status s = integratorByName(text.substr(0, colon), run.integrator); !s)
    return s;
  if (colon != std::string::npos)
  {
    std::string rest = text.substr(colon + 1);
    std::replace(rest.begin(), rest.end(), ':', ' ');
    std::istringstream in(rest);
    if (!(in >> run.tolerance) || !(run.tolerance >= 0))
      return Status::Error("run '" + text + "': the tolerance after ':' must be a number >= 0.");
    if (!(in >> run.perFrame))
      run.perFrame = 1;
    if (run.perFrame < 1 || run.perFrame > 1000)
      return Status::Error("run '" + text + "': the steps per frame must be in [1, 1000].");
  }
  return Status::Ok();
}

int accuracy(const Arguments& args)
{
  int guidesCount = 0, threads = 0, bodyContacts = 1, grid = 1;
  double seconds = 0;
  std::ofstream out;
  Status s = args.integer("guides", 200, 1, 10000, guidesCount);
  if (s)
    s = args.integer("body", 1, 0, 1, bodyContacts);
  if (s)
    s = args.integer("grid", 1, 0, 1, grid);
  if (s)
    s = args.integer("threads", 2, 1, 256, threads);
  if (s)
    s = args.number("seconds", 2, 1.0 / 30, 100, seconds);
  std::vector<AccuracyRun> runs;
  {
    std::stringstream list(args.text("runs", "semi-implicit:0,bdf2:0"));
    std::string item;
    while (s && std::getline(list, item, ','))
    {
      AccuracyRun run;
      s = parseRun(item, run);
      runs.push_back(run);
    }
  }
  AccuracyRun reference;
  const std::string referenceName = args.text("reference", "semi-implicit:0.001");
  if (s)
    s = parseRun(referenceName, reference);
  if (s)
    s = openOutput(args, out);
  if (!s)
  {
    std::cerr << "hair_study accuracy: " << s.message() << "\n";
    return 2;
  }
  auto fail = [](const Status& st)
  {
    std::cerr << "hair_study accuracy: " << st.message() << "\n";
    return 1;
  };
  BundledBody body;
  std::vector<GuideStrand> guides;
  if (s = loadBundledBody(HAIR_DATA_DIR, body); !s)
    return fail(s);
  if (s = demoGuides(body, guidesCount, 10, guides); !s)
    return fail(s);
  const int frames = static_cast<int>(std::lround(seconds * 30)) + 1;
  // The reference: from the cache when it matches, else run (and cached).
  std::ostringstream key;
  key << "# guides=" << guidesCount << " seconds=" << seconds << " reference=" << referenceName
      << " body=" << bodyContacts << " grid=" << grid;
  SceneRun ref;
  const std::string cache = args.text("cache", "");
  if (!cache.empty())
  {
    std::ifstream in(cache);
    std::string line;
    if (in && std::getline(in, line) && line == key.str())
    {
      ref.tips.assign(frames, std::vector<Eigen::Vector3d>(guides.size()));
      int f = 0, k = 0;
      double x, y, z;
      char comma;
      while (in >> f >> comma >> k >> comma >> x >> comma >> y >> comma >> z)
        if (f >= 0 && f < frames && k >= 0 && k < static_cast<int>(guides.size()))
          ref.tips[f][k] = Eigen::Vector3d(x, y, z);
      std::cerr << "hair_study accuracy: reference from " << cache << "\n";
    }
  }
  if (ref.tips.empty())
  {
    if (s = runAccuracyScene(body, guides, reference.integrator, reference.tolerance,
                             reference.perFrame, threads, frames, bodyContacts != 0, grid != 0,
                             ref);
        !s)
      return fail(s);
    std::cerr << "hair_study accuracy: reference " << referenceName << " took " << ref.wall
              << " s\n";
    if (!cache.empty())
    {
      std::ofstream c(cache);
      c << key.str() << "\n";
      c.precision(17);
      for (int f = 0; f < frames; ++f)
        for (size_t k = 0; k < ref.tips[f].size(); ++k)
          c << f << "," << k << "," << ref.tips[f][k].x() << "," << ref.tips[f][k].y() << ","
            << ref.tips[f][k].z() << "\n";
    }
  }
  out << "integrator,tolerance_m_per_s,steps_per_frame,wall_s,wall_ratio,tip_error_median_m,"
         "tip_error_p95_m,closure,substeps_per_frame,rejected_per_frame,first_order_share\n";
  double firstWall = 0;
  for (const AccuracyRun& run : runs)
  {
    SceneRun r;
    if (s = runAccuracyScene(body, guides, run.integrator, run.tolerance, run.perFrame, threads,
                             frames, bodyContacts != 0, grid != 0, r);
        !s)
      return fail(s);
    std::vector<double> errors(guides.size(), 0.0);
    for (int f = 0; f < frames; ++f)
      for (size_t k = 0; k < guides.size(); ++k)
        errors[k] = std::max(errors[k], (r.tips[f][k] - ref.tips[f][k]).norm());
    std::sort(errors.begin(), errors.end());
    auto quantile = [&](double p) {
      return errors[std::min(errors.size() - 1,
                             static_cast<size_t>(p * (errors.size() - 1) + 0.5))];
    };
    if (firstWall == 0)
      firstWall = r.wall;
    out << toString(run.integrator) << "," << run.tolerance << "," << run.perFrame << "," << r.wall
        << "," << r.wall / firstWall << "," << quantile(0.5) << "," << quantile(0.95) << ","
        << r.closure << "," << r.substeps << "," << r.rejected << "," << r.firstOrder << std::endl;
  }
  return 0;
}

// ---------------------------------------------------------------------------------------
// Hair–hair contacts (docs/hair-hair-contacts.md): the demo's head shake on the bundled body
// or the dense shaken clump, per frame: pairs of guide pieces that went through each other
// since the previous frame, the body's penetration, the contacts; the energy budget at the
// end.

/// The guides' drawn points, strand by strand, from a frame (points per the header's offsets).
/// Frame `f` of the run drawn at 8 points per element: a curled element is half a turn,
/// and coarser chords miss crossings of the curve.
std::vector<std::vector<Eigen::Vector3d>> polylines(const Simulation& sim, int f)
{
  GuideDrawing drawn;
  if (Status s = sim.drawFrame(f, 8, drawn); !s)
  {
    std::cerr << "hair_study: " << s.message() << "\n";
    std::exit(1);
  }
  const StateHeader& header = drawn.header;
  std::vector<std::vector<Eigen::Vector3d>> out(header.numberOfStrands());
  for (size_t k = 0; k < out.size(); ++k)
    out[k].assign(drawn.frame.positions.begin() + header.offsets[k],
                  drawn.frame.positions.begin() + header.offsets[k + 1]);
  return out;
}

int hairhair(const Arguments& args)
{
  int withContacts = 1, guidesCount = 200, threads = 2, bodyContacts = 1;
  double duration = 0;
  HairHairParameters p;
  std::ofstream out;
  const std::string sceneName = args.text("scene", "demo");
  Status s = sceneName == "demo" || sceneName == "clump"
                 ? Status::Ok()
                 : Status::Error("scene=" + sceneName + " is not one of demo, clump.");
  if (s)
    s = args.integer("contacts", 1, 0, 1, withContacts);
  if (s)
    s = args.integer("body", 1, 0, 1, bodyContacts);
  if (s)
    s = args.integer("guides", 200, 1, 20000, guidesCount);
  if (s)
    s = args.integer("threads", 2, 1, 256, threads);
  if (s)
    s = args.number("duration", sceneName == "demo" ? 5 : 6, 1.0 / 30, 1000, duration);
  if (s) // the demo: 0, automatic; the clump: the tests' 1.2 mm
    s = args.number("thickness", sceneName == "demo" ? 0 : 1.2e-3, 0, 0.1, p.thickness);
  if (s && sceneName == "clump" && !(p.thickness > 0))
    s = Status::Error("thickness=0 (automatic) is for guides on a head; give the clump's.");
  if (s)
    s = args.number("stiffness", p.stiffness, 1e-6, 1e6, p.stiffness);
  if (s)
    s = args.number("friction", p.friction, 0, 10, p.friction);
  if (s)
    s = args.number("margin", p.margin, 0, 4, p.margin);
  if (s)
    s = args.integer("iterations", p.iterations, 1, 1000, p.iterations);
  HairGridParameters grid;
  NearFieldParameters near;
  const std::map<std::string, HairHairSolver> solvers = {{"grid", HairHairSolver::Grid},
                                                         {"near", HairHairSolver::GridAndNearField},
                                                         {"coupled", HairHairSolver::Coupled}};
  const std::string solverName = args.text("solver", "grid");
  if (s && !solvers.count(solverName))
    s = Status::Error("solver=" + solverName + " is not one of grid, near, coupled.");
  if (s)
    s = args.number("fraction", grid.volumeFraction, 1e-4, 0.9, grid.volumeFraction);
  if (s)
    s = args.number("volume", grid.volume, 0, 1, grid.volume);
  if (s)
    s = args.number("grid_friction", grid.friction, 0, 1e4, grid.friction);
  if (s)
    s = args.number("cell", grid.cellSize, 0, 1, grid.cellSize);
  if (s)
    s = args.integer("sweeps", near.sweeps, 1, 1000, near.sweeps);
  if (s)
    s = args.number("near_margin", near.margin, 0, 4, near.margin);
  if (s)
    s = args.number("piece", near.pieceLength, 1e-4, 0.1, near.pieceLength);
  if (s)
    s = openOutput(args, out);
  if (!s)
  {
    std::cerr << "hair_study hairhair: " << s.message() << "\n";
    return 2;
  }
  const int frames = static_cast<int>(std::lround(duration * 30));
  out << "time_s,pass_throughs,nodes_inside,max_depth_m,contacts,pressed,sweeps,rounds,"
         "max_penetration_m,wall_s\n";
  long passTotal = 0, passLater = 0, insideSum = 0;
  double deepest = 0, deepestPair = 0, wall = 0;
  // Every half second on stdout: the pass-throughs since the previous line, the nodes
  // inside the body and the deepest of them at that frame, the pairs solved and pressed.
  long passWindow = 0;
  std::printf("| t (s) | pass-throughs in the last 0.5 s | nodes inside | deepest (mm) | pairs "
              "solved | pressed |\n|---|---|---|---|---|---|\n");
  auto row =
      [&](double t, long passes, long inside, double depth, const HairHairStats* hs, double seconds)
  {
    passWindow += passes;
    if (std::abs(t * 2 - std::round(t * 2)) < 1e-6)
    {
      std::printf("| %.1f | %ld | %ld | %.2f | %ld | %ld |\n", t, passWindow, inside, 1e3 * depth,
                  hs ? hs->contacts : 0L, hs ? hs->active : 0L);
      passWindow = 0;
    }
    out << t << "," << passes << "," << inside << "," << depth << "," << (hs ? hs->contacts : 0)
        << "," << (hs ? hs->active : 0) << "," << (hs ? hs->sweeps : 0) << ","
        << (hs ? hs->rounds : 0) << "," << (hs ? hs->maxPenetration : 0) << "," << seconds << "\n";
    passTotal += passes;
    passLater += t > 1 + 1e-9 ? passes : 0;
    insideSum += inside;
    deepest = std::max(deepest, depth);
    deepestPair = std::max(deepestPair, hs ? hs->maxPenetration : 0);
    wall += seconds;
  };
  if (sceneName == "demo")
  {
    BundledBody body;
    if (s = loadBundledBody(HAIR_DATA_DIR, body); !s)
    {
      std::cerr << "hair_study hairhair: " << s.message() << "\n";
      return 1;
    }
    std::vector<GuideStrand> guides;
    if (s = demoGuides(body, guidesCount, 10, guides); !s)
    {
      std::cerr << "hair_study hairhair: " << s.message() << "\n";
      return 1;
    }
    {
      const std::map<std::string, HairType> types = {{"smooth", HairType::Smooth},
                                                     {"wavy", HairType::Wavy},
                                                     {"curly", HairType::Curly},
                                                     {"fuzzy", HairType::Fuzzy}};
      const auto type = types.find(args.text("hair", "wavy"));
      if (type == types.end())
      {
        std::cerr << "hair_study hairhair: hair=" << args.text("hair", "")
                  << " is not one of smooth, wavy, curly, fuzzy.\n";
        return 2;
      }
      for (GuideStrand& g : guides)
        g.hair = HairParameters::preset(type->second);
    }
    SimulationOptions o;
    o.threads = threads;
    o.contacts.enabled = bodyContacts == 1;
    o.superHelix.hairHairEnabled = withContacts == 1;
    o.superHelix.hairHair = p;
    o.superHelix.hairHairSolver = solvers.at(solverName);
    o.superHelix.hairGrid = grid;
    o.superHelix.nearField = near;
    Simulation sim;
    if (s = sim.initialize(guides, demoScene(body), o); !s)
    {
      std::cerr << "hair_study hairhair: " << s.message() << "\n";
      return 1;
    }
    // The contact distance the pass-throughs are counted within: the run's (automatic or
    // given) thickness, the same with contacts off.
    double radius = 0;
    for (const GuideStrand& g : guides)
      radius += g.hair.radius / static_cast<double>(guides.size());
    const double thickness =
        p.thickness > 0 ? p.thickness : HairHairParameters::automaticThickness(radius, guidesCount);
    const double R = 2 * thickness;
    const auto* model = dynamic_cast<const SuperHelixModel*>(&sim.model());
    for (int f = 1; f <= frames; ++f)
    {
      const auto t0 = std::chrono::steady_clock::now();
      if (s = sim.advanceTo(f + 1); !s)
      {
        std::cerr << "hair_study hairhair: " << s.message() << "\n";
        return 1;
      }
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      HairHairStats hhStats;
      if (o.superHelix.hairHairSolver == HairHairSolver::Coupled)
        hhStats = model->hairHair().stats();
      else
      {
        // The near field's, in the columns of the coupled solve's: pairs tracked, acting,
        // sweeps, pairs found crossed (rounds), the largest gap missing after the sweeps.
        const NearFieldStats& n = model->nearField().stats();
        hhStats.contacts = n.tracked;
        hhStats.active = n.active;
        hhStats.sweeps = n.sweeps;
        hhStats.rounds = static_cast<int>(n.flipped);
        hhStats.maxPenetration = std::max(0.0, n.deficit);
      }
      const auto found = findPassThroughs(polylines(sim, f - 1), polylines(sim, f), R);
      const long passes = static_cast<long>(found.size());
      row(sim.frame(f).time, passes, sim.contacts()[f], sim.maxDepth()[f],
          withContacts ? &hhStats : nullptr, seconds);
    }
    const std::map<std::string, double> e = sim.model().energy().values();
    // Where the hair ends and how packed it is: the guides' mean tip height at the end, and
    // the volume fraction at their samples as the grid last saw it (with the grid on).
    double tip = 0;
    const auto lines = polylines(sim, frames);
    for (const auto& l : lines)
      tip += l.back().y() / static_cast<double>(lines.size());
    std::vector<double> fractions;
    if (withContacts && o.superHelix.hairHairSolver != HairHairSolver::Coupled)
      for (const SuperHelix& h : model->strands())
        for (const StrandSample& q : h.samples())
          fractions.push_back(model->hairGrid().fraction(q.position));
    std::sort(fractions.begin(), fractions.end());
    auto pct = [&](double p)
    { return fractions.empty() ? 0.0 : fractions[std::size_t(p * (fractions.size() - 1))]; };
    std::printf("mean tip height %.4f m; volume fraction at the samples: median %.3g, 95th "
                "pct %.3g, largest %.3g\n",
                tip, pct(0.5), pct(0.95), pct(1.0));
    std::printf("demo, %d guides, hair-hair %s (thickness %.3g mm): %ld pass-throughs over %d "
                "frames, %ld after 1 s; body: mean %.1f nodes inside, deepest %.2f mm; deepest "
                "pair %.2f mm of %.2f mm; %.1f s\n",
                guidesCount, withContacts ? "on" : "off", 1e3 * thickness, passTotal, frames,
                passLater, double(insideSum) / frames, 1e3 * deepest, 1e3 * deepestPair, 1e3 * R,
                wall);
    std::printf("energy (J):");
    for (const auto& [name, value] : e)
      std::printf(" %s %.4g", name.c_str(), value);
    std::printf("; |residual| / external work %.3g\n",
                std::abs(e.at("residual")) / std::max(1e-300, std::abs(e.at("external_work"))));
    return 0;
  }
  // The dense clump of the hair–hair tests (ClumpScene: 50 guides on a 12 mm disc, squeezed
  // by a converging flow, the root disc shaken 1 cm at 3 Hz from 3 s), ν = 2e-4.
  const double R = 2 * p.thickness;
  ClumpSpec spec;
  spec.hair.airFriction = 2e-4;
  std::vector<SuperHelix> strands;
  HairHairContacts contacts;
  if (s = initializeClump(spec, strands); s)
    s = contacts.setParameters(p);
  auto drawn = [&]()
  {
    std::vector<std::vector<Eigen::Vector3d>> lines(strands.size());
    for (size_t k = 0; k < strands.size(); ++k)
      strands[k].polyline(4, lines[k]);
    return lines;
  };
  std::vector<std::vector<Eigen::Vector3d>> before = drawn();
  for (int f = 1; s && f <= frames; ++f)
  {
    const auto t0 = std::chrono::steady_clock::now();
    s = withContacts ? stepStrandsWithContacts(strands, contacts, 1.0 / 30, threads)
                     : stepStrands(strands, 1.0 / 30, threads);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::vector<std::vector<Eigen::Vector3d>> after = drawn();
    row(strands[0].time(), static_cast<long>(findPassThroughs(before, after, R).size()), 0, 0,
        withContacts ? &contacts.stats() : nullptr, seconds);
    before = std::move(after);
  }
  if (!s)
  {
    std::cerr << "hair_study hairhair: " << s.message() << "\n";
    return 1;
  }
  double work = 0, residual = 0;
  for (const SuperHelix& h : strands)
  {
    work += std::abs(h.energy().total.rootWork) + std::abs(h.energy().total.windWork);
    residual += h.energy().total.residual;
  }
  std::printf("clump, hair-hair %s: %ld pass-throughs over %d frames; deepest pair %.3f mm of "
              "%.2f mm; %.1f s; residual %.3g J of |root| + |wind| work %.3g J\n",
              withContacts ? "on" : "off", passTotal, frames, 1e3 * deepestPair, 1e3 * R, wall,
              residual, work);
  return 0;
}

int usage()
{
  std::cerr
      << "usage: hair_study <convergence|buckling|release|scene|integrator|accuracy|workprecision|"
         "order|clump|demo|"
         "oscillation|"
         "pendulum|hairhair> out=<file> "
         "[key=value ...]\n"
         "  convergence [ns=1,2,...,40] [length=0.1]\n"
         "  buckling    [n=10] [loads=0.1,...,1.5 (x P_cr)] [tilt=1e-3] [length=0.1]\n"
         "              [dt=100] [maxsteps=20000] [tol=1e-13]\n"
         "  release     [n=10] [dt=1/30] [duration=2] [length=0.3] [preset=wavy]\n"
         "  scene       [strands=6] [n=10] [duration=1] [dt=1/30] [model=super-helix]\n"
         "              (out=<file>.h5)\n"
         "  integrator  [quick=0|1] [demo=0|1] [guides=200] [seconds=5]\n"
         "  workprecision [ns=5,10,20,40] [tolerances=0.05,0.02,0.01,0.005]\n"
         "  order       [integrators=semi-implicit,bdf2] [friction=0.3] [lookahead=1/30]\n"
         "              [seconds=1] [body=head|sphere]\n"
         "              [finest=64] [reference=2048 (steps per frame)]\n"
         "  accuracy    [runs=semi-implicit:0,bdf2:0 (integrator[:tolerance[:steps per "
         "frame]],...)]\n"
         "              [reference=semi-implicit:0.001] [cache=<csv>] [guides=200] [seconds=2]\n"
         "              [threads=2] [body=1] [grid=1]\n"
         "  clump       [quick=0|1] [strands=50] [duration=6] [ramp=3] [updates=1]\n"
         "              [gammas=5e-11,1e-10,2e-10,5e-10] [thickness=1.2e-3]\n"
         "              [contacts=1] [perlength=0] [reflength=0.01 (m, with perlength=1)]\n"
         "              [amplitude=0.01] [frequency=3]\n"
         "  demo        [model=projective] [strands=200] [n=40] [duration=5] [dt=1/30]\n"
         "              [threads=2] [data=<Data dir>] (out=<file>.h5)\n"
         "  oscillation [summary=<csv>] [shapes=<csv>] [preset=curly] [length=0.3] [n=40]\n"
         "              [gammas=5e-11,1e-10,5e-10] [frequencies=3] [amplitude=0.01] [nu=]\n"
         "              [duration=8] [fade=1] [window=2] [dt=1/2000] [rate=200]\n"
         "              [integrator=semi-implicit]\n"
         "  pendulum    [presets=smooth,fuzzy] [nus=0,5e-6,1e-5,2e-5,5e-5] [length=0.3]\n"
         "              [n=10] [duration=8] [dt=1/2000] [push=0.02] [frequency=1]\n"
         "              [rate=200] [integrator=semi-implicit]\n"
         "  hairhair    [scene=demo|clump] [contacts=1] [body=1] [guides=200] [threads=2]\n"
         "              [duration=5 (demo), 6 (clump)] [thickness=0 (demo), 1.2e-3 (clump)]\n"
         "              [stiffness=1] [friction=0.3] [margin=0.25] [iterations=10]\n";
  return 2;
}

} // namespace

int main(int argc, char** argv)
{
  if (argc < 2)
    return usage();
  const std::string study = argv[1];
  const std::map<std::string, std::pair<std::set<std::string>, int (*)(const Arguments&)>> studies =
      {{"convergence", {{"out", "ns", "length"}, convergence}},
       {"buckling", {{"out", "n", "loads", "tilt", "length", "dt", "maxsteps", "tol"}, buckling}},
       {"release", {{"out", "n", "dt", "duration", "length", "preset"}, release}},
       {"scene", {{"out", "strands", "n", "duration", "dt", "model"}, scene}},
       {"integrator", {{"out", "quick", "demo", "guides", "seconds"}, integrator}},
       {"workprecision", {{"out", "ns", "tolerances"}, workPrecision}},
       {"order",
        {{"out", "finest", "reference", "seconds", "friction", "lookahead", "integrators", "body"},
         order}},
       {"accuracy",
        {{"out", "guides", "threads", "seconds", "runs", "reference", "cache", "body", "grid"},
         accuracy}},
       {"demo", {{"out", "strands", "n", "duration", "dt", "model", "threads", "data"}, demo}},
       {"oscillation",
        {{"out", "summary", "shapes", "preset", "integrator", "length", "n", "gammas",
          "frequencies", "amplitude", "nu", "duration", "fade", "window", "dt", "rate"},
         oscillation}},
       {"pendulum",
        {{"out", "integrator", "presets", "length", "n", "nus", "duration", "dt", "push",
          "frequency", "rate"},
         pendulum}},
       {"clump",
        {{"out", "quick", "strands", "duration", "ramp", "gammas", "updates", "thickness",
          "contacts", "perlength", "reflength", "amplitude", "frequency"},
         clump}},
       {"hairhair",
        {{"out",       "scene",         "contacts", "body",   "guides",      "threads", "duration",
          "thickness", "stiffness",     "friction", "margin", "iterations",  "solver",  "fraction",
          "volume",    "grid_friction", "cell",     "sweeps", "near_margin", "hair",    "piece"},
         hairhair}}};
  const auto it = studies.find(study);
  if (it == studies.end())
  {
    std::cerr << "hair_study: unknown study '" << study << "'.\n";
    return usage();
  }
  Arguments args;
  if (Status s = args.parse(argc, argv, it->second.first); !s)
  {
    std::cerr << "hair_study " << study << ": " << s.message() << "\n";
    return 2;
  }
  return it->second.second(args);
}
