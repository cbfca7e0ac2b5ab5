#include "model/StrandPoints.h"

namespace hair
{

void StrandPoints::clear()
{
  positions.clear();
  velocities.clear();
  tangents.clear();
  directors.clear();
  curvature.clear();
  twist.clear();
}

void appendRoot(const RootState& root, std::vector<double>& frames, std::vector<double>& velocities)
{
  frames.insert(frames.end(), root.position.data(), root.position.data() + 3);
  // Eigen stores columns one after the other: tangent, first director, second director.
  frames.insert(frames.end(), root.orientation.data(), root.orientation.data() + 9);
  velocities.insert(velocities.end(), root.velocity.data(), root.velocity.data() + 3);
  velocities.insert(velocities.end(), root.angularVelocity.data(), root.angularVelocity.data() + 3);
}

RootState rootOf(const StateFrame& frame, std::size_t k)
{
  RootState r;
  const double* p = frame.rootFrames.data() + RootFrameValues * k;
  const double* v = frame.rootVelocities.data() + RootVelocityValues * k;
  r.position = Eigen::Vector3d(p[0], p[1], p[2]);
  r.orientation = Eigen::Map<const Eigen::Matrix3d>(p + 3);
  r.velocity = Eigen::Vector3d(v[0], v[1], v[2]);
  r.angularVelocity = Eigen::Vector3d(v[3], v[4], v[5]);
  return r;
}

} // namespace hair
