// hair_study convergence: see Tools/studies/Studies.h and docs/study-*.md.
#include "Studies.h"

using namespace hair;
using namespace hair::tools;

namespace
{

constexpr double Beta1L = 1.8751041, Beta2L = 4.6940911; // clamped–free beam (Rao §11.5)

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
  const std::vector<double> ns = args.list("ns");
  const double length = args.number("length");
  std::ofstream out;
  Status s = openOutput(args, out);
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

} // namespace

namespace hair::tools
{
Study convergenceStudy()
{
  return {
      "convergence", "a straight clamped cantilever against Euler-Bernoulli as N grows",
      Keys{outKey("<csv>"),
           listKey("ns", "1,2,3,4,5,6,8,10,13,16,20,25,32,40", 1, 400, "elements N of each run"),
           numberKey("length", "0.1", 1e-3, 10, "m, the cantilever's length")},
      convergence};
}
} // namespace hair::tools
