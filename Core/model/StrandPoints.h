#pragma once
// What a model draws of one strand at one time — the points, their velocities and the
// material frame at each — and how a root's pose and rates are kept in a frame
// (StateFrame::rootFrames, rootVelocities), so that a strand can be drawn again from its
// coordinates at any time after the run (simulation/GuideDrawing.h).
#include "io/StateFile.h"
#include "scene/RigidMotion.h"

#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace hair
{

/// One strand's points, root first.
struct StrandPoints
{
  std::vector<Eigen::Vector3d> positions, velocities;
  std::vector<Eigen::Vector3d> tangents;  ///< unit, along the strand
  std::vector<Eigen::Vector3d> directors; ///< unit, ⊥ tangent: the material frame's first director
  std::vector<double> curvature, twist;   ///< 1/m
  void clear();
};

/// Appends `root`'s position and orientation (RootFrameValues numbers: the position, then
/// the columns tangent, first director, second director) and its velocity and angular
/// velocity (RootVelocityValues numbers).
void appendRoot(const RootState& root, std::vector<double>& frames,
                std::vector<double>& velocities);
/// Strand k's root as appendRoot stored it (no acceleration: zero).
RootState rootOf(const StateFrame& frame, std::size_t k);

} // namespace hair
