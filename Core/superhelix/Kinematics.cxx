// The reconstruction of the rod from q and q̇: SuperHelix::kinematics (every quadrature
// sample's position, velocity, Jacobian and q̈ = 0 acceleration, the element ends' frames and
// the tail Jacobians, the kinetic and gravitational energies), reconstruct() and the air's
// velocity at the samples, and the queries of the current state at an arc length
// (position, frame, velocity, jacobian, accelerationAtRest, polyline, samples).
#include "superhelix/SuperHelix.h"

#include "helix/HelixFunctions.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace hair
{

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
  double kinetic = 0, grav = 0, carried = 0;
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
      // once per element (two cross products per sample and the sums of y = F0ᵀ ω + G k̇
      // would be ~20 % of the reconstruction's time, perf cpu-clock samples).
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
        // one sincos per pair instead of two (one per node would be 5 % of a fuzzy step's
        // time, perf cpu-clock samples). X is the end's angle when the element is one interval.
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
          nd.hasF = nd.hasK = nd.hasD = nd.hasField = false;
          // The cross-section's angular velocity in its own frame (see omO above).
          const Eigen::Vector3d omLocal = omO[0] + f[0] * omO[1] +
                                          (nd.u * nd.coefficients.phi0) * omO[2] + f[1] * omO[3] +
                                          f[2] * omO[4];
          kinetic += 0.5 * nd.w * (RhoS * nd.v.squaredNorm() + RotI.dot(omLocal.cwiseAbs2()));
          carried += nd.w * nd.v.dot(nd.v0);
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
  out.carried = RhoS * carried;
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

void SuperHelix::sampleVelocities(const Eigen::VectorXd& x, bool carried,
                                  std::vector<Eigen::Vector3d>& out) const
{
  // J_P(s) = A_P × r(s) + W_P for the elements P before the sample's, its own block after
  // (summed after v0 when `carried`, in the order the energy flows and the kinematics take).
  out.resize(Cur.nodes.size());
  Eigen::Vector3d pa = Eigen::Vector3d::Zero(), pw = Eigen::Vector3d::Zero();
  for (int e = 0; e < elementCount(); ++e)
  {
    const Element& el = Cur.elements[e];
    const Eigen::Vector3d xe = x.segment<3>(3 * e);
    for (int j = el.first; j < el.first + el.count; ++j)
    {
      const Node& nd = Cur.nodes[j];
      const Eigen::Vector3d base = carried ? nd.v0 : Eigen::Vector3d(Eigen::Vector3d::Zero());
      out[j] = base + pa.cross(nd.r) + pw + nd.J * xe;
    }
    pa += el.A * xe;
    pw += el.W * xe;
  }
}

} // namespace hair
