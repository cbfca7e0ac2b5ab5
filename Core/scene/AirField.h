#pragma once
// The air around the hair: its velocity in space and time, which both models' drag acts
// against (each with its own drag law: docs/super-helix.md, docs/projective-strands.md).
#include "common/Status.h"

#include <Eigen/Core>

#include <functional>
#include <string>

namespace hair
{

/// Air velocity at a world position and time. Must be safe to call from several threads.
using AirVelocityField =
    std::function<Eigen::Vector3d(const Eigen::Vector3d& position, double time)>;

/// A wind of mean speed U along a direction, with optional gusts that travel with it and an
/// optional ramp from still air; still air by default.
struct AirField
{
  /// Where the air goes (normalised when used). The bundled body faces +Z, so wind "from
  /// the front" blows along −Z.
  Eigen::Vector3d direction = Eigen::Vector3d(0, 0, -1);
  double speed = 0;         ///< mean air speed U, m/s (0: still air, drag still damps)
  double gustAmplitude = 0; ///< relative gust strength a: speed U (1 + a sin(…)), 0 ≤ a ≤ 1
  double gustPeriod = 1;    ///< s
  /// The wind blows from this time on, reaching its mean speed over `rampTime` (smoothstep;
  /// 0: at once).
  double start = 0;
  double rampTime = 0;

  /// A steady, uniform wind of this velocity (m/s).
  static AirField uniform(const Eigen::Vector3d& velocity);

  /// Refuses NaN, a negative speed, a zero direction when speed > 0, a gust amplitude
  /// outside [0, 1], a gust period ≤ 0 and a negative ramp time.
  Status validate(const std::string& what = "the wind") const;

  /// Air velocity at point x and time t. Gusts travel with the mean flow:
  ///   w(x, t) = U r(t) (1 + a sin(2π (t − x·ê/U) / T)) ê,  r the start ramp.
  Eigen::Vector3d velocity(const Eigen::Vector3d& x, double t) const;
  /// True when the velocity is the same everywhere at every time t ≥ 0: no gusts, no ramp,
  /// a start at or before 0.
  bool isSteadyAndUniform() const;
  /// The field as a function (a copy of this wind).
  AirVelocityField field() const;
};

} // namespace hair
