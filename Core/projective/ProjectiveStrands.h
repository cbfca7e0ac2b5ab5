#pragma once
// The projective strand model of Anjyo, Usami and Kurihara (1992) as extended by Kurihara,
// Anjyo and Thalmann (1993): each strand is a chain of rigid segments (Segments.h) whose
// angles each obey a damped one-dimensional angular equation with a hinge spring towards
// the styled rest value, integrated explicitly from root to tip (ProjectiveStrands.cxx);
// nodes that enter a body part get the reaction-constraint response of Platt and Barr (1988)
// and are put back on the surface by turning their segment (Projection.cxx). The equations
// the code solves are in docs/projective-strands.md.
#include "collision/PosedPart.h"
#include "common/Progress.h"
#include "common/Status.h"
#include "contact/ReactionConstraint.h"
#include "projective/Segments.h"
#include "scene/Scene.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace hair
{

struct ProjectiveOptions
{
  double timeStep = 1e-3; ///< h, s
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
  /// Coulomb friction with the body parts at the nodes the reaction constraint holds
  /// (docs/projective-strands.md, "Friction"): μ, the kinetic coefficient (0 with μ_s 0: no
  /// friction), anisotropic as the Super-Helix's, μ (1 + a cos ψ), ψ between the fibre's
  /// tangent and the sliding velocity; μ_s, the static coefficient (0: μ, plain Coulomb;
  /// otherwise ≥ μ). A node sticks to where it touched (in the part's coordinates) while the
  /// force that holds it there stays within μ_s λ, λ the constraint's normal force, and
  /// slides beyond it with μ λ until it stops.
  double friction = 0;
  double staticFriction = 0;
  double anisotropy = 0.2;
  int threads = 1; ///< strands are stepped on this many threads
  Status validate() const;
};

/// Energies (J) and cumulated works (J) since the start. With
///   E = kinetic + gravitational + elastic,
/// the budget
///   E(t) − E(0) = bodyWork + windWork + contactWork − dissipated − contactDissipated
///                 − frictionDissipated + residual
/// closes by definition of `residual`, which is the explicit integrator's error (first
/// order in h: see docs/projective-strands.md, "Energy report").
struct ProjectiveEnergy
{
  double time = 0;
  double kinetic = 0;       ///< ½ Σ I_i (θ̇_i² + φ̇_i²): the angular equations' own inertia
  double gravitational = 0; ///< −Σ m g·c over segment centres c (world coordinates)
  double elastic = 0;       ///< ½ Σ κ ((θ−θ⁰)² + (φ−φ⁰)²): the hinge springs
  double dissipated = 0;    ///< ∫ Σ γ_i |q̇_i|² dt: angular damping (≥ 0)
  double bodyWork = 0;      ///< work of the moving roots: inertial force and carried frames
  double windWork = 0;      ///< work of the air drag (negative in still air: air damping)
  /// Work of the contacts less what they dissipate: of the reaction constraint's holding
  /// and spring forces, and of the projections (moving nodes back out)
  double contactWork = 0;
  double projectionWork = 0; ///< the part of contactWork done by the projections
  /// Energy lost in contact events: what the reaction constraint's damper takes and what the
  /// projections' inelastic rule takes from the rates (≥ 0)
  double contactDissipated = 0;
  double inelasticDissipated = 0; ///< the part of contactDissipated by the inelastic rule
  /// What friction with the body dissipated (sliding, ≥ 0 but for the small pull back of a
  /// stuck node to its anchor); the rest of friction's work is in contactWork
  double frictionDissipated = 0;
  double residual = 0; ///< E − E(0) − (works − dissipated)
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
  long stuck = 0;            ///< contact nodes held by friction (static) over the step
  long sliding = 0;          ///< contact nodes sliding (kinetic friction) over the step
  double maxDepthBefore = 0; ///< deepest node inside a part before the projection, m
  double maxDepthAfter = 0;  ///< deepest node inside a part at the end of the step, m
  Eigen::Vector3d deepestPoint = Eigen::Vector3d::Zero(); ///< where maxDepthAfter was found
  int deepestPart = -1;
  double seconds = 0; ///< wall time of the step
  int threads = 1;
  /// Adds a block's figures (counts add up, the deepest stays).
  void merge(const ProjectiveStepStats& other);
};

class ProjectiveStrands
{
public:
  /// Checks everything and sets the strands at their rest shape, at rest, at time 0, in
  /// the scene (its parts, motions, gravity and air). Refuses no strands, a strand with no
  /// segments or a bad length, frame or material, NaN angles, a scene that does not
  /// validate and bad options, each with a message naming the culprit.
  Status initialize(std::vector<ProjectiveStrand> strands, Scene scene,
                    const ProjectiveOptions& options);

  /// Replaces the angles and rates of strand s (for tests and restarts) and restarts the
  /// energy budget (works to zero, E(0) the new state).
  Status setState(int s, const std::vector<Eigen::Vector2d>& angles,
                  const std::vector<Eigen::Vector2d>& rates);

  /// Replaces the rest angles (θ⁰, φ⁰) of strand s (a sag-free rest shape) and restarts the
  /// energy budget, as setState does.
  Status setRestAngles(int s, const std::vector<Eigen::Vector2d>& restAngles);
  /// The generalized forces Q (θ, φ) of every joint of strand s in its current angles, at
  /// rest: the moments of gravity and of the reaction constraint about each joint's axis,
  /// with the rates, the roots' motion, the parts' velocities and the wind all taken as zero
  /// (the hinge springs are not in Q). The forces of the step, computed by the step's own
  /// code: with κ (q − q⁰) = Q the strand is a static equilibrium.
  void restMoments(int s, std::vector<Eigen::Vector2d>& moments) const;
  const ProjectiveParameters& material(int s) const { return Strands[s].material; }
  /// κ = EI / d of strand s's hinges.
  double hingeStiffness(int s) const { return Strands[s].kappa; }
  const std::vector<Eigen::Vector2d>& restAngles(int s) const { return Strands[s].q0; }

  /// Everything strand s's next steps depend on beyond its material and rest shape, as
  /// numbers (appended to `out`): angles, rates, nodes, frames, contacts, node velocities,
  /// friction's anchors and loads, and its works since the start.
  void saveContinuation(int s, std::vector<double>& out) const;
  /// Puts back what saveContinuation gave into strand s of strands initialized alike;
  /// refuses numbers of another layout.
  Status restoreContinuation(int s, const std::vector<double>& values);
  /// How many numbers saveContinuation gives strand s.
  std::size_t continuationSize(int s) const;
  /// The clock: the time and the steps taken (restored with the strands').
  long steps() const { return Steps; }
  void restoreClock(double time, long steps)
  {
    Time = time;
    Steps = steps;
  }

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
  /// Frame of segment i (1 … k) of strand s now (world; columns e1, e2, e3 = direction).
  const Eigen::Matrix3d& segmentFrame(int s, int i) const { return Strands[s].R[i]; }
  /// Velocities of the nodes of strand s over the last step (zero before the first).
  const std::vector<Eigen::Vector3d>& nodeVelocities(int s) const { return Strands[s].nodeV; }
  /// What the model found at node i (1 … k) of strand s when it placed it at the end of
  /// the last step: the part it is deepest in or nearest to (part −1: none near).
  const PartContact& nodeContact(int s, int i) const { return Strands[s].contact[i]; }
  const hair::Scene& scene() const { return World; }
  const ProjectiveOptions& options() const { return Options; }

  /// Energies now and works since the start, summed over the strands.
  ProjectiveEnergy energy() const;

  /// One line: strands, segments, steps, time per step, threads.
  std::string summary() const;

private:
  struct Strand
  {
    ProjectiveParameters material;
    double d = 0, mass = 0, kappa = 0;
    Eigen::Vector3d rootRest;
    Eigen::Matrix3d frameRest;
    std::vector<Eigen::Vector2d> q, qd, q0;
    std::vector<double> inertia;      ///< I_i = ρ ℓ_i³ / 3, ℓ_i the length carried by joint i
    std::vector<double> damping;      ///< γ_i = α I_i + β κ
    std::vector<double> gain, damper; ///< h / I_i and 1 / (1 + h γ_i / I_i)
    /// Per node j: Σ_l m_l Σ_{i≤min(j,l)} |P_j − P_{i−1}||P_l − P_{i−1}|/I_i for the straight
    /// strand, a bound (Gershgorin's) of how much more the constraint moves node j, every
    /// node of the strand held at once, than it would move a free node.
    std::vector<double> mobility;
    std::vector<Eigen::Vector3d> P;
    std::vector<Eigen::Matrix3d> R;     ///< R[0] root frame, R[i] frame of segment i
    std::vector<PartContact> contact;   ///< per node, from the end of the previous step
    std::vector<Eigen::Vector3d> nodeV; ///< (P_i(t + h) − P_i(t)) / h of the last step
    /// Friction, per node: where it stuck (part −1: nowhere; `placed` false: it is taken
    /// where the node is at the next step's start) and the constraint's normal force λ over
    /// the step [N].
    struct Anchor
    {
      int part = -1;
      bool placed = false;
      bool sliding = false;
      Eigen::Vector3d rest = Eigen::Vector3d::Zero();
    };
    std::vector<Anchor> anchors;
    std::vector<double> load;
    // Scratch (per strand, so threads never share).
    std::vector<Eigen::Vector3d> v;
    double dissipated = 0, bodyWork = 0, windWork = 0, contactWork = 0, projectionWork = 0;
    double constraintDissipated = 0, inelasticDissipated = 0, frictionDissipated = 0;
  };
  /// Everything a step needs that does not depend on the strand.
  struct StepFrame
  {
    double t0 = 0, h = 0;
    std::vector<PosedPart> parts0, parts1; ///< the parts at t0 and t0 + h
    Eigen::Isometry3d root0, root1;        ///< the roots' pose at t0 and t0 + h
    RigidRates rootRates;                  ///< the roots' velocity field at t0
    bool stillAir = false;                 ///< no wind (restMoments)
  };

  void forward(Strand& s, const Eigen::Vector3d& root, const Eigen::Matrix3d& frame) const;
  /// The nodes' velocities (world, into the strand's scratch `v`) from the roots' velocity
  /// field and the strand's rates, in its current frames.
  void nodeVelocities(Strand& s, const RigidRates& roots) const;
  void stepStrand(Strand& s, const StepFrame& f, ProjectiveStepStats& stats) const;
  /// The step's forces and the update of every joint; with `moments`, only the forces: Q of
  /// each joint is written there and the strand's angles and rates are left as they are.
  void forces(Strand& s, const StepFrame& f, ProjectiveStepStats& stats,
              std::vector<Eigen::Vector2d>* moments = nullptr) const;
  void place(Strand& s, const StepFrame& f, ProjectiveStepStats& stats) const;
  /// Coulomb friction at the contact nodes (Friction.cxx): after forces(), before place().
  void friction(Strand& s, const StepFrame& f, ProjectiveStepStats& stats) const;
  bool frictionOn() const { return Options.friction > 0 || Options.staticFriction > 0; }
  /// How far outside a part a node is held by the reaction constraint: the contact margin,
  /// where the constraint puts it. With friction, twice that: a node resting on a part sits
  /// at the margin, and a contact that came and went with its last micrometre would take
  /// its normal force, and the friction that holds it, with it every other step.
  double contactBand() const { return (frictionOn() ? 2 : 1) * Options.contactMargin; }
  bool deepest(const std::vector<PosedPart>& parts, const Eigen::Vector3d& p, PartContact& c) const;
  double gravitational(const Strand& s) const;
  double strandEnergy(const Strand& s) const;
  double unprojectedEnergy(const Strand& s, const Eigen::Vector3d& root,
                           const Eigen::Matrix3d& rootFrame) const;

  std::vector<Strand> Strands;
  hair::Scene World;
  ProjectiveOptions Options;
  double Time = 0;
  long Steps = 0;
  double StepSeconds = 0;
  double InitialEnergy = 0;
};

} // namespace hair
