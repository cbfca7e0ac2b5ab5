#include "superhelix/SuperHelix.h"

#include "common/Multiversioning.h"
#include "superhelix/DenseLu.h"
#include "superhelix/HelixFunctions.h"
#include "superhelix/SuperHelixInternal.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <thread>

namespace hair
{

detail::StepWorkspace& detail::stepWorkspace()
{
  thread_local StepWorkspace workspace;
  return workspace;
}

const Eigen::MatrixXd& SuperHelix::massMatrix() const
{
  return detail::stepWorkspace().M;
}

const Eigen::MatrixXd& SuperHelix::velocityJacobian() const
{
  return detail::stepWorkspace().C;
}

const Eigen::MatrixXd& SuperHelix::tensionStiffness() const
{
  return detail::stepWorkspace().Kt;
}

void SuperHelix::newCurId()
{
  static std::atomic<std::uint64_t> counter{0};
  CurId = ++counter;
}

namespace
{
// The tension an explicit step carries, T_ex = ρS ℓ² / (64 h²): a string of tension T with
// nodes ℓ apart has its highest mode at ω = 2 √(T/ρS) / ℓ, so T_ex keeps h ω <= 1/4, an
// eighth of the explicit (symplectic Euler) limit h ω < 2. Measured: with 1/16 (h ω <= 1/2)
// the smooth N = 1 strand on the shaking head gained 0.011 J in 300 s (4.5 × the stability
// test's bound); with 1/64 and 1/256 every preset and N = 1…40 ran 60 s (N = 1, 2, 3:
// 600 s) with an energy gain below 6e-5 J; with no explicit share (K_T from T = 0 up) the
// falling-strand residual at dt = 1/8000 s is 4.5 × the explicit step's (docs/super-helix.md).
constexpr double ExplicitTensionDivisor = 64;
// Up to this size (3N) the step's matrix is factorized by luSolveInPlace (DenseLu.h), larger
// ones by Eigen's blocked PartialPivLU. Measured (whole steps of the wavy strand, alternated
// processes, docs/benchmarks-superhelix.md, ninth revision): ours is faster up to 3N = 360
// (N = 120: 1.9–3.1 ms a step against 4.0–4.2 ms); at 3N = 480 the two were within the noise.
constexpr int UnblockedLuMax = 360;

// [v]× m, column by column (cheaper than a 3 × 3 product with skew(v)).
EIGEN_STRONG_INLINE Eigen::Matrix3d crossCols(const Eigen::Vector3d& v, const Eigen::Matrix3d& m)
{
  Eigen::Matrix3d r;
  r.col(0) = v.cross(m.col(0));
  r.col(1) = v.cross(m.col(1));
  r.col(2) = v.cross(m.col(2));
  return r;
}

// Deterministic on every platform (std::uniform_real_distribution is not).
double uniformSigned(std::mt19937& g)
{
  return 2.0 * (static_cast<double>(g()) / 4294967296.0) - 1.0;
}
// The step's matrix a M − b C + c K_T and rhs += (M − b C) q̇, column by column (m × m,
// column-major): one pass over the three matrices instead of three. Returns whether every
// entry of the matrix is finite (x − x is 0 for finite x and NaN otherwise; a, b > 0, so a
// non-finite entry of M, C or K_T leaves one in the matrix).
HAIR_AVX2_CLONES
bool formStepSystem(double* __restrict lhs, double* __restrict rhs, const double* __restrict M,
                    const double* __restrict C, const double* __restrict Kt,
                    const double* __restrict qd, int m, double a, double b, double c)
{
  double check = 0;
  for (int j = 0; j < m; ++j)
  {
    const double q = qd[j];
    const Eigen::Index o = static_cast<Eigen::Index>(j) * m;
    double colCheck = 0;
    for (int i = 0; i < m; ++i)
    {
      const double mij = M[o + i], cij = C[o + i];
      const double l = a * mij - b * cij + c * Kt[o + i];
      lhs[o + i] = l;
      rhs[i] += (mij - b * cij) * q;
      colCheck += l - l;
    }
    check += colCheck;
  }
  return check == 0;
}

// dst(r, c) = Σ_{j < K} src(r, j) z(j, c) for r < rows and c < 3, column-major (src with
// leading dimension lds, z K × 3 contiguous, dst with leading dimension ldd); with Mirror,
// each row's three values also go to the transposed place, mirror[r ldd + c]. The three
// columns in one pass, vectorized over r: the off-diagonal blocks of M, K_T and C as one
// product over a long stack of rows (3 × 3 products block by block vectorize poorly, and
// Eigen's lazy product on these dynamic blocks was measured slower than those).
template <int K, bool Mirror>
HAIR_AVX2_CLONES void stackedProduct(double* __restrict dst, double* __restrict mirror,
                                     Eigen::Index ldd, const double* __restrict src,
                                     Eigen::Index lds, const double* __restrict z, int rows)
{
  for (int r = 0; r < rows; ++r)
  {
    double s0 = 0, s1 = 0, s2 = 0;
    for (int j = 0; j < K; ++j)
    {
      const double x = src[j * lds + r];
      s0 += x * z[j];
      s1 += x * z[K + j];
      s2 += x * z[2 * K + j];
    }
    dst[r] = s0;
    dst[ldd + r] = s1;
    dst[2 * ldd + r] = s2;
    if (Mirror)
    {
      mirror[r * ldd] = s0;
      mirror[r * ldd + 1] = s1;
      mirror[r * ldd + 2] = s2;
    }
  }
}

// dst[r · rowStride + c · colStride] += Σ_{j < K} src(r, j) z(j, c) for r < rows, c < 3 (src
// column-major with leading dimension lds, z K × 3 contiguous): a stacked product added to
// a block column (rowStride 1) or, transposed, to a block row (colStride 1). The loop is
// stackedProduct's: one kernel taking the store as a lambda was measured at +1.2 %
// instructions per step (the restrict-qualified stores no longer vectorized).
template <int K>
HAIR_AVX2_CLONES void stackedProductAdd(double* __restrict dst, Eigen::Index rowStride,
                                        Eigen::Index colStride, const double* __restrict src,
                                        Eigen::Index lds, const double* __restrict z, int rows)
{
  for (int r = 0; r < rows; ++r)
  {
    double s0 = 0, s1 = 0, s2 = 0;
    for (int j = 0; j < K; ++j)
    {
      const double x = src[j * lds + r];
      s0 += x * z[j];
      s1 += x * z[K + j];
      s2 += x * z[2 * K + j];
    }
    double* const d = dst + r * rowStride;
    d[0] += s0;
    d[colStride] += s1;
    d[2 * colStride] += s2;
  }
}

} // namespace

Status RootState::validate() const
{
  if (!(position.allFinite() && velocity.allFinite() && acceleration.allFinite() &&
        orientation.allFinite() && angularVelocity.allFinite() && angularAcceleration.allFinite()))
    return Status::Error("RootState: a root position, velocity, acceleration, orientation or "
                         "angular rate is not finite. Check the head motion.");
  const double err =
      (orientation.transpose() * orientation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (err > 1e-9 || orientation.determinant() < 0)
    return Status::Error(
        "RootState: orientation is not a rotation matrix (|FᵀF − I| = " + std::to_string(err) +
        "). Give an orthonormal, right-handed frame (n0 = tangent).");
  return Status::Ok();
}

StrandSpec StrandSpec::uniform(double length, int elements, const HairParameters& hair)
{
  StrandSpec s;
  s.hair = hair;
  if (elements > 0)
    s.elementLengths.assign(static_cast<size_t>(elements), length / elements);
  return s;
}

Status StrandSpec::validate() const
{
  const std::string who = "strand '" + name + "' (id " + std::to_string(id) + "): ";
  if (elementLengths.empty())
    return Status::Error(
        who + "the number of elements N is 0; give at least one element length (N >= 1).");
  if (elementLengths.size() > 10000)
    return Status::Error(
        who + "N = " + std::to_string(elementLengths.size()) +
        " elements is more than 10000; the dense O(N²) model is meant for N <= 100.");
  for (size_t i = 0; i < elementLengths.size(); ++i)
  {
    const double l = elementLengths[i];
    if (!(std::isfinite(l) && l > 0))
    {
      std::ostringstream s;
      s << who << "element " << i << " has length " << l
        << "; every element length must be finite and > 0 metres.";
      return Status::Error(s.str());
    }
  }
  Status st = hair.validate();
  if (!st)
    return Status::Error(who + st.message());
  if (!gravity.allFinite())
    return Status::Error(who + "gravity is not finite; give a vector in m/s².");
  if (!wind.allFinite())
    return Status::Error(who + "wind is not finite; give a velocity in m/s.");
  if (!tipForce.allFinite())
    return Status::Error(who + "the tip force is not finite; give a force in N.");
  if (!(quadratureTolerance >= QuadratureChooser::MinTolerance &&
        quadratureTolerance <= QuadratureChooser::MaxTolerance))
  {
    std::ostringstream s;
    s << who << "quadratureTolerance = " << quadratureTolerance << " is outside ["
      << QuadratureChooser::MinTolerance << ", " << QuadratureChooser::MaxTolerance
      << "]; the default " << QuadratureChooser::defaultTolerance()
      << " is the former fixed rule's accuracy.";
    return Status::Error(s.str());
  }
  if (quadraturePoints != 0 && (quadraturePoints < 3 || quadraturePoints > MaxGaussPoints))
    return Status::Error(who + "quadraturePoints = " + std::to_string(quadraturePoints) +
                         " is neither 0 (chosen per element) nor in [3, " +
                         std::to_string(MaxGaussPoints) +
                         "]; keep 0 unless reproducing the former fixed rule (4).");
  return Status::Ok();
}

std::string SuperHelix::where(double t0, double t1) const
{
  std::ostringstream s;
  s << "strand '" << Spec.name << "' (id " << Spec.id << "), step from t = " << t0
    << " s to t = " << t1 << " s: ";
  return s.str();
}

RootState SuperHelix::rootState(double time) const
{
  return Spec.root ? Spec.root(time) : RootState{};
}

Status SuperHelix::initialize(const StrandSpec& spec, double time)
{
  Status st = spec.validate();
  if (!st)
    return st;
  if (!std::isfinite(time))
    return Status::Error("strand '" + spec.name + "': initial time is not finite.");
  const RootState root = spec.root ? spec.root(time) : RootState{};
  st = root.validate();
  if (!st)
    return Status::Error("strand '" + spec.name + "' at t = " + std::to_string(time) + ": " +
                         st.message());

  Spec = spec;
  const int n = elementCount();
  Length = 0;
  Starts.resize(n + 1);
  Starts[0] = 0;
  for (int i = 0; i < n; ++i)
  {
    Length += Spec.elementLengths[i];
    Starts[i + 1] = Length;
  }
  RhoS = Spec.hair.linearDensity();
  RotI = Spec.hair.rotaryInertia();
  Rules = Spec.quadraturePoints > 0
              ? QuadratureChooser(Spec.quadratureTolerance, Spec.quadraturePoints,
                                  Spec.quadraturePoints)
              : QuadratureChooser(Spec.quadratureTolerance);
  const Eigen::Vector3d k0 = Spec.hair.naturalCurvature();
  const Eigen::Vector3d stiff = Spec.hair.stiffness();
  std::mt19937 gen(Spec.seed);
  Qrest.resize(3 * n);
  Kdiag.resize(3 * n);
  Gdiag.resize(3 * n);
  for (int e = 0; e < n; ++e)
  {
    const double l = Spec.elementLengths[e];
    for (int i = 0; i < 3; ++i)
    {
      const double var = Spec.hair.curvatureVariation * uniformSigned(gen);
      Qrest[3 * e + i] = k0[i] * (1 + var);
      Kdiag[3 * e + i] = stiff[i] * l;
      Gdiag[3 * e + i] = Spec.hair.internalFriction * l;
    }
  }
  Q = Qrest;
  Qdot = Eigen::VectorXd::Zero(3 * n);
  Time = time;
  Energy = EnergyReport{};
  F.resize(3 * n);
  Initialized = true;
  kinematics(Q, Qdot, root, Time, Cur);
  newCurId();
  CurValid = true;
  WindsValid = ContactsSet = false;
  Energy.time = Time;
  Energy.kinetic = Cur.kinetic;
  Energy.gravitational = Cur.gravitational;
  Energy.elastic = elasticEnergy(Q);
  return Status::Ok();
}

double SuperHelix::elasticEnergy(const Eigen::VectorXd& q) const
{
  return 0.5 * (Kdiag.array() * (q - Qrest).array().square()).sum();
}

void SuperHelix::kinematics(const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                            const RootState& root, double time, Kinematics& out) const
{
  const int n = elementCount();
  out.root = root;
  out.time = time;
  out.elements.resize(n);
  // Each element's rule, chosen once per call (one search over the rules for every element
  // is ~1.5 % of a fuzzy step's instructions).
  thread_local std::vector<ElementRule> rules;
  // Size the samples once (the vector keeps its capacity from step to step, and most steps
  // keep the count), then fill them in place.
  rules.resize(static_cast<size_t>(n));
  size_t count = 0;
  for (int e = 0; e < n; ++e)
  {
    rules[e] = Rules.choose(q.segment<3>(3 * e).norm() * Spec.elementLengths[e]);
    count += static_cast<size_t>(rules[e].samples());
  }
  out.nodes.resize(count);
  size_t next = 0;
  Eigen::Matrix3d Fr = root.orientation;
  Eigen::Vector3d r = root.position, om = root.angularVelocity, v = root.velocity;
  Eigen::Vector3d al = root.angularAcceleration, ac = root.acceleration;
  HelixBasis basis;
  HelixEnd he;
  double kinetic = 0, grav = 0;
  for (int e = 0; e < n; ++e)
  {
    const Eigen::Vector3d k = q.segment<3>(3 * e);
    const Eigen::Vector3d kd = qd.segment<3>(3 * e);
    const double l = Spec.elementLengths[e];
    const double omega = std::sqrt(k.squaredNorm());
    Element& el = out.elements[e];
    el.F0 = Fr;
    el.r0 = r;
    el.omega0 = om;
    el.v0 = v;
    el.alpha0 = al;
    el.acc0 = ac;
    el.first = static_cast<int>(next);
    // Every sample's Fg, J, v, a0 and v0 is linear in the element functions f_i(u)
    // (helixBasis) with coefficients constant on the element, formed here once in the world
    // frame (Fg = Σ f_i Gw_i, J = Σ f_i Jw_i, v = v + Σ f_i Vw_i, a0 = ac + Σ f_i Aw_i,
    // v0 = v0r + Σ f_i V0w_i), so a sample, and the element's end, cost a few sums instead of
    // helixPoint's kernels and the frame products (docs/super-helix.md, "Velocities and the
    // velocity-dependent terms").
    helixBasis(k, kd, basis);
    Eigen::Vector3d Gw[3], Vw[5], Aw[7], V0w[3], JwKd[4];
    Eigen::Matrix3d Jw[4];
    for (int i = 0; i < 3; ++i)
    {
      Gw[i].noalias() = Fr * basis.g[i];
      V0w[i] = root.angularVelocity.cross(Gw[i]);
      Vw[i] = om.cross(Gw[i]);
      Aw[i] = al.cross(Gw[i]) + om.cross(Vw[i]);
    }
    Vw[3].setZero();
    Vw[4].setZero();
    for (int i = 3; i < 7; ++i)
      Aw[i].setZero();
    for (int i = 0; i < 4; ++i)
    {
      Jw[i].noalias() = Fr * basis.dg[i];
      JwKd[i].noalias() = Jw[i] * kd;
      Vw[i + 1] += JwKd[i];
      Aw[i + 1] += 2 * om.cross(JwKd[i]);
    }
    for (int i = 0; i < 5; ++i)
      Aw[i + 2].noalias() += Fr * basis.d2g[i];
    // sin and cos of Ω (a + b) for the interval [a, b] being sampled, once computed.
    double sMid = 0, cMid = 1;
    bool haveMid = false;
    // Fg, J, ṙ and r̈₀ at the point whose element functions are f.
    auto pointAt = [&](const double(&f)[7], Eigen::Vector3d& Fg, Eigen::Matrix3d& J,
                       Eigen::Vector3d& vel, Eigen::Vector3d& acc) __attribute__((always_inline))
    {
      Fg = f[0] * Gw[0] + f[1] * Gw[1] + f[2] * Gw[2];
      J = f[1] * Jw[0] + f[2] * Jw[1] + f[3] * Jw[2] + f[4] * Jw[3];
      vel = v + f[0] * Vw[0] + f[1] * Vw[1] + f[2] * Vw[2] + f[3] * Vw[3] + f[4] * Vw[4];
      acc = ac + f[0] * Aw[0] + f[1] * Aw[1] + f[2] * Aw[2] + f[3] * Aw[3] + f[4] * Aw[4] +
            f[5] * Aw[5] + f[6] * Aw[6];
    };
    {
      // Kinetic energy: centreline and the cross-section's rotation ω(s) = ω + F0 G(u) k̇, in
      // the sample's frame: E(u)ᵀ (F0ᵀ ω + G(u) k̇), with E(u)ᵀ = I − u φ0 K + u² φ1 K² and
      // E(u)ᵀ G(u) = G(−k, u) = u I − u² φ1 K + u³ φ2 K² (K y = k × y; E and G are functions
      // of K). So it is linear in (1, u, u φ0, u² φ1, u³ φ2) with the coefficients omO, formed
      // once per element (two cross products per sample and the sums of y = F0ᵀ ω + G k̇ were
      // ~20 % of the reconstruction's time, perf cpu-clock samples).
      const Eigen::Vector3d omF = Fr.transpose() * om, kxkd = k.cross(kd), kxom = k.cross(omF);
      const Eigen::Vector3d omO[5] = {omF, kd, -kxom, k.cross(kxom) - kxkd, k.cross(kxkd)};
      Eigen::Vector3d wr = Eigen::Vector3d::Zero(); // Σ w r, for the gravitational energy
      const ElementRule rule = rules[e];
      const GaussRule& gauss = gaussLegendre(rule.points);
      const int nsub = rule.intervals;
      const double hsub = l / nsub;
      const Eigen::Vector3d v0r = root.velocity + root.angularVelocity.cross(r - root.position);
      for (int sI = 0; sI < nsub; ++sI)
      {
        haveMid = false;
        // The helix coefficients of the interval's nodes. Gauss nodes come in mirror pairs,
        // u and a + b − u on the interval [a, b], so sin and cos of Ω u for the farther one
        // follow from those of the nearer one and of X = Ω (a + b) by the angle difference:
        // one sincos per pair instead of two (sincos was 5 % of a fuzzy step's time, perf
        // cpu-clock samples). X is the end's angle when the element is one interval.
        const int np = rule.points;
        HelixCoefficients hc[MaxGaussPoints];
        const double xMid = omega * (hsub * (2 * sI + 1));
        for (int g = 0; g < np / 2; ++g)
        {
          const int m = np - 1 - g;
          const double x = omega * (hsub * (sI + gauss.x[g]));
          const double xm = omega * (hsub * (sI + gauss.x[m]));
          if (xm < HelixSeriesLimit)
          {
            hc[g] = helixCoefficients(x);
            hc[m] = helixCoefficients(xm);
            continue;
          }
          if (!haveMid)
          {
            sinCos(xMid, sMid, cMid);
            haveMid = true;
          }
          double sx, cx;
          sinCos(x, sx, cx);
          hc[g] = helixCoefficients(x, sx, cx);
          hc[m] = helixCoefficients(xm, sMid * cx - cMid * sx, cMid * cx + sMid * sx);
        }
        if (np % 2 == 1)
          hc[np / 2] = helixCoefficients(omega * (hsub * (sI + gauss.x[np / 2])));
        for (int g = 0; g < np; ++g)
        {
          Node& nd = out.nodes[next++];
          nd.element = e;
          nd.u = hsub * (sI + gauss.x[g]);
          nd.w = hsub * gauss.w[g];
          nd.coefficients = hc[g];
          double f[7];
          helixFunctionValues(nd.u, nd.coefficients, f);
          Eigen::Vector3d Fg;
          pointAt(f, Fg, nd.J, nd.v, nd.a0);
          nd.r = r + Fg;
          nd.v0 = v0r + f[0] * V0w[0] + f[1] * V0w[1] + f[2] * V0w[2];
          nd.hasF = nd.hasK = nd.hasD = false;
          // The cross-section's angular velocity in its own frame (see omO above).
          const Eigen::Vector3d omLocal = omO[0] + f[0] * omO[1] +
                                          (nd.u * nd.coefficients.phi0) * omO[2] + f[1] * omO[3] +
                                          f[2] * omO[4];
          kinetic += 0.5 * nd.w * (RhoS * nd.v.squaredNorm() + RotI.dot(omLocal.cwiseAbs2()));
          wr += nd.w * nd.r;
        }
      }
      el.count = static_cast<int>(next) - el.first;
      grav -= RhoS * Spec.gravity.dot(wr);
    }
    // The element's end: the same sums at u = l, and the frame's rotation over the element.
    const HelixCoefficients& ch = el.endCoefficients =
        rules[e].intervals == 1 && haveMid ? helixCoefficients(omega * l, sMid, cMid)
                                           : helixCoefficients(omega * l);
    double f[7];
    helixFunctionValues(l, ch, f);
    helixEndRotation(k, kd, l, ch, he);
    Eigen::Vector3d Fg, vEnd, acEnd;
    Eigen::Matrix3d FJ;
    pointAt(f, Fg, FJ, vEnd, acEnd);
    const Eigen::Vector3d rEnd = r + Fg;
    el.A = Fr * he.G;
    el.jEnd = FJ;
    el.jkdEnd = f[1] * JwKd[0] + f[2] * JwKd[1] + f[3] * JwKd[2] + f[4] * JwKd[3];
    el.fgEnd = Fg;
    for (int i = 0; i < 3; ++i)
      el.W.col(i) = FJ.col(i) - el.A.col(i).cross(rEnd);
    const Eigen::Vector3d Akd = el.A * kd;
    el.akd = Akd;
    const Eigen::Vector3d alEnd = al + om.cross(Akd) + Fr * he.dGk;
    om += Akd;
    al = alEnd;
    v = vEnd;
    ac = acEnd;
    r = rEnd;
    Fr = Fr * he.E;
  }
  out.tip.F0 = Fr;
  out.tip.r0 = r;
  out.tip.v0 = v;
  out.tip.omega0 = om;
  out.tip.alpha0 = al;
  out.tip.acc0 = ac;
  out.kinetic = kinetic;
  out.gravitational = grav;
}

int SuperHelix::locate(double s, double& u) const
{
  const int n = elementCount();
  s = std::clamp(s, 0.0, Length);
  int e =
      static_cast<int>(std::upper_bound(Starts.data(), Starts.data() + n + 1, s) - Starts.data()) -
      1;
  e = std::clamp(e, 0, n - 1);
  u = s - Starts[e];
  return e;
}

Eigen::Vector3d SuperHelix::position(double s) const
{
  Eigen::Vector3d x, v;
  positionAndVelocity(s, x, v);
  return x;
}

Eigen::Matrix3d SuperHelix::frame(double s) const
{
  double u;
  const int e = locate(s, u);
  HelixEnd he;
  helixEnd(Q.segment<3>(3 * e), Qdot.segment<3>(3 * e), u, he);
  return Cur.elements[e].F0 * he.E;
}

Eigen::Vector3d SuperHelix::velocity(double s) const
{
  Eigen::Vector3d x, v;
  positionAndVelocity(s, x, v);
  return v;
}

void SuperHelix::positionAndVelocity(double s, Eigen::Vector3d& position,
                                     Eigen::Vector3d& velocity) const
{
  double u;
  const int e = locate(s, u);
  const Element& el = Cur.elements[e];
  HelixPoint hp;
  const Eigen::Vector3d kd = Qdot.segment<3>(3 * e);
  helixPoint(Q.segment<3>(3 * e), kd, u, hp);
  const Eigen::Vector3d Fg = el.F0 * hp.g;
  position = el.r0 + Fg;
  velocity = el.v0 + el.omega0.cross(Fg) + el.F0 * hp.dg * kd;
}

Eigen::Vector3d SuperHelix::accelerationAtRest(double s) const
{
  double u;
  const int e = locate(s, u);
  const Element& el = Cur.elements[e];
  HelixPoint hp;
  const Eigen::Vector3d kd = Qdot.segment<3>(3 * e);
  helixPoint(Q.segment<3>(3 * e), kd, u, hp);
  const Eigen::Vector3d Fg = el.F0 * hp.g;
  const Eigen::Vector3d Jkd = el.F0 * hp.dg * kd;
  return el.acc0 + el.alpha0.cross(Fg) + el.omega0.cross(el.omega0.cross(Fg)) +
         2 * el.omega0.cross(Jkd) + el.F0 * hp.d2g;
}

Eigen::Matrix3Xd SuperHelix::jacobian(double s) const
{
  double u;
  const int e = locate(s, u);
  const int n = elementCount();
  Eigen::Matrix3Xd J = Eigen::Matrix3Xd::Zero(3, 3 * n);
  const Element& el = Cur.elements[e];
  HelixPoint hp;
  helixPoint(Q.segment<3>(3 * e), Qdot.segment<3>(3 * e), u, hp);
  const Eigen::Vector3d r = el.r0 + el.F0 * hp.g;
  for (int p = 0; p < e; ++p)
    for (int i = 0; i < 3; ++i)
      J.col(3 * p + i) = Cur.elements[p].A.col(i).cross(r) + Cur.elements[p].W.col(i);
  J.middleCols<3>(3 * e) = el.F0 * hp.dg;
  return J;
}

void SuperHelix::polyline(int perElement, std::vector<Eigen::Vector3d>& points) const
{
  perElement = std::max(1, perElement);
  points.clear();
  const int n = elementCount();
  HelixPoint hp;
  for (int e = 0; e < n; ++e)
  {
    const Element& el = Cur.elements[e];
    for (int j = 0; j < perElement; ++j)
    {
      helixPoint(Q.segment<3>(3 * e), Qdot.segment<3>(3 * e),
                 Spec.elementLengths[e] * j / perElement, hp);
      points.push_back(el.r0 + el.F0 * hp.g);
    }
  }
  points.push_back(Cur.tip.r0);
}

const std::vector<StrandSample>& SuperHelix::samples() const
{
  Samples.resize(Cur.nodes.size());
  for (size_t i = 0; i < Cur.nodes.size(); ++i)
  {
    const Node& nd = Cur.nodes[i];
    Samples[i].element = nd.element;
    Samples[i].s = Starts[nd.element] + nd.u;
    Samples[i].weight = nd.w;
    Samples[i].position = nd.r;
    Samples[i].velocity = nd.v;
  }
  return Samples;
}

void SuperHelix::reconstruct()
{
  kinematics(Q, Qdot, rootState(Time), Time, Cur);
  newCurId();
  ContactsSet = false;
  // The air's velocity too, so that assemble() called after reconstruct() sees the wind that
  // a step sees.
  WindsValid = false;
  if (Spec.windField)
    fillWinds(Time);
  CurValid = true;
}

void SuperHelix::fillWinds(double time)
{
  Winds.resize(Cur.nodes.size());
  for (size_t j = 0; j < Cur.nodes.size(); ++j)
    Winds[j] = Spec.windField(Cur.nodes[j].r, time);
  WindsValid = true;
}

Status SuperHelix::evaluateForces(Kinematics& k, double time)
{
  ContactsSet = false;
  if (Spec.windField)
  {
    if (!WindsValid) // reconstruct() has evaluated it at these samples and this time
      fillWinds(time);
    for (size_t j = 0; j < k.nodes.size(); ++j)
      if (!Winds[j].allFinite())
        return Status::Error(
            "the wind at s = " + std::to_string(Starts[k.nodes[j].element] + k.nodes[j].u) +
            " m is not finite; check the wind field.");
  }
  if (Contacts)
  {
    const std::vector<StrandSample>& smp = samples();
    std::vector<ContactResponse>& buffer = detail::stepWorkspace().ContactBuffer;
    buffer.assign(k.nodes.size(), ContactResponse());
    Contacts(Spec.id, time, smp, buffer);
    if (buffer.size() != k.nodes.size())
      return Status::Error("the contact hook changed the size of the response buffer (" +
                           std::to_string(buffer.size()) + " instead of " +
                           std::to_string(k.nodes.size()) + "); write one response per sample.");
    for (size_t i = 0; i < k.nodes.size(); ++i)
    {
      Node& nd = k.nodes[i];
      const ContactResponse& c = buffer[i];
      nd.hasF = !c.force.isZero(0);
      nd.hasK = !c.stiffness.isZero(0);
      nd.hasD = !c.damping.isZero(0);
      if (!c.force.allFinite())
        return Status::Error(
            "the contact force at s = " + std::to_string(Starts[nd.element] + nd.u) +
            " m is not finite; check the contact hook.");
      if (!c.stiffness.allFinite() || !c.damping.allFinite())
        return Status::Error(
            "the contact stiffness or damping at s = " + std::to_string(Starts[nd.element] + nd.u) +
            " m is not finite; check the contact hook.");
    }
    ContactsSet = true;
  }
  if (!Spec.tipForce.allFinite())
    return Status::Error("the tip force is not finite.");
  return Status::Ok();
}

void SuperHelix::assemble()
{
  const int n = elementCount();
  detail::StepWorkspace& ws = detail::stepWorkspace();
  Eigen::MatrixXd& M = ws.M;
  M.resize(3 * n, 3 * n); // per-thread buffer (no-op when the size is kept)
  Kinematics& k = Cur;
  if (Spec.windField && !WindsValid)
    fillWinds(Time);
  // The explicit force per unit length at each sample: gravity, drag on the rigid
  // (root-carried) velocity against the wind, the inertia of the root motion and the
  // velocity-dependent terms, contacts (the q̇-part of drag is implicit). Kept in Loads for
  // assembleTensionStiffness. Thread-local buffers are reached once, not per sample.
  ws.Loads.resize(k.nodes.size());
  ws.LoadsId = CurId;
  Eigen::Vector3d* const loads = ws.Loads.data();
  const Eigen::Vector3d* const winds = Spec.windField ? Winds.data() : nullptr;
  const ContactResponse* const contacts = ContactsSet ? ws.ContactBuffer.data() : nullptr;
  const Eigen::Vector3d gravity = RhoS * Spec.gravity;
  const double nu = Spec.hair.airFriction;
  // Tail sums, from the tip: force, torque, mass, first and second moments. The tip load
  // acts beyond every element: J(L)ᵀP = A_eᵀ (r(L) × P) + W_eᵀ P for every e.
  Eigen::Vector3d tailF = Spec.tipForce, tailT = k.tip.r0.cross(Spec.tipForce);
  Eigen::Vector3d tailC = Eigen::Vector3d::Zero();
  Eigen::Matrix3d tailTheta = Eigen::Matrix3d::Zero();
  double tailM = 0;
  // Per element P: Z_P = [U_P; V_P] such that block(Q < P) = A_Qᵀ U_P + W_Qᵀ V_P, and the
  // stack B (rows 3Q..3Q+2 = [A_Qᵀ W_Qᵀ]) so that the whole column block P above the diagonal
  // is one product B_{Q<P} Z_P over long columns (3 × 3 products block by block vectorize
  // poorly). The buffers only grow: nothing is allocated per step.
  thread_local std::vector<Eigen::Matrix<double, 6, 3>> Z;
  thread_local Eigen::Matrix<double, Eigen::Dynamic, 6> B;
  Z.resize(n);
  if (B.rows() < 3 * n)
    B.resize(3 * n, 6);
  for (int e = n - 1; e >= 0; --e)
  {
    const Element& el = k.elements[e];
    Eigen::Matrix3d Mloc = Eigen::Matrix3d::Zero(), X = Eigen::Matrix3d::Zero(),
                    Y = Eigen::Matrix3d::Zero();
    const Eigen::Matrix3d K = skew(Q.segment<3>(3 * e)), K2 = K * K;
    Eigen::Vector3d floc = Eigen::Vector3d::Zero(), eF = Eigen::Vector3d::Zero(),
                    eT = Eigen::Vector3d::Zero(), eC = Eigen::Vector3d::Zero();
    Eigen::Matrix3d eTheta, eRR = Eigen::Matrix3d::Zero();
    double eM = 0, eR2 = 0;
    double sBB[3][3] = {}, sEB[3][3] = {}, sEE[3][3] = {};
    for (int j = el.first; j < el.first + el.count; ++j)
    {
      Node& nd = k.nodes[j];
      const double wm = nd.w * RhoS;
      Eigen::Vector3d f = gravity - nu * (nd.v0 - (winds ? winds[j] : Spec.wind)) - RhoS * nd.a0;
      if (contacts && nd.hasF)
        f += contacts[j].force;
      loads[j] = f;
      floc.noalias() += nd.w * (nd.J.transpose() * f);
      eF += nd.w * f;
      eT += nd.w * nd.r.cross(f);
      // JᵀJ and r rᵀ are symmetric: their upper triangles here, mirrored after the loop.
      for (int b = 0; b < 3; ++b)
        for (int a = 0; a <= b; ++a)
        {
          Mloc(a, b) += wm * nd.J.col(a).dot(nd.J.col(b));
          eRR(a, b) += (wm * nd.r[a]) * nd.r[b];
        }
      {
        // X += [wm r]× J, written out: crossCols stayed a call here (3 % of a curly step's
        // time), and forcing it inline everywhere made every preset 3–5 % slower.
        const double r0 = wm * nd.r[0], r1 = wm * nd.r[1], r2 = wm * nd.r[2];
        for (int c = 0; c < 3; ++c)
        {
          const double j0 = nd.J(0, c), j1 = nd.J(1, c), j2 = nd.J(2, c);
          X(0, c) += r1 * j2 - r2 * j1;
          X(1, c) += r2 * j0 - r0 * j2;
          X(2, c) += r0 * j1 - r1 * j0;
        }
      }
      Y += wm * nd.J;
      eM += wm;
      eC += wm * nd.r;
      eR2 += wm * nd.r.squaredNorm(); // Θ = Σ wm (|r|² I − r rᵀ), completed below
      // Rotary inertia of the cross-section, I(s) = F diag(ρI_p, ρI1, ρI2) Fᵀ, about the
      // frame's angular velocity, whose Jacobian is A_P (P < e) and F0 G(u) (own element):
      // the same tail-sum structure as the translational second moment Θ.
      // In the sample's own frame: Fᵀ F0 G(u) = E(u)ᵀ G(u) = G(u) with −k (E and G commute),
      // so with B = G(−k, u) and D = w diag(ρI_p, ρI1, ρI2):
      // (F0G)ᵀ I F0G = Bᵀ D B, I F0G = F D B, I = F D Fᵀ.
      // E and B are polynomials in K = [k]× with per-sample coefficients,
      //   E = I + u φ0 K + u² φ1 K²,  B = u I − u² φ1 K + u³ φ2 K²,
      // so only the weighted products of the coefficients are summed per sample; the
      // matrices K^i D K^j are formed once per element, below.
      {
        double Ec[3], Bc[3]; // B = G(u) with −k: the middle coefficient changes sign
        helixFrameCoefficients(nd.u, nd.coefficients, Ec, Bc);
        Bc[1] = -Bc[1];
        for (int i = 0; i < 3; ++i)
        {
          const double wE = nd.w * Ec[i], wB = nd.w * Bc[i];
          for (int jj = 0; jj < 3; ++jj)
          {
            sBB[i][jj] += wB * Bc[jj];
            sEB[i][jj] += wE * Bc[jj];
            sEE[i][jj] += wE * Ec[jj];
          }
        }
      }
    }
    Mloc.triangularView<Eigen::StrictlyLower>() = Mloc.transpose();
    eRR.triangularView<Eigen::StrictlyLower>() = eRR.transpose();
    {
      // P_ij = K^i D K^j (D = diag(ρI_p, ρI1, ρI2)); (K^i)ᵀ = (−1)^i K^i:
      //   Σ Bᵀ D B = Σ_ij sBB_ij (−1)^i P_ij,  Σ F D B = F0 Σ_ij sEB_ij P_ij,
      //   Σ F D Fᵀ = F0 (Σ_ij sEE_ij (−1)^j P_ij) F0ᵀ.
      // The six P_ij with i <= j are formed once per element (K X by column cross products);
      // the others are P_ji = (−1)^(i+j) P_ijᵀ (K D = −(D K)ᵀ, K² D = (D K²)ᵀ,
      // K² D K = −(K D K²)ᵀ). The three sums were Horner forms in K, 150 flops each, as a
      // lambda that was not inlined: 5.6 % of a curly step's time (perf cpu-clock samples).
      const Eigen::Vector3d k = Q.segment<3>(3 * e);
      Eigen::Matrix3d P01, P02;
      P01.noalias() = RotI.asDiagonal() * K;
      P02.noalias() = RotI.asDiagonal() * K2;
      const Eigen::Matrix3d P11 = crossCols(k, P01), P12 = crossCols(k, P02),
                            P22 = crossCols(k, P12);
      auto sum = [&](const double(&c)[3][3]) __attribute__((always_inline))
      {
        Eigen::Matrix3d S = c[1][1] * P11 + c[2][2] * P22 + c[0][1] * P01 + c[0][2] * P02 +
                            c[1][2] * P12 - c[1][0] * P01.transpose() + c[2][0] * P02.transpose() -
                            c[2][1] * P12.transpose();
        S.diagonal() += c[0][0] * RotI;
        return S;
      };
      double cM[3][3], cT[3][3];
      for (int i = 0; i < 3; ++i)
        for (int jj = 0; jj < 3; ++jj)
        {
          cM[i][jj] = (i == 1 ? -1.0 : 1.0) * sBB[i][jj];
          cT[i][jj] = (jj == 1 ? -1.0 : 1.0) * sEE[i][jj];
        }
      const Eigen::Matrix3d Ms = sum(cM), Xs = sum(sEB), Ts = sum(cT);
      Mloc += Ms;
      X.noalias() += el.F0 * Xs;
      eTheta = -eRR;
      eTheta.diagonal().array() += eR2;
      eTheta.noalias() += el.F0 * Ts * el.F0.transpose();
    }
    // Generalized force of element e: own samples plus the rigid tail beyond it.
    F.segment<3>(3 * e) = floc + el.A.transpose() * tailT + el.W.transpose() * tailF;
    const Eigen::Matrix3d C = skew(tailC);
    const Eigen::Matrix3d ThA = tailTheta * el.A;
    // The tail's parts of U and V, shared with the diagonal block (fixed-size temporaries:
    // the nested product expression was evaluated coefficient by coefficient).
    Eigen::Matrix3d TU = ThA, TV = tailM * el.W;
    TU.noalias() += C * el.W;
    TV.noalias() -= C * el.A;
    Eigen::Matrix3d d = Mloc;
    d.noalias() += el.A.transpose() * TU;
    d.noalias() += el.W.transpose() * TV;
    // Symmetric up to round-off: symmetrized exactly.
    M.block<3, 3>(3 * e, 3 * e) = 0.5 * (d + d.transpose());
    Z[e].topRows<3>() = X + TU;
    Z[e].bottomRows<3>() = Y + TV;
    B.block<3, 3>(3 * e, 0) = el.A.transpose();
    B.block<3, 3>(3 * e, 3) = el.W.transpose();
    tailF += eF;
    tailT += eT;
    tailM += eM;
    tailC += eC;
    tailTheta += eTheta;
  }
  // Column block P above the diagonal, B_{Q<P} Z_P, and its transpose below.
  const Eigen::Index ld = M.rows();
  for (int p = 1; p < n; ++p)
    stackedProduct<6, true>(M.data() + 3 * p * ld, M.data() + 3 * p, ld, B.data(), B.rows(),
                            Z[p].data(), 3 * p);
}

void SuperHelix::assembleTensionStiffness(double h)
{
  // K_T = ∫ T⁺(s) J_ω(s)ᵀ (I − n0 n0ᵀ) J_ω(s) ds (docs/super-helix.md, "Tension
  // stiffness"): the part of the loads' geometric stiffness −∂f/∂q carried by the tension
  // T(s) = n0(s) · ∫_s^L f (+ the tip force), which is what makes a hanging strand a chain
  // of pendulums. J_ω is the Jacobian of the frame's rotation: A_P for P before the
  // sample's element, F0 G(u) for its own element. Only the tension beyond what an explicit
  // step carries is used, T⁺ = max(0, T − ρS ℓ² / (64 h²)), so that small steps keep the
  // explicit (energy-neutral) treatment. Tail sums as for the mass matrix: O(N²).
  const int n = elementCount();
  detail::StepWorkspace& ws = detail::stepWorkspace();
  Eigen::MatrixXd& Kt = ws.Kt;
  Kt.resize(3 * n, 3 * n); // per-thread buffer
  Kinematics& k = Cur;
  // Per element P: Y_P such that block(Q < P) = A_Qᵀ Y_P, and the stack At (rows
  // 3Q..3Q+2 = A_Qᵀ) so that column block P above the diagonal is one product At_{Q<P} Y_P.
  thread_local std::vector<Eigen::Matrix3d> Y;
  thread_local Eigen::Matrix<double, Eigen::Dynamic, 3> At;
  Y.resize(n);
  if (At.rows() < 3 * n)
    At.resize(3 * n, 3);
  if (ws.LoadsId != CurId) // assemble() ran for another strand or state on this thread since
    assemble();
  const Eigen::Vector3d* const loads = ws.Loads.data(); // set by assemble()
  Eigen::Vector3d tailF = Spec.tipForce;
  Eigen::Matrix3d tailP = Eigen::Matrix3d::Zero(); // ∫ T⁺ (I − n0 n0ᵀ) beyond the element
  for (int e = n - 1; e >= 0; --e)
  {
    const Element& el = k.elements[e];
    const double l = Spec.elementLengths[e];
    const double explicitTension = RhoS * l * l / (ExplicitTensionDivisor * h * h);
    // The own element's terms from per-sample coefficients. With K = [k]×, V_i = K^i e0 (the
    // columns of Vm), n0 = F0 E(u) e0 = F0 Vm c and F0ᵀ FG = G(u) = Σ_j d_j K^j, where
    // c = (1, uφ0, u²φ1) and d = (u, u²φ1, u³φ2), and since G(u)ᵀ E(u) = G(u) (both are
    // functions of K; Gᵀ E = ∫0^u exp((u − s) K) ds), G(u)ᵀ F0ᵀ n0 = G(u) e0 = g = Vm d. So
    // with P = wT (I − n0 n0ᵀ) at a sample of weight w and tension T:
    //   P FG = wT F0 (G − Vm c dᵀ Vmᵀ),  FGᵀ P FG = wT (GᵀG − Vm d dᵀ Vmᵀ),
    //   P = F0 (wT I − Vm c cᵀ Vmᵀ wT) F0ᵀ,
    // and GᵀG = Σ_ij (−1)^i d_i d_j K^(i+j) = d0² I + (2 d0 d2 − d1² − Ω² d2²) K² (odd powers
    // cancel, K⁴ = −Ω² K²). Per sample only the weighted products of c and d are summed.
    const Eigen::Vector3d kq = Q.segment<3>(3 * e);
    const double k0 = kq[0], k1 = kq[1], k2 = kq[2], w0 = -(k1 * k1 + k2 * k2);
    Eigen::Matrix3d Vm; // K e0 = (0, k2, −k1), K² e0 = k k0 − Ω² e0
    Vm << 1, 0, w0, 0, k2, k0 * k1, 0, -k1, k0 * k2;
    Eigen::Matrix3d W; // F0 Vm, n0 = W c
    W.col(0) = el.F0.col(0);
    W.col(1) = k2 * el.F0.col(1) - k1 * el.F0.col(2);
    W.col(2) = w0 * el.F0.col(0) + (k0 * k1) * el.F0.col(1) + (k0 * k2) * el.F0.col(2);
    double sw = 0, sd[3] = {0, 0, 0};
    Eigen::Matrix3d sdd = Eigen::Matrix3d::Zero(), scd = Eigen::Matrix3d::Zero(),
                    scc = Eigen::Matrix3d::Zero();
    double beyond = 0; // Σ w of the element's samples beyond the current one
    for (int j = el.first + el.count - 1; j >= el.first; --j)
    {
      const Node& nd = k.nodes[j];
      const Eigen::Vector3d& load = loads[j];
      const Eigen::Vector3d wf = nd.w * load;
      // Tail force at the sample: the samples beyond it, and its own load over the rest of
      // the length to the element's end (exact for a uniform load).
      const Eigen::Vector3d atSample = tailF + (l - nd.u - beyond) * load;
      tailF += wf;
      beyond += nd.w;
      const HelixCoefficients& hc = nd.coefficients;
      double ce[3], dg[3];
      helixFrameCoefficients(nd.u, hc, ce, dg);
      const Eigen::Vector3d c(ce[0], ce[1], ce[2]), d(dg[0], dg[1], dg[2]);
      // T⁺ without a branch: the sign of T changes along a moving strand, and a mispredicted
      // branch costs more than the products of a sample in compression (which add zeros).
      // A NaN tension counts as none, as before; F's check stops such a step.
      const double T = (W * c).dot(atSample) - explicitTension;
      const double wT = nd.w * (T > 0 ? T : 0.0);
      const Eigen::Vector3d wd = wT * d;
      sw += wT;
      for (int i = 0; i < 3; ++i)
        sd[i] += wd[i];
      sdd.noalias() += wd * d.transpose();
      scd.noalias() += (wT * c) * d.transpose();
      scc.noalias() += (wT * c) * c.transpose();
    }
    Eigen::Matrix3d Yown = Eigen::Matrix3d::Zero(), Down = Eigen::Matrix3d::Zero(),
                    eP = Eigen::Matrix3d::Zero();
    if (sw > 0) // some sample in tension
    {
      const Eigen::Matrix3d K = skew(kq), K2 = K * K;
      Eigen::Matrix3d Gsum = sd[1] * K + sd[2] * K2;
      Gsum.diagonal().array() += sd[0];
      Yown.noalias() = el.F0 * (Gsum - Vm * scd * Vm.transpose());
      Down = (2 * sdd(0, 2) - sdd(1, 1) - kq.squaredNorm() * sdd(2, 2)) * K2 -
             Vm * sdd * Vm.transpose();
      Down.diagonal().array() += sdd(0, 0);
      eP = -(W * scc * W.transpose());
      eP.diagonal().array() += sw;
    }
    Y[e] = Yown + tailP * el.A;
    At.block<3, 3>(3 * e, 0) = el.A.transpose();
    const Eigen::Matrix3d d = Down + el.A.transpose() * (tailP * el.A);
    Kt.block<3, 3>(3 * e, 3 * e) = 0.5 * (d + d.transpose());
    tailP += eP;
  }
  // Column block P above the diagonal, At_{Q<P} Y_P, and its transpose below.
  const Eigen::Index ld = Kt.rows();
  for (int p = 1; p < n; ++p)
    stackedProduct<3, true>(Kt.data() + 3 * p * ld, Kt.data() + 3 * p, ld, At.data(), At.rows(),
                            Y[p].data(), 3 * p);
}

namespace
{
// The per-sample moments behind the velocity Jacobian's element maps (see
// assembleVelocityJacobian), summed in plain arrays (column-major 3 × 3 blocks): the same
// sums written with Eigen's 3 × 3 expressions took 9 % more of C's instructions on fuzzy
// hair (4 % on smooth).
//   PJ = Σ w J,  N_a = Σ w J_a Fgᵀ,  X = Σ w (J_0 × J_1, J_0 × J_2, J_1 × J_2),
//   S2 = Σ w Fg Fgᵀ,  with Y = w F0 D (D = D²g[k̇, ·]):  Qm = Σ Jᵀ Y,  SD = Σ Y,  R = Σ [Fg]× Y.
struct SampleMoments
{
  double sc = 0, sF[3] = {}, PJ[9] = {}, N[27] = {}, X[9] = {}, S2[9] = {}, Qm[9] = {}, SD[9] = {},
         R[9] = {};

  HAIR_AVX2_CLONES
  void add(double w, const double* __restrict J, const Eigen::Vector3d& fgv,
           const double* __restrict y)
  {
    const double f[3] = {fgv[0], fgv[1], fgv[2]};
    double wj[9];
    for (int i = 0; i < 9; ++i)
      wj[i] = w * J[i];
    sc += w;
    for (int i = 0; i < 3; ++i)
      sF[i] += w * f[i];
    for (int i = 0; i < 9; ++i)
      PJ[i] += wj[i];
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c)
        for (int b = 0; b < 3; ++b)
          N[9 * a + 3 * c + b] += wj[3 * a + b] * f[c];
    const double* const j1 = J + 3;
    const double* const j2 = J + 6;
    const double* const v0 = wj;
    const double* const v1 = wj + 3;
    X[0] += v0[1] * j1[2] - v0[2] * j1[1];
    X[1] += v0[2] * j1[0] - v0[0] * j1[2];
    X[2] += v0[0] * j1[1] - v0[1] * j1[0];
    X[3] += v0[1] * j2[2] - v0[2] * j2[1];
    X[4] += v0[2] * j2[0] - v0[0] * j2[2];
    X[5] += v0[0] * j2[1] - v0[1] * j2[0];
    X[6] += v1[1] * j2[2] - v1[2] * j2[1];
    X[7] += v1[2] * j2[0] - v1[0] * j2[2];
    X[8] += v1[0] * j2[1] - v1[1] * j2[0];
    for (int c = 0; c < 3; ++c)
      for (int b = 0; b < 3; ++b)
        S2[3 * c + b] += w * f[b] * f[c];
    for (int c = 0; c < 3; ++c)
      for (int a = 0; a < 3; ++a)
        Qm[3 * c + a] +=
            J[3 * a] * y[3 * c] + J[3 * a + 1] * y[3 * c + 1] + J[3 * a + 2] * y[3 * c + 2];
    for (int i = 0; i < 9; ++i)
      SD[i] += y[i];
    for (int c = 0; c < 3; ++c)
    {
      const double* const yc = y + 3 * c;
      R[3 * c] += f[1] * yc[2] - f[2] * yc[1];
      R[3 * c + 1] += f[2] * yc[0] - f[0] * yc[2];
      R[3 * c + 2] += f[0] * yc[1] - f[1] * yc[0];
    }
  }
};

// The same moments from a Gram matrix of scalar functions, for elements with many samples.
// Every per-sample quantity above is linear in seven functions of u with coefficients that
// are constant on the element (helixPoint, helixBilinear), in the element's start frame:
//   f = (u, a = u²φ1, b = u³φ2, c1 = u⁴ψ1, c2 = u⁵ψ2, e6 = u⁶χ1, e7 = u⁷χ2)  (φ, ψ, χ of Ω u),
//   g = u e0 + a k×e0 + b k×(k×e0)                       (f0, f1, f2),
//   ∂g/∂k = a [e_i × e0]_i + b (k0 I − 2 e0 kᵀ + k e0ᵀ) + c1 (k×e0) kᵀ + c2 k×(k×e0) kᵀ
//                                                        (f1 … f4),
//   D = D²g[k̇, ·] = helixBilinearValues(k, k̇, f2, f3, f4, f5, f6)  (f2 … f6),
// and J = F0 ∂g/∂k, Fg = F0 g, Y = w F0 D. So each moment is a contraction of the Gram
// matrix Σ w f_i f_j (28 numbers) and the sums Σ w f_i with those coefficients, e.g.
// Σ w J_a Fgᵀ = F0 (Σ_ij G_ij ∂g_i/∂k_a g_jᵀ) F0ᵀ, Σ Jᵀ Y = Σ_ij G_ij (∂g_i/∂k)ᵀ D_j and
// Σ w J_a × J_b = F0 Σ_ij G_ij ∂g_i/∂k_a × ∂g_j/∂k_b (F0 a proper rotation). Per sample
// that is 35 products instead of SampleMoments::add and helixBilinear; the contraction is a
// fixed cost per element, which pays from GramMinSamples samples on.
struct FunctionGram
{
  double sw = 0, m[7] = {}, G[7][7] = {}; // G: upper triangle while summing

  void add(double w, double u, const HelixCoefficients& c)
  {
    double f[7];
    helixFunctionValues(u, c, f);
    sw += w;
    for (int i = 0; i < 7; ++i)
    {
      const double wf = w * f[i];
      m[i] += wf;
      for (int j = i; j < 7; ++j)
        G[i][j] += wf * f[j];
    }
  }

  // The moments of SampleMoments from the sums, for curvature k, rate kd and start frame F0.
  // The helix kernels are linear in the functions' values, so a row of G passed as values
  // gives Σ_h G_fh (coefficient of h) without forming the coefficient matrices.
  void moments(const Eigen::Vector3d& k, const Eigen::Vector3d& kd, const Eigen::Matrix3d& F0,
               SampleMoments& out)
  {
    for (int i = 0; i < 7; ++i)
      for (int j = 0; j < i; ++j)
        G[i][j] = G[j][i];
    using M3 = Eigen::Matrix3d;
    using V3 = Eigen::Vector3d;
    // Coefficients of g (functions 0 … 2: e0, k×e0, k×(k×e0)) and of ∂g/∂k (1 … 4).
    V3 g[3];
    for (int f = 0; f < 3; ++f)
      helixGValues(k, f == 0, f == 1, f == 2, g[f]);
    M3 dg[5];
    for (int f = 1; f < 5; ++f)
      helixJacobianValues(k, f == 1, f == 2, f == 3, f == 4, dg[f]);
    // Rows of G contracted: T_f = Σ_h G_fh g_h, U_f = Σ_h G_fh ∂g_h, V_f = Σ_h G_fh D_h.
    V3 T[5];
    M3 U[5], V[5];
    for (int f = 0; f < 5; ++f)
    {
      const double* r = G[f];
      helixGValues(k, r[0], r[1], r[2], T[f]);
      helixJacobianValues(k, r[1], r[2], r[3], r[4], U[f]);
      helixBilinearValues(k, kd, r[2], r[3], r[4], r[5], r[6], V[f]);
    }
    V3 sF;
    M3 PJ, SD;
    helixGValues(k, m[0], m[1], m[2], sF);
    helixJacobianValues(k, m[1], m[2], m[3], m[4], PJ);
    helixBilinearValues(k, kd, m[2], m[3], m[4], m[5], m[6], SD);
    // Σ w ∂g_a gᵀ = Σ_h U_h(:, a) g_hᵀ, Σ w g gᵀ = Σ_f g_f T_fᵀ, Σ w [g]× D = Σ_f [g_f]× V_f,
    // Σ w ∂g_a × ∂g_b = Σ_f ∂g_f(:, a) × U_f(:, b), Σ w ∂gᵀ D = Σ_f ∂g_fᵀ V_f.
    M3 Nl[3], S2 = M3::Zero(), R = M3::Zero(), Qm = M3::Zero();
    for (int a = 0; a < 3; ++a)
      Nl[a].noalias() = U[0].col(a) * g[0].transpose() + U[1].col(a) * g[1].transpose() +
                        U[2].col(a) * g[2].transpose();
    for (int f = 0; f < 3; ++f)
    {
      S2.noalias() += g[f] * T[f].transpose();
      R += crossCols(g[f], V[f]);
    }
    V3 X[3] = {V3::Zero(), V3::Zero(), V3::Zero()};
    for (int f = 1; f < 5; ++f)
    {
      X[0] += dg[f].col(0).cross(U[f].col(1));
      X[1] += dg[f].col(0).cross(U[f].col(2));
      X[2] += dg[f].col(1).cross(U[f].col(2));
      Qm.noalias() += dg[f].transpose() * V[f];
    }
    out.sc = sw;
    Eigen::Map<V3>(out.sF) = F0 * sF;
    Eigen::Map<M3>(out.PJ) = F0 * PJ;
    for (int a = 0; a < 3; ++a)
    {
      Eigen::Map<M3>(out.N + 9 * a) = F0 * Nl[a] * F0.transpose();
      Eigen::Map<V3>(out.X + 3 * a) = F0 * X[a];
    }
    Eigen::Map<M3>(out.S2) = F0 * S2 * F0.transpose();
    Eigen::Map<M3>(out.Qm) = Qm;
    Eigen::Map<M3>(out.SD) = F0 * SD;
    Eigen::Map<M3>(out.R) = F0 * R;
  }
};

// One pass over the rows of Γ_{qe+1} (columns [a l w] with leading dimension ldg, rows
// r < rows): C's column block qe below the diagonal, dst(r, :) = Γ(r, :) S (leading dimension
// ldc), then Γ_{qe+1} Prop_qe in place,
//   w += a Φ_end − l [A k̇]×,  l −= a [Fg_end]×   (row vectors: x [v]× = x × v).
// O(N²) in all (~100 instructions per row with 2-wide vectors).
HAIR_AVX2_CLONES
void lowerAndPropagate(double* __restrict dst, Eigen::Index ldc, double* __restrict g,
                       Eigen::Index ldg, const double* __restrict S, const double* __restrict phi,
                       const double* __restrict akd, const double* __restrict fg, int rows)
{
  const double v0 = akd[0], v1 = akd[1], v2 = akd[2], f0 = fg[0], f1 = fg[1], f2 = fg[2];
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC ivdep // each pass reads and writes row r of Γ only
#endif
  for (int r = 0; r < rows; ++r)
  {
    const double a0 = g[r], a1 = g[ldg + r], a2 = g[2 * ldg + r];
    const double l0 = g[3 * ldg + r], l1 = g[4 * ldg + r], l2 = g[5 * ldg + r];
    const double w0 = g[6 * ldg + r], w1 = g[7 * ldg + r], w2 = g[8 * ldg + r];
    for (int c = 0; c < 3; ++c)
    {
      const double* const s = S + 9 * c;
      dst[c * ldc + r] = a0 * s[0] + a1 * s[1] + a2 * s[2] + l0 * s[3] + l1 * s[4] + l2 * s[5] +
                         w0 * s[6] + w1 * s[7] + w2 * s[8];
    }
    g[6 * ldg + r] = w0 + (a0 * phi[0] + a1 * phi[1] + a2 * phi[2]) - (l1 * v2 - l2 * v1);
    g[7 * ldg + r] = w1 + (a0 * phi[3] + a1 * phi[4] + a2 * phi[5]) - (l2 * v0 - l0 * v2);
    g[8 * ldg + r] = w2 + (a0 * phi[6] + a1 * phi[7] + a2 * phi[8]) - (l0 * v1 - l1 * v0);
    g[3 * ldg + r] = l0 - (a1 * f2 - a2 * f1);
    g[4 * ldg + r] = l1 - (a2 * f0 - a0 * f2);
    g[5 * ldg + r] = l2 - (a0 * f1 - a1 * f0);
  }
}
} // namespace

void SuperHelix::assembleVelocityJacobian()
{
  // C = ∂f/∂q̇ with f ∋ −ρS a0: a0 is quadratic in q̇ (plus root-coupled linear terms).
  // A change δq̇ of element Q changes, at the start of each later element, the frame's
  // angular velocity δω, its q̈ = 0 angular acceleration δα and the point's acceleration
  // δa; inside an element the change at a sample is linear in those three:
  //   δa0 = δa − [Fg]× δα + Φ δω,  Φ = −[ω × Fg]× − [ω]× [Fg]× − 2 [J k̇]×,
  // so per-element moments of these maps give each column block in O(N).
  const int n = elementCount();
  Eigen::MatrixXd& C = detail::stepWorkspace().C;
  C.resize(3 * n, 3 * n); // per-thread buffer
  const Kinematics& k = Cur;
  struct Maps
  {
    // Moments over the element's samples of the maps (δa, δα, δω) ↦ δa0 (P: weighted by
    // Jᵀ, S: plain, T: by [r]×), and what is handed on to the next element.
    Eigen::Matrix3d Pc, Pl, Po, So, Tl, To, PhiEnd;
    Eigen::Vector3d sumFg, sumR, fgEnd, akd;
    double Sc;
    // The element's own k̇-dependence: moments of δa0 (own samples), and (δα, δa) at its end.
    Eigen::Matrix3d ownR, ownF, ownM, Dal0, Dac0;
  };
  thread_local std::vector<Maps> maps;
  maps.resize(n);
  // Φ = −[ω × Fg]× − [ω]× [Fg]× − 2 [J k̇]× = −2 Fg ωᵀ + ω Fgᵀ + (ω·Fg) I − 2 [J k̇]×
  // ([a × b]× = b aᵀ − a bᵀ, [a]× [b]× = b aᵀ − (a·b) I); linear in (Fg, J k̇).
  auto phi = [](const Eigen::Vector3d& om, const Eigen::Vector3d& fg, const Eigen::Vector3d& jkd)
  {
    Eigen::Matrix3d m = om * fg.transpose() - 2 * fg * om.transpose() - 2 * skew(jkd);
    m.diagonal().array() += om.dot(fg);
    return m;
  };
  Eigen::Matrix3d D2W, DGW;
  for (int e = 0; e < n; ++e)
  {
    const Element& el = k.elements[e];
    const Eigen::Vector3d kq = Q.segment<3>(3 * e), kd = Qdot.segment<3>(3 * e);
    const Eigen::Vector3d& om = el.omega0;
    Maps& m = maps[e];
    // Every moment above is linear in a few per-sample moments (ω and k̇ are the element's),
    // so only those (SampleMoments) are summed over the samples, and contracted here once
    // per element.
    SampleMoments sm;
    if (el.count >= Spec.gramMinSamples)
    {
      FunctionGram fg;
      for (int j = el.first; j < el.first + el.count; ++j)
        fg.add(k.nodes[j].w, k.nodes[j].u, k.nodes[j].coefficients);
      fg.moments(kq, kd, el.F0, sm);
    }
    else
    {
      // Y = w F0 D²g[k̇, ·] = w Σ_i f_i FB_i (helixBilinearBasis, once per element).
      Eigen::Matrix3d FB[5];
      helixBilinearBasis(kq, kd, el.F0, FB);
      for (int j = el.first; j < el.first + el.count; ++j)
      {
        const Node& nd = k.nodes[j];
        double f[7], y[9];
        helixFunctionValues(nd.u, nd.coefficients, f);
        for (int c = 0; c < 9; ++c)
          y[c] = nd.w * (f[2] * FB[0].data()[c] + f[3] * FB[1].data()[c] + f[4] * FB[2].data()[c] +
                         f[5] * FB[3].data()[c] + f[6] * FB[4].data()[c]);
        sm.add(nd.w, nd.J.data(), nd.r - el.r0, y);
      }
    }
    using M3 = Eigen::Map<const Eigen::Matrix3d>;
    using V3 = Eigen::Map<const Eigen::Vector3d>;
    const M3 PJ(sm.PJ), S2(sm.S2), Qm(sm.Qm), SD(sm.SD), R(sm.R);
    const M3 N[3] = {M3(sm.N), M3(sm.N + 9), M3(sm.N + 18)};
    const V3 X01(sm.X), X02(sm.X + 3), X12(sm.X + 6), sF(sm.sF);
    const double sc = sm.sc;
    // Σ_a k̇_a N_a = Σ w (J k̇) Fgᵀ, and J_a·Fg, J_a·ω, (Fg·ω) J_a, J_a × J k̇ summed.
    const Eigen::Matrix3d JkdF = kd[0] * N[0] + kd[1] * N[1] + kd[2] * N[2];
    const Eigen::Vector3d Xa[3] = {kd[1] * X01 + kd[2] * X02, kd[2] * X12 - kd[0] * X01,
                                   -kd[0] * X02 - kd[1] * X12}; // Σ w J_a × J k̇
    m.Sc = sc;
    m.sumFg = sF;
    m.sumR = sc * el.r0 + sF;
    m.Pc = PJ.transpose();
    Eigen::Vector3d trN, nOm[3];
    for (int a = 0; a < 3; ++a)
    {
      const M3& Na = N[a];
      trN[a] = Na.trace();        // Σ w J_a·Fg
      nOm[a].noalias() = Na * om; // Σ w (Fg·ω) J_a
      // −Jᵀ [Fg]× = ([Fg]× J)ᵀ: row a is Σ w Fg × J_a.
      m.Pl.row(a) << Na(2, 1) - Na(1, 2), Na(0, 2) - Na(2, 0), Na(1, 0) - Na(0, 1);
      // Jᵀ Φ, row a: (J_a·ω) Fgᵀ − 2 (J_a·Fg) ωᵀ + (ω·Fg) J_aᵀ − 2 (J_a × J k̇)ᵀ.
      m.Po.row(a) = (Na.transpose() * om + nOm[a] - 2 * trN[a] * om - 2 * Xa[a]).transpose();
    }
    // −[r]× [Fg]× = (r·Fg) I − Fg rᵀ with r = r0 + Fg.
    m.Tl = -S2 - sF * el.r0.transpose();
    m.Tl.diagonal().array() += el.r0.dot(sF) + S2.trace();
    const Eigen::Vector3d sumJkd = PJ * kd;
    m.So = phi(om, sF, sumJkd); // Σ w Φ
    // Σ w [r]× Φ = [r0]× Σ w Φ + Σ w [Fg]× Φ, and [Fg]× Φ = −[ω]× Fg Fgᵀ + (ω·Fg) [Fg]×
    // − 2 (J k̇ Fgᵀ − (Fg·J k̇) I).
    m.To = crossCols(el.r0, m.So) - crossCols(om, S2) + skew(S2 * om) - 2 * JkdF;
    m.To.diagonal().array() += 2 * JkdF.trace();
    // Own element: δa0 = 2 ([ω]× J + F0 D²g[k̇, ·]) δk̇ at a sample. Jᵀ [ω]× J has the
    // entries J_a·(ω × J_b) = −ω·(J_a × J_b).
    const double o01 = om.dot(X01), o02 = om.dot(X02), o12 = om.dot(X12);
    m.ownR << 0, -o01, -o02, o01, 0, -o12, o02, o12, 0;
    m.ownR = 2 * (m.ownR + Qm);
    m.ownF = 2 * (crossCols(om, PJ) + SD);
    // Σ w [Fg]× [ω]× J: column a is ω (J_a·Fg) − N_a ω.
    m.ownM = crossCols(el.r0, m.ownF);
    for (int a = 0; a < 3; ++a)
      m.ownM.col(a) += 2 * (trN[a] * om - nOm[a] + R.col(a));
    m.PhiEnd = phi(om, el.fgEnd, el.jkdEnd);
    m.fgEnd = el.fgEnd;
    m.akd = el.akd;
    helixBilinear(kq, kd, Spec.elementLengths[e], D2W, &DGW, &el.endCoefficients);
    m.Dal0 = crossCols(om, el.A) + 2 * el.F0 * DGW;
    m.Dac0 = 2 * (crossCols(om, el.jEnd) + el.F0 * D2W);
  }
  // For a column block qe, the state S_p = [δa; δα; δω] (9 × 3) at the start of each later
  // element p evolves linearly, S_{p+1} = Prop_p S_p with
  //   Prop_p = [I, −[Fg_end]×, Φ_end; 0, I, −[A k̇]×; 0, 0, I],
  // starting from S_{qe+1} = [Dac0; Dal0; A]_qe, and element p contributes R_p = P_p S_p to
  // its own row, [M_p; F_p] = Mm_p S_p to the tail torque and force felt by the rows before
  // it (row p sees A_pᵀ tailM + W_pᵀ tailF).
  // Backward, once: Λ_p = Mm_p + Λ_{p+1} Prop_p gives Σ_{p' >= p} [M_p'; F_p'] = Λ_p S_p, so
  // row p > qe is C_p,qe = G_p S_p with G_p = −ρS (P_p + [A_pᵀ W_pᵀ] Λ_{p+1} Prop_p),
  // independent of qe. Carried backward as well, the stack Γ_m (rows p >= m: the 3 × 9 maps
  // G_p Prop_{p−1} ⋯ Prop_m) gives the whole column block qe below the diagonal as ONE
  // product Γ_{qe+1} S_{qe+1} over long columns, and Γ_m = [G_m; Γ_{m+1} Prop_m] is a
  // product on long columns too (3 × 3 products block by block vectorize poorly).
  // Above the diagonal the whole tail from qe acts rigidly, C_p,qe = A_pᵀ TM + W_pᵀ TF: one
  // product B_{p<qe} [TM; TF] with B the 3N × 6 stack of the rows [A_pᵀ W_pᵀ].
  // The buffers only grow: nothing is allocated per step.
  thread_local Eigen::Matrix<double, Eigen::Dynamic, 6> B;
  thread_local Eigen::Matrix<double, Eigen::Dynamic, 9> Gam; // rows 3p..3p+2: the row p of Γ_m
  if (B.rows() < 3 * n)
  {
    B.resize(3 * n, 6);
    Gam.resize(3 * n, 9);
  }
  for (int p = 0; p < n; ++p)
  {
    B.block<3, 3>(3 * p, 0) = k.elements[p].A.transpose();
    B.block<3, 3>(3 * p, 3) = k.elements[p].W.transpose();
  }
  const Eigen::Index ldc = C.rows(), ldg = Gam.rows();
  // Λ_{qe+1} as one 6 × 9 matrix: rows 0–2 the tail torque, 3–5 the tail force; columns
  // (δa, δα, δω). Six-row products vectorize in three packets, where the eighteen 3 × 3
  // products of the same sums (the tenth revision's code) left a row over in each.
  Eigen::Matrix<double, 6, 9> L = Eigen::Matrix<double, 6, 9>::Zero();
  for (int qe = n - 1; qe >= 0; --qe)
  {
    const Maps& mq = maps[qe];
    const Element& eq = k.elements[qe];
    // Column block qe. State at the start of element qe + 1, S = [Dac; Dal; Dw].
    Eigen::Matrix<double, 9, 3> S;
    S.topRows<3>() = mq.Dac0;
    S.middleRows<3>(3) = mq.Dal0;
    S.bottomRows<3>() = eq.A;
    // Tail torque and force from the elements past qe, [HM; HF] = Λ S.
    Eigen::Matrix<double, 6, 3> H;
    H.noalias() = L * S;
    const Eigen::Matrix<double, 3, 6> Bq = B.block<3, 6>(3 * qe, 0); // [A_qeᵀ W_qeᵀ]
    Eigen::Matrix3d b = mq.ownR;
    b.noalias() += Bq * H;
    C.block<3, 3>(3 * qe, 3 * qe) = -RhoS * b;
    // Rows p < qe: [TM; TF], the rigid tail's torque and force.
    Eigen::Matrix<double, 6, 3> T;
    T.topRows<3>() = -RhoS * (mq.ownM + H.topRows<3>());
    T.bottomRows<3>() = -RhoS * (mq.ownF + H.bottomRows<3>());
    double* const col = C.data() + 3 * qe * ldc;
    stackedProduct<6, false>(col, nullptr, ldc, B.data(), B.rows(), T.data(), 3 * qe);
    // Rows p > qe: Γ_{qe+1} S; then Γ_{qe+1} Prop_qe (the rows of Γ_qe past qe).
    lowerAndPropagate(col + 3 * qe + 3, ldc, Gam.data() + 3 * qe + 3, ldg, S.data(),
                      mq.PhiEnd.data(), mq.akd.data(), mq.fgEnd.data(), 3 * (n - qe - 1));
    // Λ_{qe+1} Prop_qe, block columns (δa, δα, δω): w += a Φ_end − l [A k̇]×, l −= a [Fg_end]×
    // (w first: it uses the old l).
    L.middleCols<3>(6).noalias() += L.leftCols<3>() * mq.PhiEnd;
    L.middleCols<3>(6).noalias() -= L.middleCols<3>(3) * skew(mq.akd);
    L.middleCols<3>(3).noalias() -= L.leftCols<3>() * skew(mq.fgEnd);
    // G_qe = −ρS (P_qe + [A_qeᵀ W_qeᵀ] Λ_{qe+1} Prop_qe): row qe of Γ_qe.
    Eigen::Matrix<double, 3, 9> G;
    G.leftCols<3>() = mq.Pc;
    G.middleCols<3>(3) = mq.Pl;
    G.rightCols<3>() = mq.Po;
    G.noalias() += Bq * L;
    Gam.block<3, 9>(3 * qe, 0) = -RhoS * G;
    // Λ_qe = Mm_qe + Λ_{qe+1} Prop_qe: tail torque [[Σ w r]×, Tl, To], force [Σ w I, −[Σ w Fg]×,
    // So].
    L.block<3, 3>(0, 0) += skew(mq.sumR);
    L.block<3, 3>(0, 3) += mq.Tl;
    L.block<3, 3>(0, 6) += mq.To;
    L.block<3, 3>(3, 0).diagonal().array() += mq.Sc;
    L.block<3, 3>(3, 3) -= skew(mq.sumFg);
    L.block<3, 3>(3, 6) += mq.So;
  }
}

void SuperHelix::addContactJacobians(double h)
{
  // Backward Euler on the linearized contact force f − K h (v0 + J q̇ⁿ⁺¹) − D J (q̇ⁿ⁺¹ − q̇ⁿ):
  //   Lhs += Σ w Jᵀ S J,  S = h² K + h D,  Rhs += Σ w Jᵀ b,  b = h D J q̇ⁿ − h² K v0.
  // A sample of element e has J_p = −[r]× A_p + W_p = H(r) Z_p for p < e, with
  // H(r) = [−[r]×  I] (3 × 6) and Z_p = [A_p; W_p] (6 × 3), its own block J_e, and 0 past e.
  // So only per-element moments of the samples in contact are summed,
  //   Φ_e = Σ w Hᵀ S H (6 × 6), Ψ_e = Σ w Hᵀ S J_e, Ψ'_e = Σ w J_eᵀ S H, Ω_e = Σ w J_eᵀ S J_e,
  //   β_e = Σ w Hᵀ b, γ_e = Σ w J_eᵀ b,
  // and with the tail T_q = Σ_{e > q} Φ_e (and β's), for p < q:
  //   block(p, q) = Z_pᵀ (T_q Z_q + Ψ_q),  block(q, p) = (Z_qᵀ T_q + Ψ'_q) Z_p,
  //   block(q, q) = Z_qᵀ T_q Z_q + Ω_q,   Rhs_q = Z_qᵀ Σ_{e > q} β_e + γ_q:
  // O(N²) per strand plus O(1) per sample in contact, like the mass matrix. (Forming
  // Σ w Jᵀ S J sample by sample costs O(e²) per sample: a 40-element strand lying on the
  // scalp took 3 × the step without contacts.) S need not be symmetric (friction).
  using Mat6 = Eigen::Matrix<double, 6, 6>;
  using Mat63 = Eigen::Matrix<double, 6, 3>;
  using Mat36 = Eigen::Matrix<double, 3, 6>;
  using Vec6 = Eigen::Matrix<double, 6, 1>;
  struct Moments
  {
    Mat6 phi;
    Mat63 psi;
    Mat36 psiT;
    Eigen::Matrix3d omega;
    Vec6 beta;
    Eigen::Vector3d gamma;
  };
  const int n = elementCount();
  detail::StepWorkspace& ws = detail::stepWorkspace();
  const std::vector<ContactResponse>& responses = ws.ContactBuffer;
  Eigen::MatrixXd& Lhs = ws.Lhs;
  Eigen::VectorXd& Rhs = ws.Rhs;
  thread_local std::vector<Moments> mom;
  thread_local std::vector<char> touched;
  mom.resize(n);
  touched.assign(n, 0);
  int last = -1;
  for (size_t j = 0; j < Cur.nodes.size(); ++j)
  {
    const Node& nd = Cur.nodes[j];
    if (!nd.hasK && !nd.hasD)
      continue;
    // K and D stay in the hook's buffer (hasK/hasD are set only from it, this step).
    const Eigen::Matrix3d& contactK = responses[j].stiffness;
    const Eigen::Matrix3d& contactD = responses[j].damping;
    Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    if (nd.hasK)
    {
      S += (nd.w * h * h) * contactK;
      b -= (nd.w * h * h) * (contactK * nd.v0);
    }
    if (nd.hasD)
    {
      S += (nd.w * h) * contactD;
      b += (nd.w * h) * (contactD * (nd.v - nd.v0)); // J q̇ⁿ = v − v0
    }
    const int e = nd.element;
    Moments& m = mom[e];
    if (!touched[e])
    {
      m.phi.setZero();
      m.psi.setZero();
      m.psiT.setZero();
      m.omega.setZero();
      m.beta.setZero();
      m.gamma.setZero();
      touched[e] = 1;
    }
    last = std::max(last, e);
    // S H = [−S [r]×  S] and Hᵀ X = [[r]× X; X] ((−[r]×)ᵀ = [r]×); −X [r]× = ([r]× Xᵀ)ᵀ.
    const Eigen::Matrix3d SR = crossCols(nd.r, S.transpose()).transpose(); // −S [r]×
    const Eigen::Matrix3d SJ = S * nd.J, JtS = nd.J.transpose() * S;
    m.phi.block<3, 3>(0, 0) += crossCols(nd.r, SR);
    m.phi.block<3, 3>(0, 3) += crossCols(nd.r, S);
    m.phi.block<3, 3>(3, 0) += SR;
    m.phi.block<3, 3>(3, 3) += S;
    m.psi.topRows<3>() += crossCols(nd.r, SJ);
    m.psi.bottomRows<3>() += SJ;
    m.psiT.leftCols<3>() += crossCols(nd.r, JtS.transpose()).transpose(); // −Jᵀ S [r]×
    m.psiT.rightCols<3>() += JtS;
    m.omega.noalias() += JtS * nd.J;
    m.beta.head<3>() += nd.r.cross(b);
    m.beta.tail<3>() += b;
    m.gamma.noalias() += nd.J.transpose() * b;
  }
  if (last < 0)
    return;
  // The stack of the rows Z_pᵀ = [A_pᵀ W_pᵀ], as for M and C.
  thread_local Eigen::Matrix<double, Eigen::Dynamic, 6> B;
  if (B.rows() < 3 * n)
    B.resize(3 * n, 6);
  for (int p = 0; p <= last; ++p)
  {
    B.block<3, 3>(3 * p, 0) = Cur.elements[p].A.transpose();
    B.block<3, 3>(3 * p, 3) = Cur.elements[p].W.transpose();
  }
  const Eigen::Index ld = Lhs.rows(), lds = B.rows();
  Mat6 T = Mat6::Zero();
  Vec6 tailBeta = Vec6::Zero();
  for (int q = last; q >= 0; --q)
  {
    const Mat63 Z = B.block<3, 6>(3 * q, 0).transpose(); // [A_q; W_q]
    Mat63 upper = T * Z;                                 // T_q Z_q (+ Ψ_q below)
    Mat36 lower = Z.transpose() * T;                     // Z_qᵀ T_q (+ Ψ'_q below)
    Eigen::Matrix3d diag = Z.transpose() * upper;
    Eigen::Vector3d rhs = Z.transpose() * tailBeta;
    if (touched[q])
    {
      const Moments& m = mom[q];
      upper += m.psi;
      lower += m.psiT;
      diag += m.omega;
      rhs += m.gamma;
      T += m.phi;
      tailBeta += m.beta;
    }
    Lhs.block<3, 3>(3 * q, 3 * q) += diag;
    Rhs.segment<3>(3 * q) += rhs;
    // Rows p < q of column block q, and columns p < q of row block q (transposed: the
    // same stacked product with lowerᵀ, written to the mirrored places).
    const Eigen::Matrix<double, 6, 3> lowerT = lower.transpose();
    stackedProductAdd<6>(Lhs.data() + 3 * q * ld, 1, ld, B.data(), lds, upper.data(), 3 * q);
    stackedProductAdd<6>(Lhs.data() + 3 * q, ld, 1, B.data(), lds, lowerT.data(), 3 * q);
  }
}

Status SuperHelix::solve(double h, Eigen::VectorXd& qdotNext)
{
  // (M + hΓ + h²(𝕂 + K_T) + h D_air − ½ h C) q̇ⁿ⁺¹ = M q̇ⁿ + h (f − 𝕂 (qⁿ − q_rest) − ½ C q̇ⁿ)
  // (docs/super-helix.md). D_air = ν ∫ JᵀJ, taken as (ν / ρS) M for a uniform strand (M's
  // rotary-inertia share, < 1e-5 of it, gets the same factor). f is quadratic in q̇,
  // f = f₀ + L q̇ + Q(q̇, q̇), C = ∂f/∂q̇ = L + 2 Q(q̇ⁿ, ·), so f − ½ C q̇ⁿ + ½ C q̇ⁿ⁺¹ =
  // f₀ + L (q̇ⁿ + q̇ⁿ⁺¹)/2 + Q(q̇ⁿ, q̇ⁿ⁺¹): the linear (gyroscopic) terms at the midpoint,
  // one factor of the quadratic ones at the new velocity.
  const double airScale = 1 + h * Spec.hair.airFriction / RhoS;
  detail::StepWorkspace& ws = detail::stepWorkspace();
  const Eigen::MatrixXd &M = ws.M, &C = ws.C, &Kt = ws.Kt;
  Eigen::MatrixXd& Lhs = ws.Lhs;
  Eigen::VectorXd& Rhs = ws.Rhs;
  const int m = static_cast<int>(M.rows());
  Lhs.resize(m, m);
  Rhs = h * (F - (Kdiag.array() * (Q - Qrest).array()).matrix());
  // Lhs and M q̇ − ½ h C q̇ in one pass over M, C and K_T.
  if (!formStepSystem(Lhs.data(), Rhs.data(), M.data(), C.data(), Kt.data(), Qdot.data(), m,
                      airScale, 0.5 * h, h * h))
    return Status::Error("the step's matrix (mass matrix, velocity Jacobian or tension "
                         "stiffness) is not finite. Check the root motion and forces");
  Lhs.diagonal() += h * Gdiag + h * h * Kdiag;
  if (ContactsSet) // else no sample has a contact stiffness or damping: skip the pass
    addContactJacobians(h);
  const double scale = Lhs.diagonal().cwiseAbs().maxCoeff();
  if (m > UnblockedLuMax)
  {
    // Large systems: Eigen's blocked LU (its cache blocking pays off past 3N = 360).
    Eigen::PartialPivLU<Eigen::MatrixXd>& Lu = ws.Lu;
    Lu.compute(Lhs);
    const double pivotL = Lu.matrixLU().diagonal().cwiseAbs().minCoeff();
    if (!(pivotL > 1e-30 * scale))
      return Status::Error("the step's matrix is singular (smallest pivot " +
                           std::to_string(pivotL) + ")");
    qdotNext = Lu.solve(Rhs);
    return Status::Ok();
  }
  // Small systems: LU with partial pivoting (row interchanges, as LAPACK getrf / Eigen's
  // PartialPivLU) in panels of four columns, without packing: at 3N = 30 Eigen's blocked
  // kernel spent most of its time in packing and dispatch.
  std::vector<int>& Pivots = ws.Pivots;
  Pivots.resize(static_cast<size_t>(m));
  const double pivot = luSolveInPlace(Lhs.data(), Rhs.data(), m, Pivots.data());
  if (!(pivot > 1e-30 * scale))
    return Status::Error("the step's matrix is singular (smallest pivot " + std::to_string(pivot) +
                         ")");
  qdotNext = Rhs;
  return Status::Ok();
}

Status SuperHelix::step(double dt)
{
  Status st = checkStep(dt);
  if (!st)
    return st;
  st = singleStep(dt);
  if (!st)
    reconstruct(); // singleStep keeps q, q̇, time and energies; refresh the kinematics
  return st;
}

Status SuperHelix::checkStep(double dt) const
{
  if (!Initialized)
    return Status::Error("SuperHelix::step: the strand is not initialized; call initialize().");
  if (!(std::isfinite(dt) && dt > 0))
  {
    std::ostringstream s;
    s << "strand '" << Spec.name << "' (id " << Spec.id << ") at t = " << Time << " s: dt = " << dt
      << " is invalid; the time step must be finite and > 0 seconds "
      << "(1/30 is stable for every preset).";
    return Status::Error(s.str());
  }
  return Status::Ok();
}

Status SuperHelix::stepCount(double dt, int count)
{
  if (count == 1)
    return singleStep(dt);
  const Eigen::VectorXd q0 = Q, qd0 = Qdot;
  const double t0 = Time;
  const EnergyReport e0 = Energy;
  EnergyTerms sum;
  for (int i = 0; i < count; ++i)
  {
    const Status st = singleStep(dt / count);
    if (!st)
    {
      Q = q0;
      Qdot = qd0;
      Time = t0;
      Energy = e0;
      reconstruct();
      return st;
    }
    const EnergyTerms& l = Energy.lastStep;
    sum.frictionDissipated += l.frictionDissipated;
    sum.airDissipated += l.airDissipated;
    sum.rootWork += l.rootWork;
    sum.windWork += l.windWork;
    sum.contactWork += l.contactWork;
    sum.loadWork += l.loadWork;
    sum.residual += l.residual;
  }
  Energy.lastStep = sum;
  LastSubsteps = count;
  return Status::Ok();
}

Status SuperHelix::singleStep(double h)
{
  LastSubsteps = 1;
  if (!Initialized)
    return Status::Error("SuperHelix::step: the strand is not initialized; call initialize().");
  if (!(std::isfinite(h) && h > 0))
  {
    std::ostringstream s;
    s << "strand '" << Spec.name << "' (id " << Spec.id << ") at t = " << Time << " s: dt = " << h
      << " is invalid; the time step must be finite and > 0 seconds "
      << "(1/30 is stable for every preset).";
    return Status::Error(s.str());
  }
  const double t0 = Time, t1 = Time + h;
  if (!CurValid)
    reconstruct();
  // The contact response in the step workspace is this strand's only until the step ends.
  struct EndOfStep
  {
    bool& contactsSet;
    ~EndOfStep() { contactsSet = false; }
  } endOfStep{ContactsSet};
  Status st = evaluateForces(Cur, t0);
  if (!st)
    return Status::Error(where(t0, t1) + st.message());
  assemble();
  assembleVelocityJacobian();
  assembleTensionStiffness(h);
  if (!F.allFinite())
    return Status::Error(where(t0, t1) +
                         "the generalized forces are not finite; the previous state is kept. "
                         "Check the root motion and forces.");
  Eigen::VectorXd qdN;
  st = solve(h, qdN);
  if (!st)
    return Status::Error(where(t0, t1) + st.message() + "; the previous state is kept.");
  const Eigen::VectorXd qN = Q + h * qdN;
  if (!qN.allFinite() || !qdN.allFinite())
    return Status::Error(
        where(t0, t1) +
        "the step blew up (non-finite curvature); the previous state is kept. Reduce dt or "
        "check the forces.");
  // A fibre cannot bend tighter than its own radius: past that the model is meaningless.
  const double limit = 1.0 / Spec.hair.radius;
  for (int e = 0; e < elementCount(); ++e)
  {
    const double om = qN.segment<3>(3 * e).norm();
    if (om > limit)
    {
      std::ostringstream s;
      s << where(t0, t1) << "the step blew up: element " << e << " reached curvature " << om
        << " 1/m, tighter than 1/radius = " << limit
        << " 1/m; the previous state is kept. Reduce dt or check the forces.";
      return Status::Error(s.str());
    }
  }
  const RootState rootN = rootState(t1);
  st = rootN.validate();
  if (!st)
    return Status::Error(where(t0, t1) + st.message());

  // Energy flows over the step, at the configuration of tⁿ with the velocity of the step
  // ṽ = v0 + J q̇ⁿ⁺¹ and the acceleration r̈ = a0 + J q̈, q̈ = (q̇ⁿ⁺¹ − q̇ⁿ)/h.
  EnergyTerms flow;
  {
    const Eigen::VectorXd qdd = (qdN - Qdot) / h;
    const double nu = Spec.hair.airFriction;
    const Eigen::Vector3d* const winds = Spec.windField ? Winds.data() : nullptr;
    const ContactResponse* const contacts =
        ContactsSet ? detail::stepWorkspace().ContactBuffer.data() : nullptr;
    Eigen::Vector3d pa = Eigen::Vector3d::Zero(), pw = Eigen::Vector3d::Zero();
    Eigen::Vector3d sa = Eigen::Vector3d::Zero(), sw = Eigen::Vector3d::Zero();
    for (int e = 0; e < elementCount(); ++e)
    {
      const Element& el = Cur.elements[e];
      const Eigen::Vector3d x = qdN.segment<3>(3 * e), y = qdd.segment<3>(3 * e);
      for (int j = el.first; j < el.first + el.count; ++j)
      {
        const Node& nd = Cur.nodes[j];
        const Eigen::Vector3d vt = nd.v0 + pa.cross(nd.r) + pw + nd.J * x;
        const Eigen::Vector3d rdd = nd.a0 + sa.cross(nd.r) + sw + nd.J * y;
        const Eigen::Vector3d& wind = winds ? winds[j] : Spec.wind;
        const Eigen::Vector3d rel = vt - wind;
        flow.airDissipated += h * nd.w * nu * rel.squaredNorm();
        flow.windWork -= h * nd.w * nu * rel.dot(wind);
        // The contact force that acted: its implicit linearization (see ContactResponse).
        Eigen::Vector3d fc = Eigen::Vector3d::Zero();
        if (contacts)
        {
          if (nd.hasF)
            fc = contacts[j].force;
          if (nd.hasK)
            fc -= h * (contacts[j].stiffness * vt);
          if (nd.hasD)
            fc -= contacts[j].damping * (vt - nd.v);
        }
        flow.contactWork += h * nd.w * fc.dot(vt);
        const Eigen::Vector3d f = RhoS * Spec.gravity - nu * rel + fc;
        flow.rootWork += h * nd.w * (RhoS * rdd - f).dot(nd.v0);
      }
      pa += el.A * x;
      pw += el.W * x;
      sa += el.A * y;
      sw += el.W * y;
    }
    if (!Spec.tipForce.isZero(0))
    {
      const Eigen::Vector3d& rt = Cur.tip.r0;
      const Eigen::Vector3d v0t =
          Cur.root.velocity + Cur.root.angularVelocity.cross(rt - Cur.root.position);
      flow.loadWork += h * Spec.tipForce.dot(v0t + pa.cross(rt) + pw);
      flow.rootWork -= h * Spec.tipForce.dot(v0t);
    }
    flow.frictionDissipated = h * (Gdiag.array() * qdN.array().square()).sum();
  }

  // The new state's kinematics go to a per-thread buffer that is swapped with Cur on
  // commit, so each strand keeps one set of samples (not two): with hundreds of strands
  // stepped in turn, the strand's data streamed through the caches is what a step costs.
  thread_local Kinematics next;
  kinematics(qN, qdN, rootN, t1, next);
  const double elastic = elasticEnergy(qN);
  const double e0 = Energy.mechanical();
  const double e1 = next.kinetic + elastic + next.gravitational;
  if (!std::isfinite(e1))
    return Status::Error(where(t0, t1) + "the energy is not finite; the previous state is kept.");
  flow.residual = e1 - e0 - flow.rootWork - flow.windWork - flow.contactWork - flow.loadWork +
                  flow.frictionDissipated + flow.airDissipated;

  // Commit.
  Q = qN;
  Qdot = qdN;
  Time = t1;
  std::swap(Cur, next);
  newCurId();
  CurValid = true;
  WindsValid = false; // the wind field at the new samples is evaluated when needed
  Energy.time = t1;
  Energy.kinetic = Cur.kinetic;
  Energy.gravitational = Cur.gravitational;
  Energy.elastic = elastic;
  Energy.lastStep = flow;
  Energy.total.frictionDissipated += flow.frictionDissipated;
  Energy.total.airDissipated += flow.airDissipated;
  Energy.total.rootWork += flow.rootWork;
  Energy.total.windWork += flow.windWork;
  Energy.total.contactWork += flow.contactWork;
  Energy.total.loadWork += flow.loadWork;
  Energy.total.residual += flow.residual;
  return Status::Ok();
}

Status SuperHelix::setState(const Eigen::VectorXd& q, const Eigen::VectorXd& qdot)
{
  if (!Initialized)
    return Status::Error("SuperHelix::setState: the strand is not initialized.");
  const int n = 3 * elementCount();
  if (q.size() != n || qdot.size() != n)
    return Status::Error("strand '" + Spec.name +
                         "': setState needs q and qdot of size 3N = " + std::to_string(n) + ".");
  if (!q.allFinite() || !qdot.allFinite())
    return Status::Error("strand '" + Spec.name + "': setState got non-finite q or qdot.");
  Q = q;
  Qdot = qdot;
  reconstruct();
  Energy.time = Time;
  Energy.kinetic = Cur.kinetic;
  Energy.gravitational = Cur.gravitational;
  Energy.elastic = elasticEnergy(Q);
  return Status::Ok();
}

Status SuperHelix::advance(double dt, double tolerance, int maxDepth)
{
  if (!(tolerance > 0))
    return step(dt);
  Status st = checkStep(dt);
  if (!st)
    return st;
  // Step doubling: n sub-steps against 2n, on every element end, doubling n until they
  // agree within `tolerance`; the finer result is kept.
  int n = 1;
  const Eigen::VectorXd q0 = Q, qd0 = Qdot;
  const double t0 = Time;
  const EnergyReport en0 = Energy;
  auto restore = [&]()
  {
    Q = q0;
    Qdot = qd0;
    Time = t0;
    Energy = en0;
    reconstruct();
  };
  auto ends = [&]()
  {
    std::vector<Eigen::Vector3d> e;
    for (const Element& el : Cur.elements)
      e.push_back(el.r0);
    e.push_back(Cur.tip.r0);
    return e;
  };
  Status prev = stepCount(dt, n);
  std::vector<Eigen::Vector3d> prevEnds;
  if (prev)
    prevEnds = ends();
  for (int depth = 0; depth < maxDepth && 2 * n <= MaxSubsteps; ++depth)
  {
    restore();
    n *= 2;
    st = stepCount(dt, n);
    if (st && prev)
    {
      const std::vector<Eigen::Vector3d> e = ends();
      double err = 0;
      for (size_t i = 0; i < e.size(); ++i)
        err = std::max(err, (e[i] - prevEnds[i]).norm());
      if (err <= tolerance)
        return Status::Ok();
      prevEnds = e;
    }
    else if (st)
      prevEnds = ends();
    prev = st;
  }
  if (!st)
    restore();
  return st;
}

void SuperHelix::prefetch() const
{
  auto lines = [](const void* p, size_t bytes)
  {
    const char* c = static_cast<const char*>(p);
    for (size_t off = 0; off < bytes; off += 64)
      __builtin_prefetch(c + off);
  };
  lines(Cur.nodes.data(), Cur.nodes.size() * sizeof(Node));
  lines(Cur.elements.data(), Cur.elements.size() * sizeof(Element));
  lines(Q.data(), Q.size() * sizeof(double));
  lines(Qdot.data(), Qdot.size() * sizeof(double));
}

Status stepStrands(std::vector<SuperHelix>& strands, double dt, int threads, double tolerance)
{
  const int count = static_cast<int>(strands.size());
  std::vector<Status> results(strands.size());
  threads = std::max(1, std::min(threads, count));
  // Threads take chunks of consecutive strands, so that the strand after the current one
  // in a chunk is stepped by the same thread, later: while one strand computes, the next
  // one's samples are brought in from memory (a strand's data is not in cache when
  // hundreds are stepped in turn, and its loads are too scattered for the hardware's
  // prefetcher). Prefetching a strand another thread may be stepping would read its
  // buffers while they are swapped.
  // Chunks of 8, smaller when there are few strands (at least four chunks per thread).
  const int Chunk = std::max(1, std::min(8, count / (4 * threads)));
  std::atomic<int> next{0};
  auto work = [&]()
  {
    for (int first = next.fetch_add(Chunk); first < count; first = next.fetch_add(Chunk))
    {
      const int last = std::min(count, first + Chunk);
      for (int i = first; i < last; ++i)
      {
        if (i + 1 < last)
          strands[i + 1].prefetch();
        results[i] = strands[i].advance(dt, tolerance);
      }
    }
  };
  if (threads == 1)
    work();
  else
  {
    std::vector<std::thread> pool;
    try
    {
      for (int t = 1; t < threads; ++t)
        pool.emplace_back(work);
    }
    catch (...)
    {
      // No more threads available: the calling thread does the rest.
    }
    work();
    for (auto& th : pool)
      th.join();
  }
  for (const Status& s : results)
    if (!s)
      return s;
  return Status::Ok();
}

Status findHairHairContacts(const std::vector<SuperHelix>& strands, HairHairContacts& contacts)
{
  std::vector<std::vector<StrandSample>> samples(strands.size());
  std::vector<int> ids(strands.size());
  for (std::size_t i = 0; i < strands.size(); ++i)
  {
    samples[i] = strands[i].samples();
    ids[i] = strands[i].spec().id;
  }
  return contacts.update(samples, ids);
}

} // namespace hair
