// hair_study oscillation: see Tools/studies/Studies.h and docs/study-*.md.
#include "Studies.h"

using namespace hair;
using namespace hair::tools;

namespace
{

// ---------------------------------------------------------------------------------------
// Study 5 (issue 23): the Super-Helices paper's own experiments (Bertails et al. 2006, §4.2,
// figs. 6 and 7), one Super-Helix standing for a clump: (a) the root oscillated vertically,
// the clump's extent ℓ_A over time for several internal frictions γ; (b) its shape over a
// period; (c) a pendulum released from a push, its damping time against the air friction ν.
// docs/study-oscillation.md.

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
  const int n = args.integer("n");
  const double length = args.number("length"), amplitude = args.number("amplitude"),
               duration = args.number("duration"), dt = args.number("dt"),
               fade = args.number("fade"), rate = args.number("rate"),
               window = args.number("window");
  const double nu = args.number("nu", -1); // -1: the preset's
  const std::vector<double> gammas = args.list("gammas"), frequencies = args.list("frequencies");
  HairType type = HairType::Curly;
  Integrator integrator = Integrator::SemiImplicit;
  std::ofstream out;
  Status s = presetByName(args.text("preset"), type);
  if (s)
    s = integratorByName(args.text("integrator"), integrator);
  if (s && window > duration - fade)
    s = Status::Error("window=" + args.written("window") +
                      " is longer than the steady part of the run (duration - fade).");
  if (s && 2 * fade > duration)
    s = Status::Error("fade is more than half the duration.");
  if (s)
    s = openOutput(args, out);
  std::ofstream summary, shapes;
  if (s && args.has("summary"))
  {
    summary.open(args.text("summary"));
    if (!summary)
      s = Status::Error("cannot write '" + args.text("summary") + "'.");
    summary.precision(17);
  }
  if (s && args.has("shapes"))
  {
    shapes.open(args.text("shapes"));
    if (!shapes)
      s = Status::Error("cannot write '" + args.text("shapes") + "'.");
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

} // namespace

namespace hair::tools
{
Study oscillationStudy()
{
  return {
      "oscillation",
      "one Super-Helix as a clump, its root oscillated vertically (Bertails et al. 2006)",
      Keys{outKey("<csv>"), textKey("summary", "", "one row per run (optional)").as("<csv>"),
           textKey("shapes", "", "the shapes over a period (optional)").as("<csv>"),
           choiceKey("preset", "curly", {"smooth", "wavy", "curly", "fuzzy"}, "the hair preset"),
           integratorKey(), numberKey("length", "0.3", 1e-3, 10, "m"),
           integerKey("n", "40", 1, 400, "elements"),
           listKey("gammas", "5e-11,1e-10,5e-10", 0, 1e-6, "internal frictions, one run each"),
           listKey("frequencies", "3", 0.01, 1000, "Hz, the root's, one run each"),
           numberKey("amplitude", "0.01", 0, 1, "m, the root's vertical oscillation"),
           numberKey("nu", "the preset's", 0, 1, "kg/(m s), the air friction").computedDefault(),
           numberKey("duration", "8", 0.1, 1000, "s"),
           numberKey("fade", "1", 0, 100, "s, the oscillation's fade-in"),
           numberKey("window", "2", 0.01, 1000, "s, the steady window measured at the end"),
           numberKey("dt", "1/2000", 1e-6, 1.0 / 30, "s, the step"),
           numberKey("rate", "200", 1, 1e6, "rows per second")},
      oscillation};
}
} // namespace hair::tools
