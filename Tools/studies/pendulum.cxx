// hair_study pendulum: see Tools/studies/Studies.h and docs/study-*.md.
#include "Studies.h"

using namespace hair;
using namespace hair::tools;

namespace
{

int pendulum(const Arguments& args)
{
  const int n = args.integer("n");
  const double length = args.number("length"), duration = args.number("duration"),
               dt = args.number("dt"), push = args.number("push"),
               frequency = args.number("frequency"), rate = args.number("rate");
  const std::vector<double> nus = args.list("nus");
  std::vector<std::string> presets;
  std::ofstream out;
  Integrator integrator = Integrator::SemiImplicit;
  Status s = integratorByName(args.text("integrator"), integrator);
  if (s)
  {
    std::stringstream ss(args.text("presets"));
    std::string item;
    HairType type;
    while (s && std::getline(ss, item, ','))
      if (s = presetByName(item, type); s)
        presets.push_back(item);
  }
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

} // namespace

namespace hair::tools
{
Study pendulumStudy()
{
  return {
      "pendulum", "a pendulum released from a push: its damping time against the air friction",
      Keys{outKey("<csv>"), integratorKey(),
           textKey("presets", "smooth,fuzzy", "hair presets, comma-separated"),
           numberKey("length", "0.3", 1e-3, 10, "m"), integerKey("n", "10", 1, 400, "elements"),
           listKey("nus", "0,5e-6,1e-5,2e-5,5e-5", 0, 1, "kg/(m s), air frictions, one run each"),
           numberKey("duration", "8", 0.1, 1000, "s"),
           numberKey("dt", "1/2000", 1e-6, 1.0 / 30, "s, the step"),
           numberKey("push", "0.02", 0, 1, "m, the root's push"),
           numberKey("frequency", "1", 0.01, 100, "Hz, the push's"),
           numberKey("rate", "200", 1, 1e6, "rows per second")},
      pendulum};
}
} // namespace hair::tools
