#pragma once
// A slope for the friction tests: the side of a vertical cylinder as an exact collision table.
#include "AnalyticBodies.h"
#include "collision/CollisionTable.h"

namespace hairtest
{

/// The side of a vertical cylinder of radius R about the y axis (heights ±0.5 m) as a
/// cylindrical table of 400 × 400 samples: its radius is constant, so the table is exact
/// (1.6 cm cells at R = 1 m). With gravity tilted towards the axis its side is a slope.
inline hair::Status slopeTable(double R, hair::CollisionTable& table)
{
  const CappedCylinder body(Eigen::Vector3d::Zero(), R, 0.5);
  hair::TableSpec spec;
  spec.projection = hair::Projection::Cylindrical;
  spec.azimuthSamples = spec.secondSamples = 400;
  spec.heightMin = -0.5;
  spec.heightMax = 0.5;
  return table.build(spec, body);
}

} // namespace hairtest
