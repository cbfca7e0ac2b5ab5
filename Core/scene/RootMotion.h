#pragma once
// The clamped root of a strand moves with the head: position, velocity, acceleration,
// orientation (columns: tangent n0, n1, n2 in world coordinates), angular velocity and
// angular acceleration (world), all given at a time.
#include "common/Status.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <functional>

namespace hair
{

struct RootState
{
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d acceleration = Eigen::Vector3d::Zero();
  Eigen::Matrix3d orientation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d angularVelocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d angularAcceleration = Eigen::Vector3d::Zero();

  /// Refuses non-finite values and an orientation that is not a rotation (to 1e-9).
  Status validate() const;
};

/// Root state as a function of time. An empty function means a root fixed at RootState{}.
using RootMotion = std::function<RootState(double time)>;

/// A head turning about `axis` through `center` by θ(t) = amplitude · sin(2π frequency t),
/// carrying a root attached at `attachment` (world position at θ = 0) with orientation
/// `attachmentFrame` at θ = 0. The stability case: 3 Hz, ±30°.
struct HeadShake
{
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitY();
  double amplitude = M_PI / 6; ///< [rad]
  double frequency = 3.0;      ///< [Hz]
  Eigen::Vector3d attachment = Eigen::Vector3d(0.1, 0, 0);
  Eigen::Matrix3d attachmentFrame = Eigen::Matrix3d::Identity();

  RootState operator()(double t) const
  {
    const double w = 2 * M_PI * frequency;
    const double theta = amplitude * std::sin(w * t);
    const double thetaDot = amplitude * w * std::cos(w * t);
    const double thetaDdot = -amplitude * w * w * std::sin(w * t);
    const Eigen::Vector3d a = axis.normalized();
    const Eigen::Matrix3d R = Eigen::AngleAxisd(theta, a).toRotationMatrix();
    const Eigen::Vector3d arm = R * (attachment - center);
    RootState s;
    s.angularVelocity = thetaDot * a;
    s.angularAcceleration = thetaDdot * a;
    s.position = center + arm;
    s.velocity = s.angularVelocity.cross(arm);
    s.acceleration =
        s.angularAcceleration.cross(arm) + s.angularVelocity.cross(s.angularVelocity.cross(arm));
    s.orientation = R * attachmentFrame;
    return s;
  }
};

} // namespace hair
