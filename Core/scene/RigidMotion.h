#pragma once
// How a body part (the head, say) moves: a rigid motion given as a function of time, with
// its velocity and acceleration in closed form. Kurihara, Anjyo and Thalmann (1993) shake
// the head left, right and left; the Super-Helices paper (Bertails et al. 2006, §4.2) moves
// a clump's root up and down. One type for every body part, every strand root and both
// models: whatever moves the head moves the roots on it and its collision table alike.
#include "common/Status.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace hair
{

/// The clamped root of a strand: position, velocity, acceleration, orientation (columns:
/// tangent n0, n1, n2, in world coordinates), angular velocity and angular acceleration
/// (world), at one time.
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

/// A root's state as a function of time. An empty function means a root fixed at
/// RootState{}.
using RootMotion = std::function<RootState(double time)>;

/// The velocity field of a rigid body at one instant, about a reference point c: a point x
/// of the body moves at velocity + ω × (x − c) with acceleration
/// acceleration + α × (x − c) + ω × (ω × (x − c)). (Taken about c rather than the world
/// origin: for a head turning about its neck, the arms x − c are centimetres, not metres.)
struct RigidRates
{
  Eigen::Vector3d reference = Eigen::Vector3d::Zero(); ///< c
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  ///< of the point c
  Eigen::Vector3d angularVelocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d acceleration = Eigen::Vector3d::Zero(); ///< of the point c
  Eigen::Vector3d angularAcceleration = Eigen::Vector3d::Zero();

  Eigen::Vector3d velocityAt(const Eigen::Vector3d& x) const
  {
    return velocity + angularVelocity.cross(x - reference);
  }
  Eigen::Vector3d accelerationAt(const Eigen::Vector3d& x) const
  {
    const Eigen::Vector3d arm = x - reference;
    return acceleration + angularAcceleration.cross(arm) +
           angularVelocity.cross(angularVelocity.cross(arm));
  }
};

class RigidMotion
{
public:
  enum class Kind
  {
    Still,    ///< the identity at all times
    Shake,    ///< turning θ(t) about `axis` (up) through `pivot` (the neck)
    Nod,      ///< turning θ(t) about `axis` (lateral) through `pivot`
    Vertical, ///< moving by d(t) along `axis`
    Samples   ///< rigid transforms at sample times, interpolated
  };

  /// No motion.
  static RigidMotion still();
  /// θ(t) = amplitude · sin(2π frequency t) [rad] about `axis` through `pivot`.
  static RigidMotion shake(const Eigen::Vector3d& pivot, const Eigen::Vector3d& axis,
                           double amplitude, double frequency);
  static RigidMotion nod(const Eigen::Vector3d& pivot, const Eigen::Vector3d& axis,
                         double amplitude, double frequency);
  /// d(t) = amplitude · sin(2π frequency t) [m] along `axis`.
  static RigidMotion vertical(const Eigen::Vector3d& axis, double amplitude, double frequency);
  /// One of the three oscillations above by kind (Shake, Nod or Vertical); `pivot` is not
  /// used by Vertical.
  static RigidMotion oscillation(Kind kind, const Eigen::Vector3d& pivot,
                                 const Eigen::Vector3d& axis, double amplitude, double frequency);
  /// Rigid transforms at increasing times: translation by cubic Hermite (Catmull–Rom)
  /// interpolation, rotation by spherical linear interpolation (a constant angular velocity
  /// between samples); before the first sample the first pose, after the last the last.
  static RigidMotion samples(std::vector<double> times, std::vector<Eigen::Isometry3d> poses);

  /// An oscillation that runs only from `start` for `cycles` periods (∞: without end) and
  /// is at rest before and after, its phase counted from `start`: s(t) = amplitude ·
  /// sin(2π f (t − start)). Without it, the oscillation runs at all times, its phase
  /// counted from t = 0. With cycles = 1.5 a shake turns left, right and left (the paper's).
  RigidMotion& during(double start, double cycles = std::numeric_limits<double>::infinity());
  /// Over `seconds` after its start (and before its end, if it has one), the oscillation
  /// grows from rest (falls back to rest) by the smoothstep e(x) = 3x² − 2x³, so that s, ṡ
  /// and s̈ are continuous (an abrupt start makes ṡ jump to 2π f · amplitude). Needs a start
  /// (during()); 0, the default: no fade. At most half the window's length.
  RigidMotion& fading(double seconds);

  /// Refuses NaN or infinite parameters, a zero axis, a frequency ≤ 0, cycles ≤ 0, a fade
  /// < 0 or without a start, sample times not strictly increasing, and sample poses that are
  /// not rigid. `what` names the motion in the message.
  Status validate(const std::string& what = "the motion") const;

  Kind kind() const { return Type; }
  bool moves() const { return Type != Kind::Still; }
  const Eigen::Vector3d& pivot() const { return Pivot; }
  const Eigen::Vector3d& axis() const { return Axis; }
  double amplitude() const { return Amplitude; }
  double frequency() const { return Frequency; }
  double start() const { return Start; }
  double cycles() const { return Cycles; }
  double fade() const { return Fade; }

  /// The oscillation's signal s(t) (radians or metres) and its first two time derivatives
  /// (0 for Still and Samples).
  void signal(double t, double& s, double& sDot, double& sDdot) const;
  double signal(double t) const;
  /// Body at rest → body at time t.
  Eigen::Isometry3d pose(double t) const;
  /// The body's velocity field at time t, analytic (about the pivot for turns).
  RigidRates rates(double t) const;
  /// A point carried by the body, at `point` with frame `frame` (columns: tangent, then the
  /// two normals) when the body is at rest: its state at time t, analytic.
  RootState carried(const Eigen::Vector3d& point, const Eigen::Matrix3d& frame, double t) const;
  /// The same as a function of time (a copy of the motion is kept).
  RootMotion carriedRoot(const Eigen::Vector3d& point, const Eigen::Matrix3d& frame) const;

private:
  Kind Type = Kind::Still;
  Eigen::Vector3d Pivot = Eigen::Vector3d::Zero();
  Eigen::Vector3d Axis = Eigen::Vector3d::UnitY();
  double Amplitude = 0, Frequency = 1;
  double Start = -std::numeric_limits<double>::infinity();
  double Cycles = std::numeric_limits<double>::infinity();
  double Fade = 0;
  std::vector<double> Times;
  std::vector<Eigen::Isometry3d> Poses;
  std::size_t interval(double t) const; ///< Samples: i with Times[i] <= t < Times[i + 1]
};

} // namespace hair
