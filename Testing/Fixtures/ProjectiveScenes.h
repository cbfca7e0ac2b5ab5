#pragma once
// The two scenes of Kurihara, Anjyo and Thalmann (1993) on the bundled body: guide strands
// rooted on the scalp, combed down over the head; wind from the front; the head shaking
// left, right and left in a little wind. Used by the tests, the benchmark and the docs.
#include "collision/CollisionTable.h"
#include "common/Status.h"
#include "geometry/TriangleMesh.h"
#include "projective/ProjectiveStrands.h"
#include "scene/Scene.h"

#include <cstdint>
#include <string>
#include <vector>

namespace hair
{

/// The bundled body and its head and trunk tables, built from Data/body.vtk and
/// Data/body_parts.txt (in `dataDir`).
struct BundledBody
{
  TriangleMesh mesh;
  std::vector<ScenePart> parts; ///< "head" (spherical) then "trunk" (cylindrical), still
  int head = -1, trunk = -1;    ///< indices in `parts`
  Eigen::Vector3d headCentre = Eigen::Vector3d::Zero();
  Eigen::Vector3d neckPivot = Eigen::Vector3d::Zero(); ///< the head turns about it
};
Status loadBundledBody(const std::string& dataDir, BundledBody& body);

struct ScalpOptions
{
  int strands = 1000;
  int segments = 40;
  double length = 0.40;     ///< strand length, m
  double bendPerMetre = 20; ///< combing: rad/m turned towards −y (and a little back)
  double clearance = 2e-3;  ///< combed nodes are put this far outside the parts, m
  std::uint64_t seed = 1993;
};

/// Spreads roots over the bundled body's scalp (sampleRoots on bundled::scalp) and combs
/// each strand from the scalp normal downwards, keeping its nodes outside the parts at
/// rest. The combed shape is the styled rest shape.
Status scalpStrands(const BundledBody& body, const ScalpOptions& options,
                    std::vector<ProjectiveStrand>& strands);

enum class PaperScene
{
  Wind, ///< head and trunk still, wind from the front with gusts
  Shake ///< head shakes left, right and left about the neck, a little wind
};
/// The scene (parts, motions, wind) and its run duration in seconds.
Scene paperScene(const BundledBody& body, PaperScene which, double& duration);

} // namespace hair
