#include "collision/CollisionTable.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace hair
{

namespace
{
constexpr double TwoPi = 6.283185307179586476925286766559;
constexpr double Pi = 3.1415926535897932384626433832795;

/// fastAtan2's largest error [rad] (below): a bound on a table's cells widens its angles by it.
constexpr double AtanError = 1e-5;

/// atan2 in [−π, π] to within 1e-5 rad: Abramowitz and Stegun 4.4.49 (|ε| ≤ 1e-5 for
/// atan on [0, 1]), folded to the other octants. At the 0.1–0.3 m radii of body parts this
/// moves a point's table coordinates by at most 3 µm, far below the table's own error, and
/// it takes a few nanoseconds where std::atan2 takes tens: the query is the hot path.
inline double fastAtan2(double y, double x)
{
  const double ax = std::abs(x), ay = std::abs(y);
  const double hi = std::max(ax, ay);
  if (hi == 0)
  {
    return 0;
  }
  const double a = std::min(ax, ay) / hi, s = a * a;
  double r =
      a * (0.9998660 + s * (-0.3302995 + s * (0.1801410 + s * (-0.0851330 + s * 0.0208351))));
  // Folding written as selects (points come in random octants: branches would mispredict).
  r = ay > ax ? 0.5 * Pi - r : r;
  r = x < 0 ? Pi - r : r;
  return std::copysign(r, y);
}

std::string vec(const Eigen::Vector3d& v)
{
  std::ostringstream s;
  s << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return s.str();
}
} // namespace

const char* toString(Projection p)
{
  return p == Projection::Spherical ? "spherical" : "cylindrical";
}

Status TableFrame::validate() const
{
  if (!origin.allFinite())
  {
    return Status::Error("the frame origin " + vec(origin) + " is not finite: give three numbers.");
  }
  if (!axis.allFinite() || axis.norm() < 1e-12)
  {
    return Status::Error("the frame axis " + vec(axis) +
                         " is zero or not finite: give a non-zero direction.");
  }
  if (!reference.allFinite() || reference.norm() < 1e-12)
  {
    return Status::Error("the frame reference direction " + vec(reference) +
                         " is zero or not finite: give a non-zero direction for azimuth 0.");
  }
  const Eigen::Vector3d a = axis.normalized();
  const Eigen::Vector3d r = reference.normalized();
  if ((r - a * a.dot(r)).norm() < 1e-6)
  {
    return Status::Error(
        "the frame reference direction " + vec(reference) + " is parallel to the axis " +
        vec(axis) + ": azimuth 0 must point away from the axis; choose a perpendicular direction.");
  }
  return Status::Ok();
}

Eigen::Matrix3d TableFrame::basis() const
{
  const Eigen::Vector3d a = axis.normalized();
  const Eigen::Vector3d r = (reference - a * a.dot(reference)).normalized();
  Eigen::Matrix3d b;
  b.col(0) = r;
  b.col(1) = a.cross(r);
  b.col(2) = a;
  return b;
}

Status TableSpec::validate() const
{
  if (Status s = frame.validate(); !s)
  {
    return s;
  }
  auto resolution = [](int n, const char* what, int minimum) -> Status
  {
    if (n < minimum || n > MaximumSamples)
    {
      return Status::Error(std::string("the table resolution along ") + what + " is " +
                           std::to_string(n) + ": give between " + std::to_string(minimum) +
                           " and " + std::to_string(MaximumSamples) +
                           " samples (the paper used 40).");
    }
    return Status::Ok();
  };
  if (Status s = resolution(azimuthSamples, "the azimuth", 3); !s)
  {
    return s;
  }
  if (Status s =
          resolution(secondSamples,
                     projection == Projection::Cylindrical ? "the height" : "the polar angle", 2);
      !s)
  {
    return s;
  }
  if (projection == Projection::Cylindrical)
  {
    if (!std::isfinite(heightMin) || !std::isfinite(heightMax) || !(heightMax > heightMin))
    {
      std::ostringstream m;
      m << "the height range [" << heightMin << ", " << heightMax
        << "] is empty or not finite: give a minimum below the maximum, in the mesh's units "
           "along the axis measured from the origin.";
      return Status::Error(m.str());
    }
  }
  if (!(maxRadius > 0)) // also refuses NaN
  {
    std::ostringstream m;
    m << "the maximum radius " << maxRadius
      << " is not positive: give a positive distance, or infinity for no limit.";
    return Status::Error(m.str());
  }
  return Status::Ok();
}

Status TableSpec::fitsBody(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const
{
  const Eigen::Vector3d centre = 0.5 * (lo + hi);
  const double size = std::max((hi - lo).norm(), 1e-300);
  const double reach = 10 * size;
  auto describe = [&]()
  {
    std::ostringstream m;
    m << "the body's box spans " << vec(lo) << " to " << vec(hi) << " (size " << size << ")";
    return m.str();
  };
  if ((frame.origin - centre).norm() > reach)
  {
    return Status::Error("the frame origin " + vec(frame.origin) +
                         " lies more than ten times the "
                         "body's size from it (" +
                         describe() + "): place it inside the body.");
  }
  if (projection == Projection::Cylindrical)
  {
    const double h0 = frame.axis.normalized().dot(centre - frame.origin);
    if (heightMin < h0 - reach || heightMax > h0 + reach)
    {
      std::ostringstream m;
      m << "the height range [" << heightMin << ", " << heightMax
        << "] reaches more than ten times the body's size beyond it (" << describe()
        << "): give heights within the body's extent along the axis.";
      return Status::Error(m.str());
    }
  }
  return Status::Ok();
}

void CollisionTable::updateDerived()
{
  Basis = Spec.frame.basis();
  AzimuthScale = Spec.azimuthSamples / TwoPi;
  SecondScale = Spec.projection == Projection::Cylindrical
                    ? (Spec.secondSamples - 1) / (Spec.heightMax - Spec.heightMin)
                    : (Spec.secondSamples - 1) / Pi;
}

void CollisionTable::updateReach()
{
  Reach = 0;
  for (std::size_t i = 0; i < Hit.size(); ++i)
  {
    if (Hit[i])
    {
      Reach = std::max(Reach, Outer[i]);
    }
  }
}

double CollisionTable::windowReach(const Eigen::Vector3d& p, double delta) const
{
  constexpr double Unbounded = std::numeric_limits<double>::infinity();
  if (Hit.empty() || !p.allFinite() || !(delta >= 0))
  {
    return Unbounded;
  }
  const Eigen::Vector3d local = Basis.transpose() * (p - Spec.frame.origin);
  const double rxy = std::sqrt(local.x() * local.x() + local.y() * local.y());
  const int na = Spec.azimuthSamples, ns = Spec.secondSamples;
  // Rows: the heights h ± δ, or the polar angles φ ± asin(δ / ρ) (the ball seen from the
  // centre); the last row a point can use is the one after the cell it falls in.
  int j0, j1;
  if (Spec.projection == Projection::Cylindrical)
  {
    const double cell = (Spec.heightMax - Spec.heightMin) / (ns - 1);
    j0 = int(std::floor((local.z() - delta - Spec.heightMin) / cell));
    j1 = int(std::floor((local.z() + delta - Spec.heightMin) / cell)) + 1;
  }
  else
  {
    const double rho = local.norm();
    if (delta >= rho)
    {
      return Unbounded;
    }
    // The look-up finds a point's cells by fastAtan2: the window is widened by its error.
    const double cone = std::asin(delta / rho) + AtanError, phi = std::atan2(rxy, local.z());
    const double cell = Pi / (ns - 1);
    j0 = int(std::floor((phi - cone) / cell));
    j1 = int(std::floor((phi + cone) / cell)) + 1;
  }
  j0 = std::max(j0, 0);
  j1 = std::min(j1, ns - 1);
  // Azimuths: θ ± asin(δ / r_xy), the ball's shadow on the plane across the axis; all of
  // them when the ball holds the axis.
  int i0 = 0, i1 = na - 1;
  if (delta < rxy)
  {
    const double turn = std::asin(delta / rxy) + AtanError, cell = TwoPi / na;
    double th = std::atan2(local.y(), local.x());
    th = th < 0 ? th + TwoPi : th;
    i0 = int(std::floor((th - turn) / cell));
    i1 = int(std::floor((th + turn) / cell)) + 1;
    if (i1 - i0 >= na)
    {
      i0 = 0;
      i1 = na - 1;
    }
  }
  double r = 0;
  for (int j = j0; j <= j1; ++j)
  {
    for (int i = i0; i <= i1; ++i)
    {
      const int k = index(((i % na) + na) % na, j);
      if (Hit[k])
      {
        r = std::max(r, Outer[k]);
      }
    }
  }
  return r;
}

double CollisionTable::azimuth(int i) const
{
  return TwoPi * i / Spec.azimuthSamples;
}

double CollisionTable::second(int j) const
{
  const double f = double(j) / (Spec.secondSamples - 1);
  return Spec.projection == Projection::Cylindrical
             ? Spec.heightMin + f * (Spec.heightMax - Spec.heightMin)
             : Pi * f;
}

Eigen::Vector3d CollisionTable::rayDirection(int i, int j) const
{
  const double th = azimuth(i);
  if (Spec.projection == Projection::Cylindrical)
  {
    return Basis * Eigen::Vector3d(std::cos(th), std::sin(th), 0);
  }
  const double ph = second(j);
  return Basis *
         Eigen::Vector3d(std::sin(ph) * std::cos(th), std::sin(ph) * std::sin(th), std::cos(ph));
}

Eigen::Vector3d CollisionTable::rayOrigin(int /*i*/, int j) const
{
  if (Spec.projection == Projection::Cylindrical)
  {
    return Spec.frame.origin + second(j) * Basis.col(2);
  }
  return Spec.frame.origin;
}

int CollisionTable::numberOfHits() const
{
  return static_cast<int>(std::count(Hit.begin(), Hit.end(), std::uint8_t(1)));
}

Status CollisionTable::build(const TableSpec& spec, const RayCaster& body, const Progress& progress)
{
  if (Status s = spec.validate(); !s)
  {
    return s;
  }
  CollisionTable t;
  t.Spec = spec;
  t.updateDerived();
  const std::size_t n = std::size_t(spec.azimuthSamples) * spec.secondSamples;
  t.Hit.assign(n, 0);
  t.Outer.assign(n, 0);
  t.Inner.assign(n, 0);
  t.OuterNormal.assign(n, Eigen::Vector3d::Zero());
  t.InnerNormal.assign(n, Eigen::Vector3d::Zero());

  std::vector<RayHit> hits;
  for (int j = 0; j < spec.secondSamples; ++j)
  {
    for (int i = 0; i < spec.azimuthSamples; ++i)
    {
      const Eigen::Vector3d o = t.rayOrigin(i, j), d = t.rayDirection(i, j);
      body.castAll(o, d, hits);
      // Crossings within reach, and whether the solid continues past the reach (an odd
      // number of crossings beyond it).
      std::size_t k = 0;
      while (k < hits.size() && hits[k].t <= spec.maxRadius)
      {
        ++k;
      }
      const bool capped = ((hits.size() - k) % 2) == 1;
      const int s = t.index(i, j);
      if (capped)
      {
        // The solid runs through the end of the ray: cut it there with a cap facing out.
        t.Hit[s] = 1;
        t.Outer[s] = spec.maxRadius;
        t.OuterNormal[s] = d;
        if (k >= 1)
        {
          t.Inner[s] = hits[k - 1].t;
          t.InnerNormal[s] = hits[k - 1].normal;
        }
      }
      else if (k >= 1)
      {
        // The outermost solid interval [h(k-2), h(k-1)]: with an even number of crossings
        // the axis lies outside the solid, with an odd one inside, and either way the
        // interval's inner end is the crossing before the last (or the axis itself).
        t.Hit[s] = 1;
        t.Outer[s] = hits[k - 1].t;
        t.OuterNormal[s] = hits[k - 1].normal;
        if (k >= 2)
        {
          t.Inner[s] = hits[k - 2].t;
          t.InnerNormal[s] = hits[k - 2].normal;
        }
      }
    }
    if (progress && !progress(double(j + 1) / spec.secondSamples))
    {
      return Status::Error("building the collision table was aborted; nothing was changed.");
    }
  }
  if (t.numberOfHits() == 0)
  {
    return Status::Error(
        std::string("no ray of the ") + toString(spec.projection) +
        " table met the mesh: the frame (origin " + vec(spec.frame.origin) + ", axis " +
        vec(spec.frame.axis) +
        ") misses it. Put the origin inside the body part, or use the automatic frame.");
  }
  t.updateReach();
  *this = std::move(t);
  return Status::Ok();
}

Status CollisionTable::assign(const TableSpec& spec, std::vector<std::uint8_t> hit,
                              std::vector<double> outer, std::vector<double> inner,
                              std::vector<Eigen::Vector3d> outerNormal,
                              std::vector<Eigen::Vector3d> innerNormal)
{
  if (Status s = spec.validate(); !s)
  {
    return s;
  }
  const std::size_t n = std::size_t(spec.azimuthSamples) * spec.secondSamples;
  if (hit.size() != n || outer.size() != n || inner.size() != n || outerNormal.size() != n ||
      innerNormal.size() != n)
  {
    return Status::Error("the collision table's arrays do not have " + std::to_string(n) +
                         " samples (" + std::to_string(spec.azimuthSamples) + " x " +
                         std::to_string(spec.secondSamples) +
                         "): the table is incomplete; rebuild it.");
  }
  for (std::size_t s = 0; s < n; ++s)
  {
    if (hit[s] &&
        (!std::isfinite(outer[s]) || !std::isfinite(inner[s]) || !outerNormal[s].allFinite() ||
         !innerNormal[s].allFinite() || inner[s] < 0 || outer[s] < inner[s]))
    {
      return Status::Error(
          "the collision table's sample " + std::to_string(s) +
          " has a radius or normal that is not finite or an inner radius past the outer one: "
          "the table is corrupt; rebuild it.");
    }
  }
  Spec = spec;
  updateDerived();
  Hit = std::move(hit);
  Outer = std::move(outer);
  Inner = std::move(inner);
  OuterNormal = std::move(outerNormal);
  InnerNormal = std::move(innerNormal);
  updateReach();
  return Status::Ok();
}

TableQuery CollisionTable::query(const Eigen::Vector3d& p) const
{
  return lookUp(p, false);
}

bool CollisionTable::inside(const Eigen::Vector3d& p) const
{
  return lookUp(p, true).inside;
}

TableQuery CollisionTable::lookUp(const Eigen::Vector3d& p, bool insideOnly) const
{
  TableQuery q;
  if (Hit.empty() || !p.allFinite())
  {
    return q;
  }
  const Eigen::Vector3d local = Basis.transpose() * (p - Spec.frame.origin);
  const int na = Spec.azimuthSamples, ns = Spec.secondSamples;
  // Outside a cylindrical table's heights nothing is covered: answer before the azimuth's
  // arctangent (most of a trunk table's queries from hair on the head end here).
  if (Spec.projection == Projection::Cylindrical &&
      (local.z() < Spec.heightMin || local.z() > Spec.heightMax))
  {
    return q;
  }

  // Azimuth: periodic. (Wrapped by comparisons, not %, and radii by sqrt, not hypot: this is
  // the hot path of every collision test.)
  double th = fastAtan2(local.y(), local.x());
  if (th < 0)
  {
    th += TwoPi;
  }
  const double u = th * AzimuthScale;
  int i0 = static_cast<int>(u);
  const double fs = u - i0;
  if (i0 >= na)
  {
    i0 -= na;
  }
  const int i1 = i0 + 1 == na ? 0 : i0 + 1;

  // Second coordinate: height (only inside the table's range) or polar angle (poles clamp).
  double v, radius;
  Eigen::Vector3d radial;
  const double rxy = std::sqrt(local.x() * local.x() + local.y() * local.y());
  if (Spec.projection == Projection::Cylindrical)
  {
    v = (local.z() - Spec.heightMin) * SecondScale;
    radius = rxy;
    const double inv = 1 / radius;
    radial = radius > 0 ? Eigen::Vector3d(local.x() * inv, local.y() * inv, 0)
                        : Eigen::Vector3d::UnitX();
  }
  else
  {
    radius = std::sqrt(rxy * rxy + local.z() * local.z());
    v = fastAtan2(rxy, local.z()) * SecondScale;
    radial = radius > 0 ? Eigen::Vector3d(local * (1 / radius)) : Eigen::Vector3d::UnitZ();
  }
  int j0 = std::clamp(static_cast<int>(v), 0, ns - 2);
  const double ft = std::clamp(v - j0, 0.0, 1.0);
  const int j1 = j0 + 1;

  // Bilinear weights over the corners that met the body. A point is covered when those
  // corners carry at least half of the weight: the table's edge lies half-way between a
  // sample that met the body and one that did not.
  const int corner[4] = {index(i0, j0), index(i1, j0), index(i0, j1), index(i1, j1)};
  const double weight[4] = {(1 - fs) * (1 - ft), fs * (1 - ft), (1 - fs) * ft, fs * ft};
  // The inner surface is treated like the edge of the table: it exists at P when the
  // corners that have one (inner > 0) carry at least half of the hit corners' weight, and
  // its radius is their weighted mean. Interpolating 0 with an inner radius across such a
  // corner (a ray that re-enters a lid or a lip) would invent a surface between them.
  double w = 0, outer = 0, wIn = 0, inner = 0;
  for (int c = 0; c < 4; ++c)
  {
    if (Hit[corner[c]])
    {
      w += weight[c];
      outer += weight[c] * Outer[corner[c]];
      if (Inner[corner[c]] > 0)
      {
        wIn += weight[c];
        inner += weight[c] * Inner[corner[c]];
      }
    }
  }
  if (w < 0.5)
  {
    return q;
  }
  outer = w < 1 ? outer / w : outer;
  inner = wIn >= 0.5 * w ? inner / wIn : 0.0;

  q.covered = true;
  q.pointRadius = radius;
  q.surfaceRadius = outer;
  q.innerRadius = inner;
  q.inside = radius < outer && (inner <= 0 || radius > inner);
  if (insideOnly)
  {
    return q;
  }
  // The nearer of the two surfaces along the ray; the inner one exists only where the solid
  // does not hold the axis (inner > 0). Only that surface's normal is interpolated.
  const bool useInner = inner > 0 && (radius - inner) < (outer - radius);
  const std::vector<Eigen::Vector3d>& normals = useInner ? InnerNormal : OuterNormal;
  const double rq = useInner ? inner : outer;
  Eigen::Vector3d nLocalWorld = Eigen::Vector3d::Zero();
  for (int c = 0; c < 4; ++c)
  {
    if (Hit[corner[c]] && (!useInner || Inner[corner[c]] > 0))
    {
      nLocalWorld += weight[c] * normals[corner[c]];
    }
  }
  if (nLocalWorld.squaredNorm() < 1e-24)
  {
    nLocalWorld = Basis * radial * (useInner ? -1.0 : 1.0);
  }
  const Eigen::Vector3d normal = nLocalWorld.normalized();
  Eigen::Vector3d qLocal = rq * radial;
  if (Spec.projection == Projection::Cylindrical)
  {
    qLocal.z() = local.z();
  }
  q.surfacePoint = Spec.frame.origin + Basis * qLocal;
  q.normal = normal;
  q.depth = (q.surfacePoint - p).dot(normal);
  q.nearest = p + q.depth * normal;
  return q;
}

} // namespace hair
