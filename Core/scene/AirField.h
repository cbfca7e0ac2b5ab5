#pragma once
// Wind as a field of air velocity in space and time, and the drag it puts on a thin
// cylinder (a hair segment).
#include "common/Status.h"

#include <Eigen/Core>

#include <functional>
#include <string>

namespace hair
{

/// Wind velocity at a world position and time. Must be safe to call from several threads.
using AirVelocityField =
    std::function<Eigen::Vector3d(const Eigen::Vector3d& position, double time)>;

struct GustyWind
{
  /// Where the air goes (normalised when used). The bundled body faces +Z, so wind "from
  /// the front" blows along −Z.
  Eigen::Vector3d direction = Eigen::Vector3d(0, 0, -1);
  double speed = 0;         ///< mean air speed U, m/s (0: still air, drag still damps)
  double gustAmplitude = 0; ///< relative gust strength a: speed U (1 + a sin(…)), 0 ≤ a ≤ 1
  double gustPeriod = 1;    ///< s
  /// The wind starts at this time and reaches its mean speed over `rampTime` (smoothstep).
  double start = 0;
  double rampTime = 0.25;
  double airDensity = 1.2;      ///< kg/m³
  double dragCoefficient = 1.2; ///< C_d of a cylinder across the flow (Re ~ 1–10: 1–3)

  /// Refuses NaN, negative speed or density, a zero direction when speed > 0, a gust
  /// amplitude outside [0, 1] and a period ≤ 0.
  Status validate(const std::string& what = "the wind") const;

  /// Air velocity at point x and time t. Gusts travel with the mean flow:
  ///   w(x, t) = U r(t) (1 + a sin(2π (t − x·ê/U) / T)) ê,  r the start ramp.
  Eigen::Vector3d velocity(const Eigen::Vector3d& x, double t) const;

  /// Drag force on a straight segment of length `length` and diameter `diameter`, unit
  /// direction `tangent`, moving at `segmentVelocity`, in air moving at `air`: only the
  /// relative flow across the segment counts (independence principle),
  ///   f = ½ ρ C_d D ℓ |w⊥| w⊥,  w⊥ = (I − t tᵀ)(air − segmentVelocity).
  Eigen::Vector3d drag(const Eigen::Vector3d& air, const Eigen::Vector3d& segmentVelocity,
                       const Eigen::Vector3d& tangent, double length, double diameter) const;
};

} // namespace hair
