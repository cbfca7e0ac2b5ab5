#pragma once
// The projective strand model of Anjyo, Usami and Kurihara (1992) as extended by Kurihara,
// Anjyo and Thalmann (1993): each strand is a chain of k rigid segments whose directions
// are two angles relative to the parent segment, each angle obeying a damped
// one-dimensional angular equation with a hinge spring towards its styled rest value,
// integrated explicitly from root to tip; nodes that enter a body part get the
// reaction-constraint response of Platt and Barr (1988) and are put back on the surface by
// turning their segment. The equations the code solves are in docs/projective-strands.md.
#include "collision/CollisionTable.h"
#include "common/Progress.h"
#include "common/Status.h"
#include "contact/ReactionConstraint.h"
#include "scene/BodyMotion.h"
#include "scene/AirField.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace hair
{

/// One guide strand at rest, in the coordinates of the root's body part at rest.
struct ProjectiveStrand
{
  Eigen::Vector3d root = Eigen::Vector3d::Zero();
  /// Root frame, columns (e1, e2, e3), orthonormal and right-handed. The first segment's
  /// angles are measured in it (e3 is the straight continuation, see `direction`).
  Eigen::Matrix3d rootFrame = Eigen::Matrix3d::Identity();
  double segmentLength = 0.01;             ///< d, metres
  std::vector<Eigen::Vector2d> restAngles; ///< (θ⁰, φ⁰) of each segment; its size is k
};

/// Direction of a segment in its parent's frame: θ from the parent's e1 (the pole), φ about
/// it from e3 towards e2, so that (θ, φ) = (π/2, 0) continues the parent straight on and
/// the rest shapes of hair lie far from the poles:
///   u = (cos θ, sin θ sin φ, sin θ cos φ).
Eigen::Vector3d segmentDirection(double theta, double phi);
/// The rotation that takes the parent's frame to the child's: A = Rx(−φ) Ry(π/2 − θ).
Eigen::Matrix3d segmentRotation(double theta, double phi);

/// Builds a strand from a polyline of equal segments (relative spread ≤ 1e-6, refused
/// otherwise): rest angles from the polyline, root frame with e3 along the first segment
/// and e1 as close as possible to `rootSide` (any vector not parallel to the first segment).
Status strandFromPolyline(const std::vector<Eigen::Vector3d>& points,
                          const Eigen::Vector3d& rootSide, ProjectiveStrand& strand);

/// Physical parameters, SI. Defaults: one human hair (radius 40 µm, E ≈ 4 GPa, 1300 kg/m³).
struct ProjectiveParameters
{
  double linearDensity = 6.5e-6;  ///< ρA, kg/m
  double bendingStiffness = 8e-9; ///< EI, N·m²; hinge stiffness κ = EI / d
  double dampingRate = 2.0;       ///< α, 1/s: angular damping per unit inertia
  /// β, s: damping proportional to the hinge stiffness (internal friction of the hinge),
  /// γ_i = α I_i + β κ. It damps the stiff high-frequency bending of short tip segments
  /// (ω ≈ √(3EI/(ρA d⁴))) without slowing the slow swing of the whole strand.
  double stiffnessDamping = 1e-3;
  double dragDiameter = 8e-5; ///< D for the air drag, m
  Status validate() const;
};

struct ProjectiveOptions
{
  double timeStep = 1e-3; ///< h, s
  Eigen::Vector3d gravity = Eigen::Vector3d(0, -9.81, 0);
  ProjectiveParameters parameters;
  /// Reaction constraint: stiffness per unit mass (1/s²) and damping (critical when < 0).
  ReactionConstraintOptions contact = {4.0e4, -1, true};
  /// Nodes closer than this to a surface are in contact: the constraint holds them at this
  /// distance outside, and projected nodes are put back at it. Metres.
  double contactMargin = 1.0e-3;
  /// Turn segments so that their end nodes stay outside the body parts (the paper's
  /// angle update). Off: the reaction-constraint force alone.
  bool projectOutside = true;
  /// The inertial force −m a of the moving roots (a = acceleration of each root).
  bool inertialForce = true;
  int threads = 1; ///< strands are split among this many std::threads
  Status validate() const;
};

/// What a scene holds besides the strands: body parts with their motions, the motion of
/// the strand roots (usually the head's) and the wind.
struct ProjectiveScene
{
  std::vector<BodyPart> parts;     ///< tables; poses are set from `motions` at each step
  std::vector<BodyMotion> motions; ///< one per part (empty: every part still)
  BodyMotion rootMotion;           ///< where the roots are carried
  GustyWind wind;
};

/// Energies (J) and cumulated works (J) since the start. With
///   E = kinetic + gravitational + elastic,
/// the budget E(t) − E(0) = bodyWork + windWork + contactWork − dissipated + residual
/// closes by definition of `residual`, which is the explicit integrator's error (it stays
/// O(h) and does not drift: see docs/projective-strands.md).
struct ProjectiveEnergy
{
  double time = 0;
  double kinetic = 0;       ///< ½ Σ I_i (θ̇_i² + φ̇_i²): the angular equations' own inertia
  double gravitational = 0; ///< −Σ m g·c over segment centres c (world coordinates)
  double elastic = 0;       ///< ½ Σ κ ((θ−θ⁰)² + (φ−φ⁰)²): the hinge springs
  double dissipated = 0;    ///< ∫ Σ γ_i |q̇_i|² dt: angular damping (≥ 0)
  double bodyWork = 0;      ///< work of the moving roots: inertial force and carried frames
  double windWork = 0;      ///< work of the air drag (negative in still air: air damping)
  double contactWork = 0;   ///< work of the reaction constraint and of the projections
  double projectionWork = 0; ///< the part of contactWork done by the projections
  double residual = 0;       ///< E − E(0) − (works − dissipated)
  /// (h/2) Σ q̇·Q_cons: with it, E + shadow is the quantity the symplectic Euler scheme
  /// keeps (its modified energy, to O(h²)); without driving it never increases.
  double shadow = 0;
  double total() const { return kinetic + gravitational + elastic; }
};

/// Per-step collision figures.
struct ProjectiveStepStats
{
  long contacts = 0;         ///< nodes within the contact margin of a part (constraint on)
  long projections = 0;      ///< nodes turned back outside during the step
  double maxDepthBefore = 0; ///< deepest node inside a part before the projection, m
  double maxDepthAfter = 0;  ///< deepest node inside a part at the end of the step, m
  Eigen::Vector3d deepestPoint = Eigen::Vector3d::Zero(); ///< where maxDepthAfter was found
  int deepestPart = -1;
  double seconds = 0; ///< wall time of the step
  int threads = 1;
};

class ProjectiveStrands
{
public:
  /// Checks everything and sets the strands at their rest shape, at rest, at time 0.
  /// Refuses no strands, a strand with no segments or a bad length or frame, NaN angles,
  /// a body part with an empty table, a motion count that does not match the parts, NaN in
  /// a motion or in the wind, and bad options, each with a message naming the culprit.
  Status initialize(std::vector<ProjectiveStrand> strands, ProjectiveScene scene,
                    const ProjectiveOptions& options);

  /// Replaces the angles and rates of strand s (for tests and restarts) and restarts the
  /// energy budget (works to zero, E(0) the new state).
  Status setState(int s, const std::vector<Eigen::Vector2d>& angles,
                  const std::vector<Eigen::Vector2d>& rates);

  /// One step of h. Thread-safe inside; not to be called concurrently.
  Status step(ProjectiveStepStats* stats = nullptr);
  /// Steps until `duration` has passed (rounded to whole steps); `progress` (optional) is
  /// told the fraction done after each step and may abort.
  Status advance(double duration, const Progress& progress = {});

  double time() const { return Time; }
  int numberOfStrands() const { return static_cast<int>(Strands.size()); }
  int numberOfSegments(int s) const { return static_cast<int>(Strands[s].q.size()); }
  double segmentLength(int s) const { return Strands[s].d; }
  /// Nodes P_0 … P_k of strand s in world coordinates at the current time.
  const std::vector<Eigen::Vector3d>& nodes(int s) const { return Strands[s].P; }
  const std::vector<Eigen::Vector2d>& angles(int s) const { return Strands[s].q; }
  const std::vector<Eigen::Vector2d>& rates(int s) const { return Strands[s].qd; }
  /// Root frame of strand s now (world).
  const Eigen::Matrix3d& rootFrame(int s) const { return Strands[s].R.front(); }
  const ProjectiveScene& scene() const { return Scene; }
  const ProjectiveOptions& options() const { return Options; }

  /// Energies now and works since the start, summed over the strands.
  ProjectiveEnergy energy() const;

  /// One line: strands, segments, steps, time per step, threads.
  std::string summary() const;

private:
  struct Contact
  {
    int part = -1; ///< −1: no part near
    double depth = 0;
    Eigen::Vector3d normal = Eigen::Vector3d::UnitY();
    Eigen::Vector3d surface = Eigen::Vector3d::Zero(); ///< Q, world
  };
  struct Strand
  {
    double d = 0, mass = 0, kappa = 0;
    Eigen::Vector3d rootRest;
    Eigen::Matrix3d frameRest;
    std::vector<Eigen::Vector2d> q, qd, q0;
    std::vector<double> inertia;      ///< I_i = ρ ℓ_i³ / 3, ℓ_i the length carried by joint i
    std::vector<double> damping;      ///< γ_i = α I_i + β κ
    std::vector<double> gain, damper; ///< h / I_i and 1 / (1 + h γ_i / I_i)
    /// Per node: m_n Σ_{i≤j} |P_j − P_{i−1}|²/I_i for the straight strand, a bound of how
    /// much more a force at node j moves it than it would move a free node of mass m_n.
    std::vector<double> mobility;
    std::vector<Eigen::Vector3d> P;
    std::vector<Eigen::Matrix3d> R; ///< R[0] root frame, R[i] frame of segment i
    std::vector<Contact> contact;   ///< per node, from the end of the previous step
    // Scratch (per strand, so threads never share).
    std::vector<Eigen::Vector3d> v;
    double dissipated = 0, bodyWork = 0, windWork = 0, contactWork = 0, projectionWork = 0;
  };
  struct StepFrame; // per-step data shared read-only by the threads

  void forward(Strand& s, const Eigen::Vector3d& root, const Eigen::Matrix3d& frame) const;
  void stepStrand(Strand& s, const StepFrame& f, ProjectiveStepStats& stats) const;
  void forces(Strand& s, const StepFrame& f, ProjectiveStepStats& stats) const;
  bool deepest(const StepFrame& f, const Eigen::Vector3d& p, Contact& c) const;
  double gravitational(const Strand& s) const;
  double strandEnergy(const Strand& s) const;
  double unprojectedEnergy(const Strand& s, const Eigen::Vector3d& root,
                           const Eigen::Matrix3d& rootFrame) const;

  std::vector<Strand> Strands;
  ProjectiveScene Scene;
  ProjectiveOptions Options;
  std::vector<double> PartReach;         ///< per part: squared radius of a ball holding its table
  std::vector<Eigen::Vector3d> PartAxis; ///< per part: unit axis of its table frame
  double Time = 0;
  long Steps = 0;
  double StepSeconds = 0;
  double InitialEnergy = 0;
};

} // namespace hair
