// hair_study buckling: see Tools/studies/Studies.h and docs/study-*.md.
#include "Studies.h"

using namespace hair;
using namespace hair::tools;

namespace
{

// ---------------------------------------------------------------------------------------
// Study 3: Euler buckling of a clamped–free column under a dead axial tip load.

int buckling(const Arguments& args)
{
  const int n = args.integer("n"), maxSteps = args.integer("maxsteps");
  const double tilt = args.number("tilt"), length = args.number("length"), dt = args.number("dt"),
               tol = args.number("tol");
  const std::vector<double> loads = args.list("loads");
  std::ofstream out;
  Status s = openOutput(args, out);
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

} // namespace

namespace hair::tools
{
Study bucklingStudy()
{
  return {
      "buckling", "Euler buckling of a clamped-free column under a dead axial tip load",
      Keys{outKey("<csv>"), integerKey("n", "10", 1, 400, "elements"),
           listKey("loads", "0.1,0.2,0.3,0.4,0.5,0.6,0.7,0.8,0.85,0.9,0.95,1,1.05,1.1,1.2,1.3,1.5",
                   0, 10, "tip loads, multiples of the critical load P_cr"),
           numberKey("tilt", "1e-3", 0, 0.1, "rad, the load's tilt (the imperfection)"),
           numberKey("length", "0.1", 1e-3, 10, "m"),
           numberKey("dt", "100", 1e-6, 1e6, "s, the step of the static iteration"),
           integerKey("maxsteps", "20000", 1, 10000000, "steps at most per load"),
           numberKey("tol", "1e-13", 0, 1, "the static iteration's tolerance")},
      buckling};
}
} // namespace hair::tools
