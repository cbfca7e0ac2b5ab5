#include "scene/BodyMotion.h"

#include <algorithm>
#include <cmath>

namespace hair
{

namespace
{
constexpr double TwoPi = 6.28318530717958647692;

double smoothstep(double x)
{
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3 - 2 * x);
}
} // namespace

BodyMotion BodyMotion::still()
{
  return BodyMotion();
}

BodyMotion BodyMotion::shake(const Eigen::Vector3d& pivot, const Eigen::Vector3d& axis,
                             double amplitude, double period, double start, double cycles)
{
  BodyMotion m;
  m.Type = Kind::Shake;
  m.Pivot = pivot;
  m.Axis = axis;
  m.Amplitude = amplitude;
  m.Period = period;
  m.Start = start;
  m.Cycles = cycles;
  return m;
}

BodyMotion BodyMotion::nod(const Eigen::Vector3d& pivot, const Eigen::Vector3d& axis,
                           double amplitude, double period, double start, double cycles)
{
  BodyMotion m = shake(pivot, axis, amplitude, period, start, cycles);
  m.Type = Kind::Nod;
  return m;
}

BodyMotion BodyMotion::verticalOscillation(const Eigen::Vector3d& axis, double amplitude,
                                           double period, double start, double cycles)
{
  BodyMotion m = shake(Eigen::Vector3d::Zero(), axis, amplitude, period, start, cycles);
  m.Type = Kind::VerticalOscillation;
  return m;
}

BodyMotion BodyMotion::samples(std::vector<double> times, std::vector<Eigen::Isometry3d> poses)
{
  BodyMotion m;
  m.Type = Kind::Samples;
  m.Times = std::move(times);
  m.Poses = std::move(poses);
  return m;
}

Status BodyMotion::validate(const std::string& what) const
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
                   " is not a rigid transform (rotation not "
                   "orthonormal, or a reflection)");
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
  if (!std::isfinite(Amplitude) || !std::isfinite(Period) || !std::isfinite(Start) ||
      !std::isfinite(Cycles))
  {
    return err("amplitude, period, start and cycles must be finite numbers");
  }
  if (!(Period > 0))
  {
    return err("the period must be > 0 s");
  }
  if (!(Cycles > 0))
  {
    return err("the number of cycles must be > 0");
  }
  return Status::Ok();
}

double BodyMotion::signal(double t) const
{
  if (Type == Kind::Still || Type == Kind::Samples)
  {
    return 0;
  }
  const double tau = t - Start, duration = Cycles * Period;
  if (!(tau > 0) || !(tau < duration))
  {
    return 0;
  }
  const double w = std::min(0.25 * Period, 0.5 * duration);
  const double envelope = smoothstep(tau / w) * smoothstep((duration - tau) / w);
  return Amplitude * std::sin(TwoPi * tau / Period) * envelope;
}

Eigen::Isometry3d BodyMotion::pose(double t) const
{
  Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
  switch (Type)
  {
  case Kind::Still:
    break;
  case Kind::Shake:
  case Kind::Nod:
  {
    const Eigen::AngleAxisd rot(signal(t), Axis.normalized());
    m.linear() = rot.toRotationMatrix();
    m.translation() = Pivot - m.linear() * Pivot;
    break;
  }
  case Kind::VerticalOscillation:
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
    const std::size_t i =
        std::upper_bound(Times.begin(), Times.end(), t) - Times.begin() - 1; // Times[i] <= t
    const double h = Times[i + 1] - Times[i], s = (t - Times[i]) / h;
    auto x = [&](std::size_t j) { return Eigen::Vector3d(Poses[j].translation()); };
    // Catmull–Rom tangents (one-sided at the ends).
    auto tangent = [&](std::size_t j) -> Eigen::Vector3d
    {
      if (j == 0)
      {
        return (x(1) - x(0)) / (Times[1] - Times[0]);
      }
      if (j == n - 1)
      {
        return (x(n - 1) - x(n - 2)) / (Times[n - 1] - Times[n - 2]);
      }
      return (x(j + 1) - x(j - 1)) / (Times[j + 1] - Times[j - 1]);
    };
    const double s2 = s * s, s3 = s2 * s;
    const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2,
                 h11 = s3 - s2;
    m.translation() = h00 * x(i) + h10 * h * tangent(i) + h01 * x(i + 1) + h11 * h * tangent(i + 1);
    const Eigen::Quaterniond q0(Poses[i].linear()), q1(Poses[i + 1].linear());
    m.linear() = q0.slerp(s, q1).toRotationMatrix();
    break;
  }
  }
  return m;
}

void motionVelocity(const BodyMotion& motion, double t, double h, Eigen::Vector3d& v0,
                    Eigen::Vector3d& omega)
{
  const Eigen::Isometry3d now = motion.pose(t);
  const Eigen::Isometry3d inv = now.inverse();
  const Eigen::Isometry3d plus = motion.pose(t + h) * inv, minus = motion.pose(t - h) * inv;
  // plus ≈ I + h [ω]× , translation ≈ h v0 (velocity of the world origin).
  const Eigen::Matrix3d w = (plus.linear() - minus.linear()) / (2 * h);
  omega = 0.5 * Eigen::Vector3d(w(2, 1) - w(1, 2), w(0, 2) - w(2, 0), w(1, 0) - w(0, 1));
  v0 = (plus.translation() - minus.translation()) / (2 * h);
}

} // namespace hair
