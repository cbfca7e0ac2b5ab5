#include "scene/RigidMotion.h"

#include <algorithm>
#include <cmath>

namespace hair
{

namespace
{
constexpr double TwoPi = 6.283185307179586476925286766559;

/// The smoothstep E(x) = 3x² − 2x³ on [0, 1] (0 before, 1 after) and its derivatives.
void smoothstep(double x, double& e, double& de, double& dde)
{
  if (!(x > 0))
  {
    e = de = dde = 0;
  }
  else if (!(x < 1))
  {
    e = 1;
    de = dde = 0;
  }
  else
  {
    e = x * x * (3 - 2 * x);
    de = 6 * x * (1 - x);
    dde = 6 - 12 * x;
  }
}

/// The Catmull–Rom curve through the sample translations, on interval i at s ∈ [0, 1] of
/// it (tangents one-sided at the ends): its point and its first two time derivatives.
void hermite(const std::vector<double>& times, const std::vector<Eigen::Isometry3d>& poses,
             std::size_t i, double s, Eigen::Vector3d& x, Eigen::Vector3d& xd, Eigen::Vector3d& xdd)
{
  const std::size_t n = times.size();
  auto point = [&](std::size_t j) { return Eigen::Vector3d(poses[j].translation()); };
  auto tangent = [&](std::size_t j) -> Eigen::Vector3d
  {
    if (j == 0)
    {
      return (point(1) - point(0)) / (times[1] - times[0]);
    }
    if (j == n - 1)
    {
      return (point(n - 1) - point(n - 2)) / (times[n - 1] - times[n - 2]);
    }
    return (point(j + 1) - point(j - 1)) / (times[j + 1] - times[j - 1]);
  };
  const double h = times[i + 1] - times[i];
  const double s2 = s * s, s3 = s2 * s;
  const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2,
               h11 = s3 - s2;
  x = h00 * point(i) + h10 * h * tangent(i) + h01 * point(i + 1) + h11 * h * tangent(i + 1);
  // The basis differentiated in s (ds/dt = 1/h), once and twice.
  const double d00 = 6 * s2 - 6 * s, d10 = 3 * s2 - 4 * s + 1, d01 = -6 * s2 + 6 * s,
               d11 = 3 * s2 - 2 * s;
  const double dd00 = 12 * s - 6, dd10 = 6 * s - 4, dd01 = -12 * s + 6, dd11 = 6 * s - 2;
  xd = (d00 * point(i) + d01 * point(i + 1)) / h + d10 * tangent(i) + d11 * tangent(i + 1);
  xdd = (dd00 * point(i) + dd01 * point(i + 1)) / (h * h) +
        (dd10 * tangent(i) + dd11 * tangent(i + 1)) / h;
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

RigidMotion RigidMotion::still()
{
  return RigidMotion();
}

RigidMotion RigidMotion::oscillation(Kind kind, const Eigen::Vector3d& pivot,
                                     const Eigen::Vector3d& axis, double amplitude,
                                     double frequency)
{
  RigidMotion m;
  m.Type = kind;
  m.Pivot = kind == Kind::Vertical ? Eigen::Vector3d::Zero() : pivot;
  m.Axis = axis;
  m.Amplitude = amplitude;
  m.Frequency = frequency;
  return m;
}

RigidMotion RigidMotion::shake(const Eigen::Vector3d& pivot, const Eigen::Vector3d& axis,
                               double amplitude, double frequency)
{
  return oscillation(Kind::Shake, pivot, axis, amplitude, frequency);
}

RigidMotion RigidMotion::nod(const Eigen::Vector3d& pivot, const Eigen::Vector3d& axis,
                             double amplitude, double frequency)
{
  return oscillation(Kind::Nod, pivot, axis, amplitude, frequency);
}

RigidMotion RigidMotion::vertical(const Eigen::Vector3d& axis, double amplitude, double frequency)
{
  return oscillation(Kind::Vertical, Eigen::Vector3d::Zero(), axis, amplitude, frequency);
}

RigidMotion RigidMotion::samples(std::vector<double> times, std::vector<Eigen::Isometry3d> poses)
{
  RigidMotion m;
  m.Type = Kind::Samples;
  m.Times = std::move(times);
  m.Poses = std::move(poses);
  return m;
}

RigidMotion& RigidMotion::during(double start, double cycles)
{
  Start = start;
  Cycles = cycles;
  return *this;
}

RigidMotion& RigidMotion::fading(double seconds)
{
  Fade = seconds;
  return *this;
}

Status RigidMotion::validate(const std::string& what) const
{
  auto err = [&](const std::string& s) { return Status::Error(what + ": " + s); };
  if (Type == Kind::Still)
  {
    return Status::Ok();
  }
  if (Type == Kind::Samples)
  {
    if (Times.empty())
    {
      return err("no samples; give at least one time and pose");
    }
    if (Times.size() != Poses.size())
    {
      return err("there are " + std::to_string(Times.size()) + " times but " +
                 std::to_string(Poses.size()) + " poses; give one pose per time");
    }
    for (std::size_t i = 0; i < Times.size(); ++i)
    {
      if (!std::isfinite(Times[i]))
      {
        return err("sample time " + std::to_string(i) + " is not a finite number");
      }
      if (i > 0 && !(Times[i] > Times[i - 1]))
      {
        return err("sample times must increase strictly (sample " + std::to_string(i) + ")");
      }
      if (!Poses[i].matrix().allFinite())
      {
        return err("pose " + std::to_string(i) + " holds NaN or infinite entries");
      }
      const Eigen::Matrix3d r = Poses[i].linear();
      if (!(r.transpose() * r).isIdentity(1e-6) || r.determinant() < 0)
      {
        return err("pose " + std::to_string(i) +
                   " is not a rigid transform (rotation not orthonormal, or a reflection)");
      }
    }
    return Status::Ok();
  }
  if (!Pivot.allFinite() || !Axis.allFinite())
  {
    return err("the pivot or axis holds NaN or infinite entries");
  }
  if (!(Axis.norm() > 1e-12))
  {
    return err("the axis is zero; give a direction");
  }
  if (!std::isfinite(Amplitude) || !std::isfinite(Frequency))
  {
    return err("the amplitude and the frequency must be finite numbers");
  }
  if (!(Frequency > 0))
  {
    return err("the frequency must be > 0 Hz");
  }
  if (std::isnan(Start) || Start == std::numeric_limits<double>::infinity())
  {
    return err("the start must be a finite time (or none)");
  }
  if (std::isnan(Cycles) || !(Cycles > 0))
  {
    return err("the number of cycles must be > 0");
  }
  if (!std::isfinite(Fade) || Fade < 0)
  {
    return err("the fade time must be a number of seconds >= 0");
  }
  if (Fade > 0 && !std::isfinite(Start))
  {
    return err("a fade needs a start: the motion fades in from rest after it");
  }
  return Status::Ok();
}

void RigidMotion::signal(double t, double& s, double& sDot, double& sDdot) const
{
  s = sDot = sDdot = 0;
  if (Type == Kind::Still || Type == Kind::Samples)
  {
    return;
  }
  const double w = TwoPi * Frequency;
  const bool windowed = std::isfinite(Start);
  const double tau = windowed ? t - Start : t;
  const double duration = Cycles / Frequency;
  if (windowed && (!(tau > 0) || !(tau < duration)))
  {
    return;
  }
  const double b = Amplitude * std::sin(w * tau);
  const double bd = Amplitude * w * std::cos(w * tau);
  const double bdd = -Amplitude * w * w * std::sin(w * tau);
  if (!(Fade > 0))
  {
    s = b;
    sDot = bd;
    sDdot = bdd;
    return;
  }
  // Envelope e = E(τ/f) E((D − τ)/f), f the fade (at most half the window).
  const double f = std::min(Fade, 0.5 * duration);
  double e1, d1, dd1, e2, d2, dd2;
  smoothstep(tau / f, e1, d1, dd1);
  smoothstep((duration - tau) / f, e2, d2, dd2);
  d1 /= f;
  dd1 /= f * f;
  d2 = -d2 / f;
  dd2 /= f * f;
  const double e = e1 * e2, ed = d1 * e2 + e1 * d2, edd = dd1 * e2 + 2 * d1 * d2 + e1 * dd2;
  s = b * e;
  sDot = bd * e + b * ed;
  sDdot = bdd * e + 2 * bd * ed + b * edd;
}

double RigidMotion::signal(double t) const
{
  double s, sd, sdd;
  signal(t, s, sd, sdd);
  return s;
}

std::size_t RigidMotion::interval(double t) const
{
  return std::upper_bound(Times.begin(), Times.end(), t) - Times.begin() - 1;
}

Eigen::Isometry3d RigidMotion::pose(double t) const
{
  Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
  switch (Type)
  {
  case Kind::Still:
    break;
  case Kind::Shake:
  case Kind::Nod:
  {
    m.linear() = Eigen::AngleAxisd(signal(t), Axis.normalized()).toRotationMatrix();
    m.translation() = Pivot - m.linear() * Pivot;
    break;
  }
  case Kind::Vertical:
    m.translation() = signal(t) * Axis.normalized();
    break;
  case Kind::Samples:
  {
    const std::size_t n = Times.size();
    if (n == 0)
    {
      break;
    }
    if (n == 1 || t <= Times.front())
    {
      return Poses.front();
    }
    if (t >= Times.back())
    {
      return Poses.back();
    }
    const std::size_t i = interval(t);
    const double s = (t - Times[i]) / (Times[i + 1] - Times[i]);
    Eigen::Vector3d x, xd, xdd;
    hermite(Times, Poses, i, s, x, xd, xdd);
    m.translation() = x;
    const Eigen::Quaterniond q0(Poses[i].linear()), q1(Poses[i + 1].linear());
    m.linear() = q0.slerp(s, q1).toRotationMatrix();
    break;
  }
  }
  return m;
}

RigidRates RigidMotion::rates(double t) const
{
  RigidRates r;
  switch (Type)
  {
  case Kind::Still:
    break;
  case Kind::Shake:
  case Kind::Nod:
  {
    double s, sd, sdd;
    signal(t, s, sd, sdd);
    const Eigen::Vector3d a = Axis.normalized();
    r.reference = Pivot;
    r.angularVelocity = sd * a;
    r.angularAcceleration = sdd * a;
    break;
  }
  case Kind::Vertical:
  {
    double s, sd, sdd;
    signal(t, s, sd, sdd);
    const Eigen::Vector3d a = Axis.normalized();
    r.reference = s * a;
    r.velocity = sd * a;
    r.acceleration = sdd * a;
    break;
  }
  case Kind::Samples:
  {
    const std::size_t n = Times.size();
    const Eigen::Isometry3d p = pose(t);
    r.reference = p.translation();
    if (n < 2 || t <= Times.front() || t >= Times.back())
    {
      break; // at rest before the first sample and after the last
    }
    const std::size_t i = interval(t);
    const double h = Times[i + 1] - Times[i];
    Eigen::Vector3d x;
    hermite(Times, Poses, i, (t - Times[i]) / h, x, r.velocity, r.acceleration);
    // Slerp turns at a constant rate about a fixed axis: R(s) = R0 exp(s φ [u]×), so the
    // world angular velocity is R0 u φ / h (the shorter way round, as slerp takes it).
    const Eigen::Quaterniond q0(Poses[i].linear());
    Eigen::Quaterniond q1(Poses[i + 1].linear());
    if (q0.dot(q1) < 0)
    {
      q1.coeffs() = -q1.coeffs();
    }
    const Eigen::AngleAxisd relative(q0.conjugate() * q1);
    r.angularVelocity = q0 * (relative.axis() * (relative.angle() / h));
    break;
  }
  }
  return r;
}

RootState RigidMotion::carried(const Eigen::Vector3d& point, const Eigen::Matrix3d& frame,
                               double t) const
{
  RootState s;
  switch (Type)
  {
  case Kind::Still:
    s.position = point;
    s.orientation = frame;
    break;
  case Kind::Shake:
  case Kind::Nod:
  {
    double theta, thetaDot, thetaDdot;
    signal(t, theta, thetaDot, thetaDdot);
    const Eigen::Vector3d a = Axis.normalized();
    const Eigen::Matrix3d R = Eigen::AngleAxisd(theta, a).toRotationMatrix();
    const Eigen::Vector3d arm = R * (point - Pivot);
    s.angularVelocity = thetaDot * a;
    s.angularAcceleration = thetaDdot * a;
    s.position = Pivot + arm;
    s.velocity = s.angularVelocity.cross(arm);
    s.acceleration =
        s.angularAcceleration.cross(arm) + s.angularVelocity.cross(s.angularVelocity.cross(arm));
    s.orientation = R * frame;
    break;
  }
  case Kind::Vertical:
  {
    double d, dDot, dDdot;
    signal(t, d, dDot, dDdot);
    const Eigen::Vector3d a = Axis.normalized();
    s.position = point + d * a;
    s.velocity = dDot * a;
    s.acceleration = dDdot * a;
    s.orientation = frame;
    break;
  }
  case Kind::Samples:
  {
    const Eigen::Isometry3d p = pose(t);
    const RigidRates r = rates(t);
    s.position = p * point;
    s.orientation = p.linear() * frame;
    s.velocity = r.velocityAt(s.position);
    s.acceleration = r.accelerationAt(s.position);
    s.angularVelocity = r.angularVelocity;
    s.angularAcceleration = r.angularAcceleration;
    break;
  }
  }
  return s;
}

RootMotion RigidMotion::carriedRoot(const Eigen::Vector3d& point,
                                    const Eigen::Matrix3d& frame) const
{
  const RigidMotion motion = *this;
  return [motion, point, frame](double t) { return motion.carried(point, frame, t); };
}

} // namespace hair
