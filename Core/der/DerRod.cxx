// The Discrete Elastic Rod: its spec, initial state, backward Euler step solved by Newton's
// method on the incremental potential, energy budget and continuation
// (docs/discrete-elastic-rods.md).
#include "der/DerRod.h"

#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

namespace hair
{

struct DerRod::Solver
{
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
  bool analyzed = false;
};

// What one step's potential reads besides the unknowns.
struct DerRod::Step
{
  double h = 0;                          // 0: the elastic energy alone (no inertia, no dissipation)
  Eigen::VectorXd q0, v0, target;        // qⁿ, vⁿ and the inertial target qⁿ + h vⁿ
  std::vector<StencilData> stencils;     // per node (0 and N unused)
  std::vector<Eigen::Vector3d> air;      // air velocity per node
  std::vector<ContactResponse> contacts; // per node, empty without a hook
};

namespace
{
// Deterministic on every platform (std::uniform_real_distribution is not); the Super-Helix's.
double uniformSigned(std::mt19937& g)
{
  return 2.0 * (static_cast<double>(g()) / 4294967296.0) - 1.0;
}

// The nearest angle to `near` equal to `angle` modulo 2π.
double unwrap(double angle, double near)
{
  return angle + 2 * M_PI * std::round((near - angle) / (2 * M_PI));
}

Eigen::Matrix3d symmetric(const Eigen::Matrix3d& m)
{
  return 0.5 * (m + m.transpose());
}

constexpr int StateVersion = 1;
constexpr int EnergyValues = 7 + 2 * 9;
} // namespace

DerRod::DerRod() : Factor(std::make_unique<Solver>()) {}
DerRod::~DerRod() = default;
// The factorization's pattern is re-analyzed on the copy's first step (the same numbers).
DerRod::DerRod(const DerRod& o)
    : Spec(o.Spec), Initialized(o.Initialized), Time(o.Time), Q(o.Q), V(o.V), Mass(o.Mass),
      Voronoi(o.Voronoi), Tangents(o.Tangents), Directors(o.Directors), RefTwist(o.RefTwist),
      Rest(o.Rest), Stiffness(o.Stiffness), StretchStiffness(o.StretchStiffness),
      MinEdge(o.MinEdge), Free(o.Free), FreeCount(o.FreeCount), Energy(o.Energy),
      LastIterations(o.LastIterations), Contacts(o.Contacts), Factor(std::make_unique<Solver>())
{
}
DerRod& DerRod::operator=(const DerRod& o)
{
  if (this == &o)
    return *this;
  Spec = o.Spec;
  Initialized = o.Initialized;
  Time = o.Time;
  Q = o.Q;
  V = o.V;
  Mass = o.Mass;
  Voronoi = o.Voronoi;
  Tangents = o.Tangents;
  Directors = o.Directors;
  RefTwist = o.RefTwist;
  Rest = o.Rest;
  Stiffness = o.Stiffness;
  StretchStiffness = o.StretchStiffness;
  MinEdge = o.MinEdge;
  Free = o.Free;
  FreeCount = o.FreeCount;
  Energy = o.Energy;
  LastIterations = o.LastIterations;
  Contacts = o.Contacts;
  Factor = std::make_unique<Solver>();
  return *this;
}

DerSpec DerSpec::uniform(double length, int edges, const HairParameters& hair)
{
  DerSpec s;
  s.hair = hair;
  if (edges > 0)
    s.edgeLengths.assign(static_cast<std::size_t>(edges), length / edges);
  return s;
}

Status DerSpec::validate() const
{
  const std::string who = "strand '" + name + "' (id " + std::to_string(id) + "): ";
  const std::size_t n = edgeLengths.size();
  if (n < 2)
    return Status::Error(who + "the number of edges N is " + std::to_string(n) +
                         "; a discrete elastic rod needs N >= 2 (one interior node), give at "
                         "least two edge lengths.");
  if (clampTip && n < 4)
    return Status::Error(who +
                         "a rod clamped at both ends needs N >= 4 edges (a free node "
                         "between its clamped end edges), not " +
                         std::to_string(n) + ".");
  if (!std::isfinite(tipTwist))
    return Status::Error(who + "the tip's twist is not finite; give an angle in radians.");
  if (n > 100000)
    return Status::Error(who + "N = " + std::to_string(n) +
                         " edges is more than 100000; give fewer, longer edges.");
  for (std::size_t j = 0; j < n; ++j)
    if (!(std::isfinite(edgeLengths[j]) && edgeLengths[j] > 0))
    {
      std::ostringstream s;
      s << who << "edge " << j << " has rest length " << edgeLengths[j]
        << "; every edge length must be finite and > 0 metres.";
      return Status::Error(s.str());
    }
  if (!restStrains.empty())
  {
    if (restStrains.size() != 3 * (n - 1))
      return Status::Error(who + "the rest strains have " + std::to_string(restStrains.size()) +
                           " values; give 3 per interior node (τ, κ1, κ2 per metre), " +
                           std::to_string(3 * (n - 1)) + " in all, or none.");
    for (double v : restStrains)
      if (!std::isfinite(v))
        return Status::Error(who + "the rest strains are not finite.");
  }
  if (!initialNodes.empty())
  {
    if (initialNodes.size() != n + 1)
      return Status::Error(who + "the initial shape has " + std::to_string(initialNodes.size()) +
                           " nodes; give N + 1 = " + std::to_string(n + 1) + ", or none.");
    for (std::size_t k = 0; k < initialNodes.size(); ++k)
      if (!initialNodes[k].allFinite() ||
          (k > 0 && (initialNodes[k] - initialNodes[k - 1]).norm() == 0))
        return Status::Error(who + "initial node " + std::to_string(k) +
                             " is not finite or coincides with the previous one.");
  }
  if (!initialTwists.empty())
  {
    if (initialTwists.size() != n || initialNodes.empty())
      return Status::Error(who + "the initial twists are " + std::to_string(initialTwists.size()) +
                           " values; give one per edge (" + std::to_string(n) +
                           ") with the initial nodes, or none.");
    for (double v : initialTwists)
      if (!std::isfinite(v))
        return Status::Error(who + "the initial twists are not finite.");
  }
  if (Status st = hair.validate(); !st)
    return Status::Error(who + st.message());
  // The natural curl must be resolved by the edges: an interior node's rest curvature κ̄ l̄
  // is the discrete 2 tan(φ/2) of a turning angle φ, which reaches 90° at 2 and 180° at
  // infinity; beyond 90° the rest shape folds back within two edges, its discretisation
  // error (~ φ²/12) passes 20 %, and the twists' Newton solve stalls near the fold (24
  // mixed demo guides of 5 edges: the fuzzy preset's 530 rad/m turned by 160° per edge).
  {
    const double helix = hair.largestNaturalBending();
    double worst = 0, kappa = 0;
    std::size_t node = 0;
    for (std::size_t i = 1; i < n; ++i)
    {
      const double k = restStrains.empty()
                           ? helix
                           : std::hypot(restStrains[3 * (i - 1) + 1], restStrains[3 * (i - 1) + 2]);
      const double turn = k * 0.5 * (edgeLengths[i - 1] + edgeLengths[i]);
      if (turn > worst)
        worst = turn, kappa = k, node = i;
    }
    if (worst > MaxRestTurn)
    {
      std::ostringstream s;
      s << who << "its natural curvature " << kappa << " /m turns interior node " << node << " by "
        << 2 * std::atan(0.5 * worst) * 180 / M_PI
        << "°; a discrete elastic rod follows a curl only with edges that turn by at most "
           "90° (κ̄ l̄ <= 2): give at least "
        << static_cast<long>(std::ceil(n * worst / MaxRestTurn))
        << " edges over its length, or a less curly hair.";
      return Status::Error(s.str());
    }
  }
  if (!gravity.allFinite())
    return Status::Error(who + "gravity is not finite; give a vector in m/s².");
  if (!wind.allFinite())
    return Status::Error(who + "wind is not finite; give a velocity in m/s.");
  if (!tipForce.allFinite())
    return Status::Error(who + "the tip force is not finite; give a force in N.");
  if (!(solver.stepTolerance > 0 && solver.stepTolerance < 1) ||
      !(solver.gradientTolerance > 0 && solver.gradientTolerance < 1) || solver.maxIterations < 1)
    return Status::Error(who + "the solver options are out of range: give tolerances in (0, 1) "
                               "(defaults 1e-10) and at least one iteration (default 50).");
  return Status::Ok();
}

std::string DerRod::where(double t0, double t1) const
{
  std::ostringstream s;
  s << "strand '" << Spec.name << "' (id " << Spec.id << "), step from t = " << t0
    << " s to t = " << t1 << " s: ";
  return s.str();
}

Status DerRod::initialize(const DerSpec& spec, double time)
{
  if (Status st = spec.validate(); !st)
    return st;
  const std::string who = "strand '" + spec.name + "' (id " + std::to_string(spec.id) + ")";
  if (!std::isfinite(time))
    return Status::Error(who + ": the initial time is not finite.");
  const RootState root = spec.root ? spec.root(time) : RootState{};
  if (Status st = root.validate(); !st)
    return Status::Error(who + " at t = " + std::to_string(time) + ": " + st.message());

  const int n = static_cast<int>(spec.edgeLengths.size());
  const Eigen::Vector3d t0 = root.orientation.col(0);
  std::vector<Eigen::Vector3d> x(n + 1);
  x[0] = root.position;
  for (int k = 1; k <= n; ++k)
    x[k] = x[k - 1] + spec.edgeLengths[k - 1] * t0;
  if (!spec.initialNodes.empty())
  {
    const double tol = 1e-9 * spec.edgeLengths[0];
    if ((spec.initialNodes[0] - x[0]).norm() > tol || (spec.initialNodes[1] - x[1]).norm() > tol)
      return Status::Error(who + ": the initial shape's first two nodes are not the clamp's "
                                 "(root position, and root position + |ē_0| root tangent); "
                                 "resample the curve from the root along its tangent.");
    x = spec.initialNodes;
  }
  Eigen::Matrix3Xd tangents(3, n), directors(3, n);
  for (int j = 0; j < n; ++j)
  {
    tangents.col(j) = (x[j + 1] - x[j]).normalized();
    if (j == 0)
      directors.col(0) = root.orientation.col(1);
    else
    {
      if (tangents.col(j - 1).dot(tangents.col(j)) < -1 + 1e-12)
        return Status::Error(who + ": the initial shape folds back on itself at node " +
                             std::to_string(j) + "; give a curve without a 180° turn.");
      const Eigen::Vector3d d =
          parallelTransport(directors.col(j - 1), tangents.col(j - 1), tangents.col(j));
      directors.col(j) = (d - d.dot(tangents.col(j)) * tangents.col(j)).normalized();
    }
  }

  Spec = spec;
  Time = time;
  Q.resize(4 * n + 3);
  V.resize(4 * n + 3);
  for (int k = 0; k <= n; ++k)
  {
    Q.segment<3>(4 * k) = x[k];
    V.segment<3>(4 * k) = root.velocity + root.angularVelocity.cross(x[k] - root.position);
    if (k < n)
    {
      Q[4 * k + 3] = !spec.initialTwists.empty() ? spec.initialTwists[k]
                     : spec.clampTip             ? spec.tipTwist * k / (n - 1)
                                                 : 0.0;
      V[4 * k + 3] = root.angularVelocity.dot(tangents.col(k));
    }
  }
  Tangents = tangents;
  Directors = directors;
  RefTwist = Eigen::VectorXd::Zero(n + 1);

  const double rhoS = Spec.hair.linearDensity();
  const double polar = Spec.hair.rotaryInertia()[0];
  Voronoi.resize(n + 1);
  Mass.resize(4 * n + 3);
  MinEdge = *std::min_element(Spec.edgeLengths.begin(), Spec.edgeLengths.end());
  for (int k = 0; k <= n; ++k)
  {
    Voronoi[k] = 0.5 * ((k > 0 ? Spec.edgeLengths[k - 1] : 0) + (k < n ? Spec.edgeLengths[k] : 0));
    Mass.segment<3>(4 * k).setConstant(rhoS * Voronoi[k]);
    if (k < n)
      Mass[4 * k + 3] = polar * Spec.edgeLengths[k];
  }
  Stiffness = Spec.hair.stiffness();
  StretchStiffness = Spec.hair.youngModulus * Spec.hair.area();

  const Eigen::Vector3d natural = Spec.hair.naturalCurvature();
  std::mt19937 gen(Spec.seed);
  Rest = Eigen::Matrix3Xd::Zero(3, n + 1);
  for (int i = 1; i < n; ++i)
  {
    const double lbar = 0.5 * (Spec.edgeLengths[i - 1] + Spec.edgeLengths[i]);
    for (int c = 0; c < 3; ++c)
    {
      const double var = Spec.hair.curvatureVariation * uniformSigned(gen);
      const double rate =
          Spec.restStrains.empty() ? natural[c] * (1 + var) : Spec.restStrains[3 * (i - 1) + c];
      Rest(c, i) = lbar * rate;
    }
  }

  Free.assign(4 * n + 3, -1);
  FreeCount = 0;
  // The clamp's x_0, θ_0, x_1; with the tip clamped, x_{N−1}, θ_{N−1}, x_N too.
  const int last = Spec.clampTip ? 4 * (n - 1) : 4 * n + 3;
  for (int i = 7; i < last; ++i)
    Free[i] = FreeCount++;
  Factor = std::make_unique<Solver>();
  LastIterations = 0;
  Initialized = true;
  Energy = DerEnergyReport{};
  Energy.time = Time;
  updateStateEnergies(Energy);
  return Status::Ok();
}

StencilData DerRod::stencil(int i) const
{
  StencilData d;
  d.tangentA = Tangents.col(i - 1);
  d.tangentB = Tangents.col(i);
  d.directorA = Directors.col(i - 1);
  d.directorB = Directors.col(i);
  d.referenceTwist = RefTwist[i];
  d.restLength = 0.5 * (Spec.edgeLengths[i - 1] + Spec.edgeLengths[i]);
  d.rest = Rest.col(i);
  d.stiffness = Stiffness;
  return d;
}

Eigen::Vector3d DerRod::materialDirector1(int edge) const
{
  const double th = Q[4 * edge + 3];
  const Eigen::Vector3d d1 = Directors.col(edge), d2 = Tangents.col(edge).cross(d1);
  return std::cos(th) * d1 + std::sin(th) * d2;
}

Eigen::Vector3d DerRod::materialDirector2(int edge) const
{
  return Tangents.col(edge).cross(materialDirector1(edge));
}

Eigen::Vector3d DerRod::strains(int node) const
{
  return stencilStrains(Q.segment<11>(4 * (node - 1)), stencil(node)).strains;
}

double DerRod::potential(const Eigen::VectorXd& q, const Step& s, Eigen::VectorXd* gradient,
                         std::vector<Eigen::Triplet<double>>* hessian) const
{
  const int n = edgeCount();
  double phi = 0;
  if (gradient)
    gradient->setZero(q.size());
  if (hessian)
    hessian->clear();
  auto add = [&](int a, int b, double v)
  {
    const int fa = Free[a], fb = Free[b];
    if (fa >= 0 && fb >= 0)
      hessian->emplace_back(fa, fb, v);
  };

  // Bending, twisting and the viscous friction of the interior nodes.
  for (int i = 1; i < n; ++i)
  {
    const int off = 4 * (i - 1);
    const Vector11d u = q.segment<11>(off);
    if (gradient)
    {
      Vector11d g;
      Matrix11d H;
      phi += stencilEnergy(u, s.stencils[i], g, H);
      gradient->segment<11>(off) += g;
      if (hessian)
        for (int c = 0; c < 11; ++c)
          for (int r = 0; r < 11; ++r)
            add(off + r, off + c, H(r, c));
    }
    else
      phi += stencilEnergy(u, s.stencils[i]).total();
  }

  // Stretching: ½ EA |ē| (|e|/|ē| − 1)².
  const double ea = StretchStiffness;
  for (int j = 0; j < n; ++j)
  {
    const int a = 4 * j, b = 4 * j + 4;
    const Eigen::Vector3d e = q.segment<3>(b) - q.segment<3>(a);
    const double l = e.norm(), lb = Spec.edgeLengths[j], strain = l / lb - 1;
    phi += 0.5 * ea * lb * strain * strain;
    if (gradient)
    {
      const Eigen::Vector3d t = e / l;
      gradient->segment<3>(a) -= ea * strain * t;
      gradient->segment<3>(b) += ea * strain * t;
      if (hessian)
      {
        const Eigen::Matrix3d tt = t * t.transpose();
        const Eigen::Matrix3d K =
            ea / lb * tt + ea * strain / l * (Eigen::Matrix3d::Identity() - tt);
        for (int c = 0; c < 3; ++c)
          for (int r = 0; r < 3; ++r)
          {
            add(a + r, a + c, K(r, c));
            add(b + r, b + c, K(r, c));
            add(a + r, b + c, -K(r, c));
            add(b + r, a + c, -K(r, c));
          }
      }
    }
  }

  // Per node: gravity and the tip load (measured from qⁿ), inertia, air drag, contacts.
  const double h = s.h, nu = Spec.hair.airFriction;
  for (int k = 0; k <= n; ++k)
  {
    const int a = 4 * k;
    const Eigen::Vector3d dx = q.segment<3>(a) - s.q0.segment<3>(a);
    const double m = Mass[a];
    Eigen::Vector3d g = -m * Spec.gravity;
    if (k == n)
      g -= Spec.tipForce;
    phi += g.dot(dx);
    Eigen::Matrix3d K = Eigen::Matrix3d::Zero();
    if (h > 0)
    {
      const Eigen::Vector3d r = q.segment<3>(a) - s.target.segment<3>(a);
      phi += 0.5 * m * r.squaredNorm() / (h * h);
      g += m * r / (h * h);
      K.diagonal().array() += m / (h * h);
      const double c = nu * Voronoi[k];
      const Eigen::Vector3d rel = dx / h - s.air[k];
      phi += 0.5 * h * c * rel.squaredNorm();
      g += c * rel;
      K.diagonal().array() += c / h;
      if (!s.contacts.empty())
      {
        const ContactResponse& cr = s.contacts[k];
        const double w = Voronoi[k];
        const Eigen::Matrix3d Ks = symmetric(cr.stiffness), Ds = symmetric(cr.damping);
        const Eigen::Vector3d v0 = s.v0.segment<3>(a);
        const Eigen::Vector3d dm = dx / h - cr.medium;
        phi += w * (-cr.force.dot(dx) + 0.5 * dx.dot(Ks * dx) + 0.5 * dx.dot(Ds * dx) / h -
                    (Ds * v0).dot(dx) + 0.5 * cr.drag * h * dm.squaredNorm() - cr.push.dot(dx) +
                    0.5 * cr.spring * dx.squaredNorm());
        g += w *
             (-cr.force + Ks * dx + Ds * (dx / h - v0) + cr.drag * dm - cr.push + cr.spring * dx);
        K += w * (Ks + Ds / h);
        K.diagonal().array() += w * (cr.drag / h + cr.spring);
      }
    }
    if (gradient)
    {
      gradient->segment<3>(a) += g;
      if (hessian)
        for (int c = 0; c < 3; ++c)
          for (int r = 0; r < 3; ++r)
            add(a + r, a + c, K(r, c));
    }
    if (k < n)
    {
      const double r = h > 0 ? q[a + 3] - s.target[a + 3] : 0;
      const double w = h > 0 ? Mass[a + 3] / (h * h) : 0;
      phi += 0.5 * w * r * r;
      if (gradient)
      {
        (*gradient)[a + 3] += w * r;
        if (hessian)
          add(a + 3, a + 3, w);
      }
    }
  }
  return phi;
}

Status DerRod::solveStep(double h, Eigen::VectorXd& q, Step& s, int& iterations) const
{
  (void)h;
  const DerSolverOptions& opt = Spec.solver;
  const int n = FreeCount;
  Eigen::VectorXd g, gf(n), p, trial;
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::SparseMatrix<double> H(n, n);
  double g0 = 0, gn = 0, lastStep = 0;
  const bool correct = !Spec.clampTip;
  for (int it = 0; it < opt.maxIterations; ++it)
  {
    const double phi = potential(q, s, &g, &triplets);
    if (!std::isfinite(phi) || !g.allFinite())
      return Status::Error("the incremental potential is not finite at Newton iteration " +
                           std::to_string(it) + "; the step is too large or a load is not finite.");
    for (int i = 0; i < static_cast<int>(Free.size()); ++i)
      if (Free[i] >= 0)
        gf[Free[i]] = g[i];
    gn = gf.lpNorm<Eigen::Infinity>();
    if (it == 0)
      g0 = gn;
    if (gn <= opt.gradientTolerance * g0)
    {
      iterations = it;
      return Status::Ok();
    }
    H.setFromTriplets(triplets.begin(), triplets.end());
    if (!Factor->analyzed)
    {
      Factor->ldlt.analyzePattern(H);
      Factor->analyzed = true;
    }
    // Newton's direction, with H + μI when H is not positive definite.
    double mu = 0;
    const double scale = H.diagonal().cwiseAbs().maxCoeff();
    bool descent = false;
    for (int attempt = 0; attempt < 30 && !descent; ++attempt)
    {
      if (attempt > 0)
      {
        const double next = attempt == 1 ? 1e-14 * scale : 4 * mu;
        for (int i = 0; i < n; ++i)
          H.coeffRef(i, i) += next - mu;
        mu = next;
      }
      Factor->ldlt.factorize(H);
      if (Factor->ldlt.info() != Eigen::Success || !(Factor->ldlt.vectorD().minCoeff() > 0))
        continue;
      p = -Factor->ldlt.solve(gf);
      descent = p.allFinite() && p.dot(gf) < 0;
    }
    if (!descent)
      return Status::Error("the Newton matrix could not be made positive definite at iteration " +
                           std::to_string(it) + ".");
    // A full Newton step within the tolerance: converged (at round-off the line search may
    // see no decrease, and need not).
    lastStep = 0;
    for (int i = 0; i < static_cast<int>(Free.size()); ++i)
      if (Free[i] >= 0)
        lastStep = std::max(lastStep, std::abs(p[Free[i]]) / (i % 4 == 3 ? 1 : MinEdge));
    // The full step with its edges' lengths corrected to second order (correctStretch): a
    // strand swinging through a step turns its edges, and the plain linear step, stretched
    // along the chords, was cut back by the stiff stretching to a percent of an edge an
    // iteration (49 iterations a step on the demo's shake against 9.1). When that full step
    // does not decrease Φ enough, or H needed μ: backtracking (Armijo) on the plain step.
    const double slope = p.dot(gf);
    auto decreases = [&](double alpha, bool corrected)
    {
      trial = q;
      for (int i = 0; i < static_cast<int>(Free.size()); ++i)
        if (Free[i] >= 0)
          trial[i] += alpha * p[Free[i]];
      if (corrected)
        correctStretch(q, p, alpha, trial);
      const double next = potential(trial, s, nullptr, nullptr);
      return std::isfinite(next) &&
             next <= phi + 1e-4 * alpha * slope + 1e-14 * (std::abs(phi) + std::abs(next));
    };
    bool accepted = correct && mu == 0 && decreases(1, true);
    double alpha = 1;
    for (int ls = 0; ls < 40 && !accepted; ++ls, alpha *= 0.5)
      accepted = decreases(alpha, false);
    if (accepted)
      q = trial;
    if (lastStep <= opt.stepTolerance)
    {
      iterations = it + 1;
      return Status::Ok();
    }
    if (!accepted)
      return Status::Error("the line search found no decrease at Newton iteration " +
                           std::to_string(it) + " (gradient " + std::to_string(gn) + ").");
  }
  std::ostringstream m;
  m << "Newton's method did not converge in " << opt.maxIterations << " iterations (gradient " << gn
    << " of " << g0 << " at the start, last step " << lastStep
    << " of the shortest edge); take a smaller step.";
  return Status::Error(m.str());
}

void DerRod::correctStretch(const Eigen::VectorXd& q, const Eigen::VectorXd& p, double alpha,
                            Eigen::VectorXd& trial) const
{
  const int n = edgeCount();
  Eigen::Vector3d before = trial.segment<3>(4); // node 1, clamped: not moved
  for (int k = 2; k <= n; ++k)
  {
    const int a = 4 * k, b = 4 * (k - 1);
    const Eigen::Vector3d e = q.segment<3>(a) - q.segment<3>(b);
    const double l = e.norm();
    const Eigen::Vector3d pa = p.segment<3>(Free[a]);
    const Eigen::Vector3d pb =
        Free[b] >= 0 ? Eigen::Vector3d(p.segment<3>(Free[b])) : Eigen::Vector3d::Zero();
    const double target = l + alpha * e.dot(pa - pb) / l;
    const Eigen::Vector3d linear = trial.segment<3>(a) - before;
    const double length = linear.norm();
    before = trial.segment<3>(a);
    trial.segment<3>(a) =
        trial.segment<3>(b) + (target > 0 && length > 0 ? linear * (target / length) : linear);
  }
}

void DerRod::naturalShape(std::vector<Eigen::Vector3d>& nodes, std::vector<double>& twists) const
{
  const int n = edgeCount();
  const RootState root = rootState(0);
  // The material frame (columns t, m1, m2) edge by edge.
  Eigen::Matrix3d frame = root.orientation;
  nodes.assign(1, root.position);
  nodes.push_back(root.position + Spec.edgeLengths[0] * frame.col(0));
  twists.assign(1, 0.0);
  Eigen::Vector3d carried = frame.col(1); // the root's m1, parallel-transported
  for (int i = 1; i < n; ++i)
  {
    const Eigen::Vector3d rest = Rest.col(i); // (m̄, κ̄1, κ̄2) [rad]
    const Eigen::Matrix3d halfTwist =
        Eigen::AngleAxisd(0.5 * rest[0], Eigen::Vector3d::UnitX()).toRotationMatrix();
    Eigen::Matrix3d bend = Eigen::Matrix3d::Identity();
    const double k = rest.tail<2>().norm();
    if (k > 0)
    {
      // t × t' along κ1 m1 + κ2 m2; |κb| = 2 tan(φ/2).
      const Eigen::Vector3d axis(0, rest[1] / k, rest[2] / k);
      bend = Eigen::AngleAxisd(2 * std::atan(0.5 * k), axis).toRotationMatrix();
    }
    const Eigen::Vector3d before = frame.col(0);
    frame = frame * halfTwist * bend * halfTwist;
    const Eigen::Vector3d t = frame.col(0);
    nodes.push_back(nodes.back() + Spec.edgeLengths[i] * t);
    carried = parallelTransport(carried, before, t);
    carried = (carried - carried.dot(t) * t).normalized();
    twists.push_back(twists.back() +
                     std::atan2(carried.cross(frame.col(1)).dot(t), carried.dot(frame.col(1))));
    carried = frame.col(1);
  }
}

Status DerRod::step(double h)
{
  const double t0 = Time, t1 = Time + h;
  if (!Initialized)
    return Status::Error("strand: step() before initialize().");
  if (!(std::isfinite(h) && h > 0))
    return Status::Error(where(t0, t1) + "h = " + std::to_string(h) +
                         " is not a time step; give a finite h > 0 s.");
  const RootState root = rootState(t1);
  if (Status st = root.validate(); !st)
    return Status::Error(where(t0, t1) + st.message());
  const int n = edgeCount();

  Step s;
  s.h = h;
  s.q0 = Q;
  s.v0 = V;
  s.target = Q + h * V;
  s.stencils.resize(n + 1);
  const double gamma = Spec.hair.internalFriction;
  for (int i = 1; i < n; ++i)
  {
    StencilData d = stencil(i);
    d.previous = stencilStrains(Q.segment<11>(4 * (i - 1)), d).strains;
    d.viscosity = gamma / h;
    s.stencils[i] = d;
  }
  s.air.resize(n + 1);
  for (int k = 0; k <= n; ++k)
  {
    s.air[k] = Spec.windField ? Spec.windField(Q.segment<3>(4 * k), t1) : Spec.wind;
    if (!s.air[k].allFinite())
      return Status::Error(where(t0, t1) + "the wind field is not finite at node " +
                           std::to_string(k) + ".");
  }
  if (Contacts)
  {
    std::vector<StrandSample> samples(n + 1);
    double arc = 0;
    for (int k = 0; k <= n; ++k)
    {
      samples[k].element = std::min(k, n - 1);
      samples[k].s = arc;
      samples[k].weight = Voronoi[k];
      samples[k].position = Q.segment<3>(4 * k);
      samples[k].velocity = V.segment<3>(4 * k);
      if (k < n)
        arc += Spec.edgeLengths[k];
    }
    s.contacts.assign(n + 1, ContactResponse{});
    Contacts(Spec.id, t0, samples, s.contacts);
    if (static_cast<int>(s.contacts.size()) != n + 1)
      return Status::Error(where(t0, t1) + "the contact hook changed the number of responses.");
    for (const ContactResponse& c : s.contacts)
      if (!c.force.allFinite() || !c.stiffness.allFinite() || !c.damping.allFinite() ||
          !std::isfinite(c.drag) || !std::isfinite(c.spring) || !c.medium.allFinite() ||
          !c.push.allFinite())
        return Status::Error(where(t0, t1) + "the contact hook gave a non-finite response.");
  }

  // Newton starts from the strand carried rigidly by the root's motion over the step, each
  // node moving on at its velocity relative to the root: a node at rest on a turning head
  // starts where the head takes it, not an edge's stretch behind (from qⁿ a shaken strand's
  // step took more than 50 iterations; from here 25–30).
  Eigen::VectorXd q = Q;
  {
    const RootState before = rootState(t0);
    const Eigen::Matrix3d turn = root.orientation * before.orientation.transpose();
    for (int k = 2; k <= (Spec.clampTip ? n - 2 : n); ++k)
    {
      const Eigen::Vector3d x = Q.segment<3>(4 * k), arm = x - before.position;
      const Eigen::Vector3d carried = before.velocity + before.angularVelocity.cross(arm);
      q.segment<3>(4 * k) = root.position + turn * arm + h * (V.segment<3>(4 * k) - carried);
    }
  }
  // The clamp at t1: x_0, x_1 and θ_0 (m1_0 = R e_y against the transported director).
  const Eigen::Vector3d t = root.orientation.col(0);
  if (Tangents.col(0).dot(t) < -1 + 1e-12)
    return Status::Error(where(t0, t1) + "the root turned by 180° within the step; take a "
                                         "smaller step.");
  q.segment<3>(0) = root.position;
  q.segment<3>(4) = root.position + Spec.edgeLengths[0] * t;
  const Eigen::Vector3d d1 = parallelTransport(Directors.col(0), Tangents.col(0), t);
  const Eigen::Vector3d m1 = root.orientation.col(1);
  q[3] = unwrap(std::atan2(m1.dot(t.cross(d1)), m1.dot(d1)), Q[3]);

  int iterations = 0;
  if (Status st = solveStep(h, q, s, iterations); !st)
    return Status::Error(where(t0, t1) + st.message());
  const Eigen::VectorXd v = (q - Q) / h;

  // The flows of the step.
  DerEnergyTerms e;
  Eigen::VectorXd g;
  potential(q, s, &g, nullptr);
  for (int i = 0; i < static_cast<int>(Free.size()); ++i)
    if (Free[i] < 0)
      e.rootWork += g[i] * (q[i] - Q[i]);
  const double nu = Spec.hair.airFriction;
  for (int k = 0; k <= n; ++k)
  {
    const int a = 4 * k;
    const Eigen::Vector3d dx = q.segment<3>(a) - Q.segment<3>(a), vk = v.segment<3>(a);
    const double c = nu * Voronoi[k];
    e.airDissipated += h * c * (vk - s.air[k]).squaredNorm();
    e.windWork += h * c * (s.air[k] - vk).dot(s.air[k]);
    if (!s.contacts.empty())
    {
      const ContactResponse& cr = s.contacts[k];
      const double w = Voronoi[k];
      const Eigen::Vector3d near =
          cr.force - symmetric(cr.stiffness) * dx - symmetric(cr.damping) * (vk - V.segment<3>(a));
      const Eigen::Vector3d field = cr.drag * (cr.medium - vk) + cr.push - cr.spring * dx;
      e.contactWork += w * (near + field).dot(dx);
      e.fieldWork += w * field.dot(dx);
      e.fieldDissipated += h * w * cr.drag * (vk - cr.medium).squaredNorm();
    }
  }
  e.loadWork = Spec.tipForce.dot(q.segment<3>(4 * n) - Q.segment<3>(4 * n));
  Eigen::VectorXd twist(n + 1);
  for (int i = 1; i < n; ++i)
  {
    const StencilStrains st = stencilStrains(q.segment<11>(4 * (i - 1)), s.stencils[i]);
    twist[i] = st.referenceTwist;
    e.frictionDissipated += gamma * (st.strains - s.stencils[i].previous).squaredNorm() /
                            (h * s.stencils[i].restLength);
  }

  // Commit: the reference frames carried to the new tangents (time-parallel transport).
  const double before = Energy.mechanical();
  for (int j = 0; j < n; ++j)
  {
    const Eigen::Vector3d tj = (q.segment<3>(4 * j + 4) - q.segment<3>(4 * j)).normalized();
    const Eigen::Vector3d d = parallelTransport(Directors.col(j), Tangents.col(j), tj);
    Directors.col(j) = (d - d.dot(tj) * tj).normalized();
    Tangents.col(j) = tj;
  }
  for (int i = 1; i < n; ++i)
    RefTwist[i] = twist[i];
  Q = q;
  V = v;
  Time = t1;
  LastIterations = iterations;
  Energy.time = Time;
  updateStateEnergies(Energy);
  e.residual = Energy.mechanical() - before - e.rootWork - e.windWork - e.contactWork - e.loadWork +
               e.frictionDissipated + e.airDissipated;
  Energy.lastStep = e;
  DerEnergyTerms& tot = Energy.total;
  tot.frictionDissipated += e.frictionDissipated;
  tot.airDissipated += e.airDissipated;
  tot.rootWork += e.rootWork;
  tot.windWork += e.windWork;
  tot.contactWork += e.contactWork;
  tot.loadWork += e.loadWork;
  tot.residual += e.residual;
  tot.fieldWork += e.fieldWork;
  tot.fieldDissipated += e.fieldDissipated;
  return Status::Ok();
}

void DerRod::updateStateEnergies(DerEnergyReport& e) const
{
  const int n = edgeCount();
  e.kinetic = 0.5 * (Mass.array() * V.array().square()).sum();
  e.gravitational = 0;
  e.stretching = e.bending = e.twisting = 0;
  for (int k = 0; k <= n; ++k)
    e.gravitational -= Mass[4 * k] * Spec.gravity.dot(Q.segment<3>(4 * k));
  for (int j = 0; j < n; ++j)
  {
    const double lb = Spec.edgeLengths[j];
    const double strain = (Q.segment<3>(4 * j + 4) - Q.segment<3>(4 * j)).norm() / lb - 1;
    e.stretching += 0.5 * StretchStiffness * lb * strain * strain;
  }
  for (int i = 1; i < n; ++i)
  {
    const StencilEnergy se = stencilEnergy(Q.segment<11>(4 * (i - 1)), stencil(i));
    e.bending += se.bending;
    e.twisting += se.twisting;
  }
  e.elastic = e.stretching + e.bending + e.twisting;
}

Eigen::MatrixXd DerRod::elasticHessian() const
{
  Step s;
  s.q0 = Q;
  s.stencils.resize(edgeCount() + 1);
  for (int i = 1; i < edgeCount(); ++i)
    s.stencils[i] = stencil(i);
  Eigen::VectorXd g;
  std::vector<Eigen::Triplet<double>> triplets;
  potential(Q, s, &g, &triplets);
  Eigen::SparseMatrix<double> H(FreeCount, FreeCount);
  H.setFromTriplets(triplets.begin(), triplets.end());
  return Eigen::MatrixXd(H);
}

void DerRod::saveState(std::vector<double>& out) const
{
  const int n = edgeCount();
  out.push_back(StateVersion);
  out.push_back(n);
  out.push_back(Time);
  out.insert(out.end(), Q.data(), Q.data() + Q.size());
  out.insert(out.end(), V.data(), V.data() + V.size());
  out.insert(out.end(), Tangents.data(), Tangents.data() + Tangents.size());
  out.insert(out.end(), Directors.data(), Directors.data() + Directors.size());
  out.insert(out.end(), RefTwist.data(), RefTwist.data() + RefTwist.size());
  const DerEnergyReport& e = Energy;
  for (double x :
       {e.time, e.kinetic, e.elastic, e.stretching, e.bending, e.twisting, e.gravitational})
    out.push_back(x);
  for (const DerEnergyTerms* t : {&e.lastStep, &e.total})
    for (double x : {t->frictionDissipated, t->airDissipated, t->rootWork, t->windWork,
                     t->contactWork, t->loadWork, t->residual, t->fieldWork, t->fieldDissipated})
      out.push_back(x);
  out.push_back(LastIterations);
}

Status DerRod::restoreState(const std::vector<double>& values)
{
  if (!Initialized)
    return Status::Error("strand: restoreState() before initialize().");
  const int n = edgeCount();
  const std::size_t expected = 3 + 2 * (4 * n + 3) + 6 * n + (n + 1) + EnergyValues + 1;
  const std::string who = "strand '" + Spec.name + "' (id " + std::to_string(Spec.id) + "): ";
  if (values.size() != expected || values[0] != StateVersion || values[1] != n)
    return Status::Error(who + "the saved state has " + std::to_string(values.size()) +
                         " numbers; a strand of " + std::to_string(n) + " edges saves " +
                         std::to_string(expected) + " (version " + std::to_string(StateVersion) +
                         "). Restore into the strand it came from.");
  for (double x : values)
    if (!std::isfinite(x))
      return Status::Error(who + "the saved state holds a non-finite number.");
  const double* p = values.data() + 2;
  Time = *p++;
  for (Eigen::VectorXd* v : {&Q, &V})
    for (int i = 0; i < 4 * n + 3; ++i)
      (*v)[i] = *p++;
  for (Eigen::Matrix3Xd* m : {&Tangents, &Directors})
    for (int i = 0; i < 3 * n; ++i)
      m->data()[i] = *p++;
  for (int i = 0; i <= n; ++i)
    RefTwist[i] = *p++;
  DerEnergyReport& e = Energy;
  for (double* x :
       {&e.time, &e.kinetic, &e.elastic, &e.stretching, &e.bending, &e.twisting, &e.gravitational})
    *x = *p++;
  for (DerEnergyTerms* t : {&e.lastStep, &e.total})
    for (double* x :
         {&t->frictionDissipated, &t->airDissipated, &t->rootWork, &t->windWork, &t->contactWork,
          &t->loadWork, &t->residual, &t->fieldWork, &t->fieldDissipated})
      *x = *p++;
  LastIterations = static_cast<int>(*p++);
  return Status::Ok();
}

} // namespace hair
