#pragma once
// What the strands live in, the same for every model: body parts (collision tables) with
// their motions, the motion that carries the roots, gravity and the air.
#include "collision/CollisionTable.h"
#include "collision/PosedPart.h"
#include "common/Status.h"
#include "scene/AirField.h"
#include "scene/RigidMotion.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace hair
{

/// A body part: its table, built where the part is at rest, and how it moves.
struct ScenePart
{
  std::string name;
  CollisionTable table;
  RigidMotion motion; ///< still by default
};

struct Scene
{
  std::vector<ScenePart> parts;
  RigidMotion rootMotion; ///< carries the strands' roots (usually the head's motion)
  Eigen::Vector3d gravity = Eigen::Vector3d(0, -9.81, 0);
  AirField air;

  /// Refuses a part with an empty table, a motion or air that does not validate and
  /// non-finite gravity, naming which.
  Status validate() const;
  /// Every part at time t: its pose and velocity field from its motion. `out` is resized;
  /// its tables point into this scene.
  void posedParts(double t, std::vector<PosedPart>& out) const;
  /// A number that changes when anything a run's steps read of the scene does: the parts'
  /// names and tables, the poses of the parts and of the roots at fixed probe times over
  /// the first 100 s, gravity and the air's velocity at probe points and times (a 52-bit
  /// hash, exact in a double: the state file's scene_fingerprint).
  double fingerprint() const;
};

} // namespace hair
