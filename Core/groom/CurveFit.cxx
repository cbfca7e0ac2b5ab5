// fitSuperHelix: a first guess element by element (the curve's rotation-minimizing frame
// gives each element's curvature and twist, then a small least-squares fit of each element
// to the points it covers, chained from the root), then Levenberg–Marquardt on every
// coordinate, the root tangent and the length at once, each curve point measured from its
// foot point on the strand (orthogonal distance). docs/super-helix.md, "Fitting a guide
// curve", gives the choices and the expected order.
#include "groom/CurveFit.h"

#include "helix/HelixFunctions.h"
#include "strands/GuideStrand.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace hair
{

namespace
{

/// The rotation vector of the smallest rotation taking unit a to unit b.
Eigen::Vector3d turning(const Eigen::Vector3d& a, const Eigen::Vector3d& b)
{
  const Eigen::Vector3d c = a.cross(b);
  const double s = c.norm(), cs = a.dot(b);
  if (s < 1e-300)
  {
    return Eigen::Vector3d::Zero(); // parallel (an antiparallel pair is refused before)
  }
  return (std::atan2(s, cs) / s) * c;
}

Eigen::Matrix3d rotation(const Eigen::Vector3d& v)
{
  const double a = v.norm();
  return a > 0 ? Eigen::AngleAxisd(a, v / a).toRotationMatrix() : Eigen::Matrix3d::Identity();
}

/// A Super-Helix of n equal elements: each element's start frame and point, and what a
/// point further along needs of it (the tail's rigid motion under a change of the element's
/// coordinates or length).
struct Chain
{
  int n = 0;
  double l = 0;                       // element length
  std::vector<Eigen::Matrix3d> F;     // start frames, F[n] the tip's
  std::vector<Eigen::Vector3d> r;     // start points, r[n] the tip
  std::vector<Eigen::Matrix3d> A;     // F_e G(l): ∂(tail rotation)/∂k_e
  std::vector<Eigen::Matrix3d> Jend;  // F_e ∂g/∂k at the element's end
  std::vector<Eigen::Vector3d> omega; // F_e k_e: the element's Darboux vector (world)

  void build(const Eigen::VectorXd& q, const Eigen::Matrix3d& F0, const Eigen::Vector3d& r0,
             double length)
  {
    n = static_cast<int>(q.size() / 3);
    l = length / n;
    F.resize(n + 1);
    r.resize(n + 1);
    A.resize(n);
    Jend.resize(n);
    omega.resize(n);
    F[0] = F0;
    r[0] = r0;
    HelixEnd he;
    for (int e = 0; e < n; ++e)
    {
      const Eigen::Vector3d k = q.segment<3>(3 * e);
      helixEnd(k, Eigen::Vector3d::Zero(), l, he);
      A[e] = F[e] * he.G;
      Jend[e] = F[e] * he.dg;
      omega[e] = F[e] * k;
      r[e + 1] = r[e] + F[e] * he.g;
      F[e + 1] = F[e] * he.E;
    }
  }

  /// Element and distance into it of the arc length s (clamped to the strand).
  int locate(double s, double& u) const
  {
    s = std::clamp(s, 0.0, n * l);
    const int e = std::min(n - 1, static_cast<int>(s / l));
    u = s - e * l;
    return e;
  }

  /// Position, tangent and, optionally, the 3 × (3n + 3) Jacobian of the position with
  /// respect to (q, the root's rotation about n1 and n2, the length) at arc length s.
  void point(const Eigen::VectorXd& q, double s, Eigen::Vector3d& x, Eigen::Vector3d& t,
             Eigen::Matrix3Xd* J, int* element = nullptr) const
  {
    double u;
    const int e = locate(s, u);
    if (element)
    {
      *element = e;
    }
    HelixEnd he;
    helixEnd(q.segment<3>(3 * e), Eigen::Vector3d::Zero(), u, he);
    x = r[e] + F[e] * he.g;
    t = F[e] * he.E.col(0);
    if (!J)
    {
      return;
    }
    Eigen::Matrix3Xd& j = *J;
    j.setZero(3, 3 * n + 3);
    Eigen::Vector3d dL = (u / l) * t;
    for (int p = 0; p < e; ++p)
    {
      const Eigen::Vector3d arm = x - r[p + 1];
      for (int i = 0; i < 3; ++i)
      {
        j.col(3 * p + i) = A[p].col(i).cross(arm) + Jend[p].col(i);
      }
      // Lengthening element p moves its end along its end tangent and turns the tail
      // about its end by its Darboux vector.
      dL += F[p + 1].col(0) + omega[p].cross(arm);
    }
    j.middleCols<3>(3 * e) = F[e] * he.dg;
    const Eigen::Vector3d arm0 = x - r[0];
    j.col(3 * n) = F[0].col(1).cross(arm0);
    j.col(3 * n + 1) = F[0].col(2).cross(arm0);
    j.col(3 * n + 2) = dL / n;
  }
};

/// A polyline with at least `perElement` points per element (points added on its chords),
/// and its cumulative chord length.
void refine(const std::vector<Eigen::Vector3d>& curve, int elements, int perElement,
            std::vector<Eigen::Vector3d>& points, std::vector<double>& sigma)
{
  double total = 0;
  for (std::size_t j = 1; j < curve.size(); ++j)
  {
    total += (curve[j] - curve[j - 1]).norm();
  }
  points.clear();
  points.push_back(curve[0]);
  const bool enough = static_cast<int>(curve.size()) - 1 >= perElement * elements;
  const double target = total / (perElement * elements);
  for (std::size_t j = 1; j < curve.size(); ++j)
  {
    const double h = (curve[j] - curve[j - 1]).norm();
    const int parts = enough ? 1 : std::max(1, static_cast<int>(std::ceil(h / target - 1e-9)));
    for (int i = 1; i <= parts; ++i)
    {
      points.push_back(curve[j - 1] + (double(i) / parts) * (curve[j] - curve[j - 1]));
    }
    points.back() = curve[j];
  }
  // Arc length: each chord lengthened to the arc of the circle that turns, over the
  // chord, the mean of the turnings at its two ends, (θ/2) / sin(θ/2) (exact on a circle;
  // curled hair drawn at a few points per turn has chords several per cent shorter than
  // its arcs, which the first guess would otherwise inherit).
  const std::size_t M = points.size() - 1;
  std::vector<double> turn(M + 1, 0.0);
  for (std::size_t j = 1; j < M; ++j)
  {
    const Eigen::Vector3d a = (points[j] - points[j - 1]).normalized();
    const Eigen::Vector3d b = (points[j + 1] - points[j]).normalized();
    turn[j] = std::atan2(a.cross(b).norm(), a.dot(b));
  }
  sigma.assign(points.size(), 0.0);
  for (std::size_t j = 1; j <= M; ++j)
  {
    const int ends = (j - 1 > 0 ? 1 : 0) + (j < M ? 1 : 0);
    const double theta = ends > 0 ? (turn[j - 1] + turn[j]) / ends : 0.0;
    const double half = 0.5 * std::min(theta, 3.0);
    const double stretch = half > 1e-8 ? half / std::sin(half) : 1.0;
    sigma[j] = sigma[j - 1] + stretch * (points[j] - points[j - 1]).norm();
  }
}

/// First guess of q, element by element. The curve's rotation-minimizing (Bishop) frame,
/// transported chord to chord from the root frame, has no twist; its curvature m(s) =
/// (m1, m2) turns at the curve's torsion. A Super-Helix element is a constant (τ, κ1, κ2) in
/// a material frame that rolls by ψ' = τ against the Bishop frame, so τ_e is the rate at
/// which m turns over the element (a weighted line fit of its angle) and (κ1, κ2)_e the
/// mean of m turned back by the roll (exact for a helix).
Eigen::VectorXd bishopGuess(const std::vector<Eigen::Vector3d>& x, const std::vector<double>& sigma,
                            const Eigen::Matrix3d& rootFrame, int n)
{
  const std::size_t M = x.size() - 1;
  const double L = sigma.back(), l = L / n;
  // Curvature samples (position along the curve, weight, Bishop components).
  struct Sample
  {
    double s, w;
    Eigen::Vector2d m;
  };
  std::vector<Sample> samples;
  Eigen::Matrix3d B = rootFrame;
  Eigen::Vector3d prev = rootFrame.col(0);
  for (std::size_t j = 0; j < M; ++j)
  {
    const double h = sigma[j + 1] - sigma[j];
    const Eigen::Vector3d d = (x[j + 1] - x[j]).normalized();
    const Eigen::Vector3d v = turning(prev, d);
    const double span = j == 0 ? 0.5 * h : 0.5 * (h + sigma[j] - sigma[j - 1]);
    const Eigen::Vector3d local = B.transpose() * v / span;
    samples.push_back({sigma[j], span, Eigen::Vector2d(local.y(), local.z())});
    B = rotation(v) * B;
    prev = d;
  }
  Eigen::VectorXd q = Eigen::VectorXd::Zero(3 * n);
  double psi = 0, lastTwist = 0;
  std::size_t first = 0;
  for (int e = 0; e < n; ++e)
  {
    const double a = e * l, b = (e + 1) * l;
    std::vector<const Sample*> in;
    while (first < samples.size() && samples[first].s < a)
    {
      ++first;
    }
    for (std::size_t j = first; j < samples.size() && samples[j].s < b; ++j)
    {
      in.push_back(&samples[j]);
    }
    // Twist: the weighted slope of the unwrapped angle of m.
    double twist = lastTwist;
    double sw = 0, ss = 0, sp = 0, sss = 0, ssp = 0, prevAngle = 0, unwrapped = 0;
    int used = 0;
    for (const Sample* p : in)
    {
      const double w = p->w * p->m.squaredNorm();
      if (!(w > 0))
      {
        continue;
      }
      const double angle = std::atan2(p->m.y(), p->m.x());
      unwrapped = used == 0 ? angle : unwrapped + std::remainder(angle - prevAngle, 2 * M_PI);
      prevAngle = angle;
      ++used;
      sw += w;
      ss += w * p->s;
      sp += w * unwrapped;
      sss += w * p->s * p->s;
      ssp += w * p->s * unwrapped;
    }
    const double det = sw * sss - ss * ss;
    if (used >= 3 && det > 1e-12 * sw * sw * l * l)
    {
      twist = (sw * ssp - ss * sp) / det;
    }
    Eigen::Vector2d kappa = Eigen::Vector2d::Zero();
    double weight = 0;
    for (const Sample* p : in)
    {
      const double ang = -(psi + twist * (p->s - a));
      const double c = std::cos(ang), s = std::sin(ang);
      kappa += p->w * Eigen::Vector2d(c * p->m.x() - s * p->m.y(), s * p->m.x() + c * p->m.y());
      weight += p->w;
    }
    if (weight > 0)
    {
      kappa /= weight;
    }
    q.segment<3>(3 * e) = Eigen::Vector3d(twist, kappa.x(), kappa.y());
    psi += twist * l;
    lastTwist = twist;
  }
  return q;
}

/// Refines each element in turn against the points it covers (positions at their chord
/// arc length), from the start point and frame the elements before it give: errors of the
/// guess do not add up along the strand.
void refineElements(const std::vector<Eigen::Vector3d>& x, const std::vector<double>& sigma,
                    const Eigen::Matrix3d& rootFrame, Eigen::VectorXd& q)
{
  const int n = static_cast<int>(q.size() / 3);
  const double l = sigma.back() / n;
  Eigen::Matrix3d F = rootFrame;
  Eigen::Vector3d r = x[0];
  std::size_t first = 1;
  HelixPoint hp;
  HelixEnd he;
  for (int e = 0; e < n; ++e)
  {
    const double a = e * l, b = (e + 1) * l;
    std::vector<std::size_t> in;
    while (first < x.size() && sigma[first] <= a)
    {
      ++first;
    }
    for (std::size_t j = first; j < x.size() && sigma[j] <= b * (1 + 1e-12); ++j)
    {
      in.push_back(j);
    }
    Eigen::Vector3d k = q.segment<3>(3 * e);
    if (!in.empty())
    {
      auto cost = [&](const Eigen::Vector3d& kk)
      {
        double c = 0;
        for (std::size_t j : in)
        {
          helixPoint(kk, Eigen::Vector3d::Zero(), sigma[j] - a, hp);
          c += (r + F * hp.g - x[j]).squaredNorm();
        }
        return c;
      };
      double mu = 1e-3, c0 = cost(k);
      for (int it = 0; it < 30 && c0 > 0; ++it)
      {
        Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
        Eigen::Vector3d g = Eigen::Vector3d::Zero();
        for (std::size_t j : in)
        {
          helixPoint(k, Eigen::Vector3d::Zero(), sigma[j] - a, hp);
          const Eigen::Matrix3d Jj = F * hp.dg;
          H += Jj.transpose() * Jj;
          g += Jj.transpose() * (r + F * hp.g - x[j]);
        }
        bool accepted = false;
        for (int tries = 0; tries < 10 && !accepted; ++tries)
        {
          Eigen::Matrix3d D = H;
          D.diagonal() += mu * (H.diagonal().array() + 1e-12 * H.diagonal().maxCoeff()).matrix();
          const Eigen::Vector3d step = D.ldlt().solve(-g);
          const double c1 = cost(k + step);
          if (std::isfinite(c1) && c1 < c0)
          {
            k += step;
            accepted = c0 - c1 > 1e-30;
            c0 = c1;
            mu = std::max(mu / 3, 1e-9);
            if (!accepted)
            {
              tries = 10;
            }
          }
          else
          {
            mu *= 4;
          }
        }
        if (!accepted)
        {
          break;
        }
      }
    }
    q.segment<3>(3 * e) = k;
    helixEnd(k, Eigen::Vector3d::Zero(), l, he);
    r += F * he.g;
    F = F * he.E;
  }
}

/// Levenberg–Marquardt on p = (q, rotation of the root about n1 and n2, length) from a
/// first guess. Interior points are measured at their foot points (the residual projected
/// across the strand's tangent: the distance to the strand); the tip is the strand's end.
/// `footPoints` false keeps each point at its arc length σ_j L / σ_M (a smoother problem,
/// for getting near). Returns the final sum of squares.
double leastSquares(const std::vector<Eigen::Vector3d>& x, const std::vector<double>& sigma,
                    bool footPoints, Eigen::Matrix3d& F0, Eigen::VectorXd& q, double& L,
                    std::vector<double>& s, int maxIterations, double relativeDecrease,
                    int& iterations, double twistWeight, double twistPrior)
{
  const std::size_t M = x.size() - 1;
  const int n = static_cast<int>(q.size() / 3);
  const double Lp = sigma.back();
  Chain chain;
  const int np = 3 * n + 3;
  Eigen::Matrix3Xd J(3, np);
  auto project = [&](const Eigen::VectorXd& qq)
  {
    if (!footPoints)
    {
      for (std::size_t j = 1; j < M; ++j)
      {
        s[j] = sigma[j] * L / Lp;
      }
      return;
    }
    // Newton on t·(x(s) − c) = 0 per point (its derivative 1 + (ω × t)·(x − c)).
    Eigen::Vector3d p, t;
    for (std::size_t j = 1; j < M; ++j)
    {
      for (int it = 0; it < 4; ++it)
      {
        int e;
        chain.point(qq, s[j], p, t, nullptr, &e);
        const Eigen::Vector3d d = p - x[j];
        const double f = t.dot(d);
        const double df = 1 + chain.omega[e].cross(t).dot(d);
        const double ds = -f / (df > 0.1 ? df : 1.0);
        s[j] = std::clamp(s[j] + ds, 0.0, L);
        if (std::abs(ds) < 1e-15 * L)
        {
          break;
        }
      }
    }
  };
  auto cost = [&](const Eigen::VectorXd& qq)
  {
    double c = 0;
    Eigen::Vector3d p, t;
    for (std::size_t j = 1; j <= M; ++j)
    {
      chain.point(qq, j == M ? L : s[j], p, t, nullptr);
      Eigen::Vector3d d = p - x[j];
      if (j < M && footPoints)
      {
        d -= t.dot(d) * t;
      }
      c += d.squaredNorm();
    }
    for (int e = 0; e < n; ++e)
    {
      c += twistWeight * (qq(3 * e) - twistPrior) * (qq(3 * e) - twistPrior);
    }
    return c;
  };
  chain.build(q, F0, x[0], L);
  project(q);
  double c0 = cost(q);

  double mu = 1e-4;
  iterations = 0;
  int slow = 0;
  Eigen::MatrixXd H(np, np);
  Eigen::VectorXd g(np);
  const double floor = 1e-30 * Lp * Lp * double(M);
  for (; iterations < maxIterations && c0 > floor; ++iterations)
  {
    H.setZero();
    g.setZero();
    Eigen::Vector3d p, t;
    for (std::size_t j = 1; j <= M; ++j)
    {
      chain.point(q, j == M ? L : s[j], p, t, &J);
      Eigen::Vector3d d = p - x[j];
      if (j < M && footPoints)
      {
        // Across the tangent only: P = I − t tᵀ.
        d -= t.dot(d) * t;
        J -= t * (t.transpose() * J);
      }
      H.selfadjointView<Eigen::Lower>().rankUpdate(J.transpose());
      g.noalias() += J.transpose() * d;
    }
    for (int e = 0; e < n; ++e)
    {
      H(3 * e, 3 * e) += twistWeight;
      g(3 * e) += twistWeight * (q(3 * e) - twistPrior);
    }
    H.triangularView<Eigen::Upper>() = H.transpose();
    const double diagMax = H.diagonal().maxCoeff();
    bool accepted = false, converged = false;
    for (int tries = 0; tries < 12 && !accepted; ++tries)
    {
      Eigen::MatrixXd D = H;
      D.diagonal() += mu * (H.diagonal().array() + 1e-14 * diagMax).matrix();
      const Eigen::VectorXd step = D.ldlt().solve(-g);
      if (!step.allFinite())
      {
        mu *= 10;
        continue;
      }
      const double newL = L + step(np - 1);
      if (!(newL > 0.5 * L && newL < 2 * L))
      {
        mu *= 10;
        continue;
      }
      const Eigen::VectorXd qn = q + step.head(3 * n);
      const Eigen::Matrix3d Fn =
          rotation(step(3 * n) * F0.col(1) + step(3 * n + 1) * F0.col(2)) * F0;
      const std::vector<double> keep = s;
      for (double& v : s)
      {
        v *= newL / L;
      }
      const double oldL = L;
      L = newL;
      chain.build(qn, Fn, x[0], L);
      project(qn);
      const double c1 = cost(qn);
      if (std::isfinite(c1) && c1 <= c0)
      {
        converged = step.head(3 * n).norm() <= 1e-15 * (1 + q.norm()) &&
                    std::abs(step(np - 1)) <= 1e-15 * L && step.segment<2>(3 * n).norm() <= 1e-15;
        // Slow for three steps in a row: at the minimum (one slow step can be a damped step
        // in a narrow valley).
        slow = c0 - c1 <= relativeDecrease * c0 ? slow + 1 : 0;
        converged = converged || slow >= 3;
        q = qn;
        F0 = Fn;
        c0 = c1;
        accepted = true;
        mu = std::max(mu / 5, 1e-12);
      }
      else
      {
        s = keep;
        L = oldL;
        chain.build(q, F0, x[0], L);
        mu *= 8;
      }
    }
    if (!accepted || converged)
    {
      ++iterations;
      break;
    }
  }
  return c0;
}

} // namespace

void superHelixPoints(const Eigen::VectorXd& q, const Eigen::Matrix3d& rootFrame,
                      const Eigen::Vector3d& root, double length, const std::vector<double>& s,
                      std::vector<Eigen::Vector3d>& points)
{
  Chain chain;
  chain.build(q, rootFrame, root, length);
  points.resize(s.size());
  Eigen::Vector3d t;
  for (std::size_t j = 0; j < s.size(); ++j)
  {
    chain.point(q, s[j], points[j], t, nullptr);
  }
}

Status fitSuperHelix(const std::vector<Eigen::Vector3d>& curve, const Eigen::Vector3d& normal,
                     int elements, SuperHelixFit& fit, double twistWeight, double twistPrior)
{
  if (curve.size() < 2 || elements < 1)
  {
    return Status::Error("fitSuperHelix: a curve of at least two points and at least one "
                         "element are needed.");
  }
  std::vector<Eigen::Vector3d> x;
  std::vector<double> sigma;
  refine(curve, elements, 4, x, sigma);
  const double Lp = sigma.back();
  for (std::size_t j = 1; j < x.size(); ++j)
  {
    if (!(sigma[j] - sigma[j - 1] > 1e-12 * Lp) || !x[j].allFinite())
    {
      return Status::Error("fitSuperHelix: the curve has repeated or non-finite points.");
    }
  }
  const std::size_t M = x.size() - 1; // the tip's index
  const int n = elements;

  // The root tangent: the first chord turned back by half its turning to the second (the
  // tangent at the root of the circle through the first three points, for equal chords).
  const Eigen::Vector3d d0 = (x[1] - x[0]).normalized();
  Eigen::Vector3d t0 = d0;
  if (M >= 2)
  {
    const Eigen::Vector3d d1 = (x[2] - x[1]).normalized();
    t0 = rotation(-0.5 * turning(d0, d1)) * d0;
  }
  // Two first guesses, each taken near by least squares at fixed arc lengths, then to the
  // end with foot points; the better wins. The element-wise guess is the better one on most
  // curves, but on coarsely sampled tight curls its errors can add up along the strand, where
  // the plain one from the curve's frame lands in the right basin.
  const Eigen::Matrix3d Fstart = orthonormalFrame(t0, normal);
  const Eigen::VectorXd guess = bishopGuess(x, sigma, Fstart, n);
  double best = std::numeric_limits<double>::infinity();
  Eigen::Matrix3d F0 = Fstart;
  Eigen::VectorXd q = guess;
  double L = Lp;
  std::vector<double> s = sigma;
  int iterations = 0;
  for (int attempt = 0; attempt < 2; ++attempt)
  {
    Eigen::Matrix3d Fa = Fstart;
    Eigen::VectorXd qa = guess;
    if (attempt == 0)
    {
      refineElements(x, sigma, Fa, qa);
    }
    double La = Lp;
    std::vector<double> sa = sigma;
    int ia = 0, ib = 0;
    // Near at fixed arc lengths (a few digits are enough), then to the end with foot points:
    // a curve that is a Super-Helix converges quadratically to round-off; on any other the
    // fit stops when a step gains less than 1e-9 of the sum of squares (the error's
    // fourth digit).
    leastSquares(x, sigma, false, Fa, qa, La, sa, 30, 1e-4, ia, twistWeight, twistPrior);
    const double c =
        leastSquares(x, sigma, true, Fa, qa, La, sa, 200, 1e-9, ib, twistWeight, twistPrior);
    if (c < best)
    {
      best = c;
      F0 = Fa;
      q = qa;
      L = La;
      s = sa;
      iterations = ia + ib;
    }
    if (best <= 1e-24 * Lp * Lp * double(M))
    {
      break; // round-off already: no need for another start
    }
  }
  Chain chain;

  // The frame the guide will have: n1 from the normal. It differs from the fitted F0 by a
  // roll ψ about n0; turning every element's (κ1, κ2) by −ψ gives the same centreline
  // (k' = R_x(ψ)ᵀ k: the material frames all turn by the same constant roll).
  const Eigen::Matrix3d Fg = orthonormalFrame(F0.col(0), normal);
  const Eigen::Matrix3d R = F0.transpose() * Fg; // R_x(ψ)
  for (int e = 0; e < n; ++e)
  {
    q.segment<3>(3 * e) = R.transpose() * q.segment<3>(3 * e);
  }
  chain.build(q, Fg, x[0], L);
  double maxErr = 0, sum = 0;
  {
    Eigen::Vector3d p, t;
    for (std::size_t j = 1; j <= M; ++j)
    {
      chain.point(q, j == M ? L : s[j], p, t, nullptr);
      const double d = (p - x[j]).norm();
      maxErr = std::max(maxErr, d);
      sum += d * d;
    }
  }
  if (!q.allFinite() || !std::isfinite(L))
  {
    return Status::Error("fitSuperHelix: the fit did not converge (non-finite coordinates).");
  }
  fit.q = q;
  fit.rootFrame = Fg;
  fit.length = L;
  fit.maxError = maxErr;
  fit.rmsError = std::sqrt(sum / double(M + 1));
  fit.iterations = iterations;
  return Status::Ok();
}

} // namespace hair
