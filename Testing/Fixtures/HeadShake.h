#pragma once
// The Super-Helix tests' and benchmarks' shaken root: a root attached at `attachment` (with
// frame `attachmentFrame` at rest) on a head turning θ(t) = amplitude · sin(2π f t) about
// `axis` through `center`; by default the stability case of Bertails et al. (2006), ±30° at
// 3 Hz. Only parameters: the motion is Core's RigidMotion.
#include "scene/RigidMotion.h"
#include "superhelix/SuperHelix.h"

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

/// The stability case's strand: 30 cm of `n` elements of the preset, hanging (tangent −y)
/// from a root 10 cm from the axis of the default shake, the id-th of a row of roots 2 mm
/// apart, seed 1 + id (the Super-Helix benchmarks and the golden values).
inline StrandSpec shakenStrand(HairType type, int n, int id = 0)
{
  StrandSpec s = StrandSpec::uniform(0.3, n, HairParameters::preset(type));
  s.id = id;
  s.seed = 1 + id;
  HeadShake shake;
  shake.attachment = Eigen::Vector3d(0.1, 0.002 * (id % 50), 0);
  shake.attachmentFrame.col(0) = Eigen::Vector3d(0, -1, 0);
  shake.attachmentFrame.col(1) = Eigen::Vector3d(1, 0, 0);
  shake.attachmentFrame.col(2) = Eigen::Vector3d(0, 0, 1);
  s.root = shake;
  return s;
}

} // namespace hair
