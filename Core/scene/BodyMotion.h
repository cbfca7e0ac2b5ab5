#pragma once
// Rigid motion of a body part (or of the strand roots attached to it) as a function of
// time: the pose that maps the part at rest to where it is at time t. Kurihara, Anjyo and
// Thalmann (1993) shake the head left, right and left; a nod, a vertical oscillation and a
// motion given by rigid transforms at sample times are the other kinds.
//
// (The Super-Helix model in Core/superhelix/ has its own root motion; the two are to be
// unified later.)
#include "common/Status.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace hair
{

class BodyMotion
{
public:
  enum class Kind
  {
    Still,
    Shake,               ///< rotation about `axis` (up) through `pivot` (the neck)
    Nod,                 ///< rotation about `axis` (lateral) through `pivot`
    VerticalOscillation, ///< translation along `axis`
    Samples              ///< rigid transforms at sample times, interpolated
  };

  /// No motion: the identity at all times.
  static BodyMotion still();
  /// An oscillation s(t) = amplitude · sin(2π τ/period) · e(τ), τ = t − start, during
  /// `cycles` periods, zero before and after. The envelope e rises from 0 to 1 over the
  /// first quarter period and falls back over the last (smoothstep), so that the angle,
  /// its rate and its acceleration are continuous. With cycles = 1.5 a shake turns left,
  /// right and left (the paper's head shake). Amplitude in radians (shake, nod) or metres.
  static BodyMotion shake(const Eigen::Vector3d& pivot, const Eigen::Vector3d& axis,
                          double amplitude, double period, double start = 0, double cycles = 1.5);
  static BodyMotion nod(const Eigen::Vector3d& pivot, const Eigen::Vector3d& axis, double amplitude,
                        double period, double start = 0, double cycles = 1.5);
  static BodyMotion verticalOscillation(const Eigen::Vector3d& axis, double amplitude,
                                        double period, double start = 0, double cycles = 1.5);
  /// Rigid transforms at increasing times: translation by cubic Hermite (Catmull–Rom)
  /// interpolation, rotation by spherical linear interpolation; before the first sample
  /// the first pose, after the last the last.
  static BodyMotion samples(std::vector<double> times, std::vector<Eigen::Isometry3d> poses);

  /// Refuses NaN or infinite parameters, a zero axis, a period ≤ 0, cycles ≤ 0, sample
  /// times not strictly increasing, and sample poses whose rotation is not orthonormal.
  Status validate(const std::string& what = "the motion") const;

  Kind kind() const { return Type; }
  /// The scalar s(t) of the oscillating kinds (0 for the others).
  double signal(double t) const;
  /// The pose at time t (part at rest → part now).
  Eigen::Isometry3d pose(double t) const;

private:
  Kind Type = Kind::Still;
  Eigen::Vector3d Pivot = Eigen::Vector3d::Zero();
  Eigen::Vector3d Axis = Eigen::Vector3d::UnitY();
  double Amplitude = 0, Period = 1, Start = 0, Cycles = 1.5;
  std::vector<double> Times;
  std::vector<Eigen::Isometry3d> Poses;
};

/// Linear and angular velocity of a rigid motion at time t by central differences of step
/// h: the velocity of a world point p is v0 + ω × p.
void motionVelocity(const BodyMotion& motion, double t, double h, Eigen::Vector3d& v0,
                    Eigen::Vector3d& omega);

} // namespace hair
