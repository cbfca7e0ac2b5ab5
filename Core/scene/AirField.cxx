#include "scene/AirField.h"

#include <algorithm>
#include <cmath>

namespace hair
{

AirField AirField::uniform(const Eigen::Vector3d& velocity)
{
  AirField a;
  a.speed = velocity.norm();
  if (a.speed > 0)
  {
    a.direction = velocity / a.speed;
  }
  return a;
}

Status AirField::validate(const std::string& what) const
{
  auto err = [&](const std::string& s) { return Status::Error(what + ": " + s); };
  if (!direction.allFinite() || !std::isfinite(speed) || !std::isfinite(gustAmplitude) ||
      !std::isfinite(gustPeriod) || !std::isfinite(start) || !std::isfinite(rampTime))
  {
    return err("holds NaN or infinite values");
  }
  if (speed < 0)
  {
    return err("the speed must be ≥ 0 m/s (turn the direction round instead)");
  }
  if (speed > 0 && !(direction.norm() > 1e-12))
  {
    return err("the direction is zero; give where the air goes");
  }
  if (gustAmplitude < 0 || gustAmplitude > 1)
  {
    return err("the gust amplitude must lie in [0, 1]");
  }
  if (!(gustPeriod > 0))
  {
    return err("the gust period must be > 0 s");
  }
  if (rampTime < 0)
  {
    return err("the ramp time must be ≥ 0 s");
  }
  return Status::Ok();
}

Eigen::Vector3d AirField::velocity(const Eigen::Vector3d& x, double t) const
{
  if (speed <= 0 || t < start)
  {
    return Eigen::Vector3d::Zero();
  }
  const Eigen::Vector3d e = direction.normalized();
  double ramp = 1;
  if (rampTime > 0 && t - start < rampTime)
  {
    const double s = (t - start) / rampTime;
    ramp = s * s * (3 - 2 * s);
  }
  if (gustAmplitude == 0)
  {
    return speed * ramp * e;
  }
  const double phase = 6.28318530717958647692 * (t - x.dot(e) / speed) / gustPeriod;
  return speed * ramp * (1 + gustAmplitude * std::sin(phase)) * e;
}

bool AirField::isSteadyAndUniform() const
{
  return speed <= 0 || (gustAmplitude == 0 && rampTime == 0 && start <= 0);
}

AirVelocityField AirField::field() const
{
  const AirField air = *this;
  return [air](const Eigen::Vector3d& x, double t) { return air.velocity(x, t); };
}

} // namespace hair
