#pragma once
// The Super-Helix tests' and benchmarks' shaken root: a root attached at `attachment` (with
// frame `attachmentFrame` at rest) on a head turning θ(t) = amplitude · sin(2π f t) about
// `axis` through `center`; by default the stability case of Bertails et al. (2006), ±30° at
// 3 Hz. Only parameters: the motion is Core's RigidMotion.
#include "scene/RigidMotion.h"

#include <cmath>

namespace hair
{

struct HeadShake
{
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitY();
  double amplitude = M_PI / 6; ///< [rad]
  double frequency = 3.0;      ///< [Hz]
  Eigen::Vector3d attachment = Eigen::Vector3d(0.1, 0, 0);
  Eigen::Matrix3d attachmentFrame = Eigen::Matrix3d::Identity();

  RigidMotion motion() const { return RigidMotion::shake(center, axis, amplitude, frequency); }
  operator RootMotion() const { return motion().carriedRoot(attachment, attachmentFrame); }
};

} // namespace hair
