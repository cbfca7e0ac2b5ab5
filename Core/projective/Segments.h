#pragma once
// A projective strand at rest: a chain of k rigid segments whose directions are two angles
// relative to the parent segment (Anjyo, Usami and Kurihara 1992; Kurihara, Anjyo and
// Thalmann 1993), with its material. The angle convention and the equations are in
// docs/projective-strands.md.
#include "common/Status.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <vector>

namespace hair
{

/// The material of one strand, SI. Defaults: one human hair (radius 40 µm, E ≈ 4 GPa,
/// 1300 kg/m³).
struct ProjectiveParameters
{
  double linearDensity = 6.5e-6;  ///< ρA, kg/m
  double bendingStiffness = 8e-9; ///< EI, N·m²; hinge stiffness κ = EI / d
  double dampingRate = 2.0;       ///< α, 1/s: angular damping per unit inertia
  /// β, s: damping proportional to the hinge stiffness (internal friction of the hinge),
  /// γ_i = α I_i + β κ. It damps the stiff high-frequency bending of short tip segments
  /// (ω ≈ √(3EI/(ρA d⁴))) without slowing the slow swing of the whole strand.
  double stiffnessDamping = 1e-3;
  double dragDiameter = 8e-5;   ///< D for the air drag, m
  double airDensity = 1.2;      ///< ρ_air, kg/m³
  double dragCoefficient = 1.2; ///< C_d of a cylinder across the flow (Re ~ 1–10: 1–3)
  Status validate() const;
};

/// One guide strand at rest, in the coordinates of the root's body part at rest.
struct ProjectiveStrand
{
  Eigen::Vector3d root = Eigen::Vector3d::Zero();
  /// Root frame, columns (e1, e2, e3), orthonormal and right-handed. The first segment's
  /// angles are measured in it (e3 is the straight continuation, see `segmentDirection`).
  Eigen::Matrix3d rootFrame = Eigen::Matrix3d::Identity();
  double segmentLength = 0.01;             ///< d, metres
  std::vector<Eigen::Vector2d> restAngles; ///< (θ⁰, φ⁰) of each segment; its size is k
  /// (θ, φ) of each segment at t = 0 when the strand starts out of its rest shape (a groom
  /// with a sag-free rest shape); empty: the rest angles.
  std::vector<Eigen::Vector2d> angles;
  ProjectiveParameters parameters;
};

/// Direction of a segment in its parent's frame: θ from the parent's e1 (the pole), φ about
/// it from e3 towards e2, so that (θ, φ) = (π/2, 0) continues the parent straight on and
/// the rest shapes of hair lie far from the poles:
///   u = (cos θ, sin θ sin φ, sin θ cos φ).
Eigen::Vector3d segmentDirection(double theta, double phi);
/// The rotation that takes the parent's frame to the child's: A = Rx(−φ) Ry(π/2 − θ).
Eigen::Matrix3d segmentRotation(double theta, double phi);

/// The material frame at each node of a strand whose root frame is `rootFrame` (columns
/// e1, e2, e3) and whose k segments have the angles (θ_i, φ_i), angles[2i] and
/// angles[2i + 1]: each segment's frame is its parent's times segmentRotation, as the model
/// chains them. Node 0 carries the root frame (the scalp's, which the head carries; the
/// first segment hinges on it), node i ≥ 1 the frame of segment i, the segment that ends at
/// it: tangent e3 (the segment's direction), first director e1. k + 1 values each;
/// overwritten.
void nodeFrames(const Eigen::Matrix3d& rootFrame, const double* angles, int segments,
                std::vector<Eigen::Vector3d>& tangents, std::vector<Eigen::Vector3d>& directors);
/// The material frame (tangent, first director, second director) of a frame (e1, e2, e3),
/// and back: (e3, e1, e2) and (n1, n2, n0).
Eigen::Matrix3d materialFrame(const Eigen::Matrix3d& segmentFrame);
Eigen::Matrix3d segmentFrame(const Eigen::Matrix3d& materialFrame);

/// Builds a strand from a polyline of equal segments (relative spread ≤ 1e-6, refused
/// otherwise): rest angles from the polyline, root frame with e3 along the first segment
/// and e1 as close as possible to `rootSide` (any vector not parallel to the first segment).
/// The material is left as it is in `strand`.
Status strandFromPolyline(const std::vector<Eigen::Vector3d>& points,
                          const Eigen::Vector3d& rootSide, ProjectiveStrand& strand);

/// The angles (θ, φ) of the segments of a polyline (root first) chained from `rootFrame`,
/// one per segment: the polyline's directions, whatever the frame's e3 (the first segment
/// need not continue it).
std::vector<Eigen::Vector2d> anglesAlong(const Eigen::Matrix3d& rootFrame,
                                         const std::vector<Eigen::Vector3d>& points);

/// Quadratic air drag on a straight segment of length `length`, unit direction `tangent`,
/// moving at `segmentVelocity` in air moving at `air`: only the relative flow across the
/// segment counts (independence principle),
///   f = ½ ρ C_d D ℓ |w⊥| w⊥,  w⊥ = (I − t tᵀ)(air − segmentVelocity).
Eigen::Vector3d segmentDrag(const ProjectiveParameters& material, const Eigen::Vector3d& air,
                            const Eigen::Vector3d& segmentVelocity, const Eigen::Vector3d& tangent,
                            double length);

} // namespace hair
