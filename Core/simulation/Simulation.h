#pragma once
// A whole scene advanced frame by frame, for either strand model: the one place where the
// pipeline's Hair Simulation meets the models. Guide strands, body parts (collision tables,
// some moving with the head), head motion, gravity and wind in; frames of positions,
// velocities, generalized coordinates and energy terms out.
#include "collision/CollisionTable.h"
#include "common/Progress.h"
#include "common/Status.h"
#include "contact/BodyContacts.h"
#include "contact/HairHairContacts.h"
#include "io/StateFile.h"
#include "scene/RootMotion.h"
#include "strands/HairParameters.h"
#include "superhelix/Quadrature.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace hair
{

enum class StrandModel
{
  SuperHelix = 0, ///< Bertails, Audoly, Cani et al. 2006
  Projective = 1  ///< Kurihara, Anjyo and Thalmann 1993
};

/// A guide strand as Hair Strands grows it.
struct GuideStrand
{
  Eigen::Vector3d root = Eigen::Vector3d::Zero();
  Eigen::Vector3d growth = Eigen::Vector3d::UnitY(); ///< direction of the first element
  Eigen::Vector3d normal = Eigen::Vector3d::UnitY(); ///< scalp normal at the root
  double length = 0.3;
  int elements = 10;
  HairParameters hair;
  std::uint32_t seed = 1;
};

/// How the head moves: θ(t) = amplitude · sin(2π frequency t) about `axis` through `pivot`
/// (shake, nod; amplitude in radians) or a displacement amplitude · sin(2π f t) along `axis`
/// (vertical oscillation; amplitude in metres).
struct HeadMotion
{
  enum class Kind
  {
    None = 0,
    Shake = 1,
    Nod = 2,
    Vertical = 3
  };
  Kind kind = Kind::None;
  double amplitude = 0.5;
  double frequency = 1.0;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitY();
  Eigen::Vector3d pivot = Eigen::Vector3d(0, 1.45, 0.02); ///< the bundled body's neck
  Status validate() const;
  /// Head at rest → head at time t.
  Eigen::Isometry3d pose(double t) const;
  /// Velocity v0 + ω × x and acceleration a0 + α × x + ω × (ω × x) of the head's points,
  /// analytic: returns (v0, ω, a0, α) about the world origin.
  void rates(double t, Eigen::Vector3d& v0, Eigen::Vector3d& omega, Eigen::Vector3d& a0,
             Eigen::Vector3d& alpha) const;
  /// A root carried rigidly by the head, at `root` with frame `frame` (columns: tangent,
  /// then the two normals) when the head is at rest: its state at any time, analytic.
  RootMotion carriedRoot(const Eigen::Vector3d& root, const Eigen::Matrix3d& frame) const;
};

struct SimulationPart
{
  BodyPart part;
  bool movesWithHead = false;
};

struct SimulationOptions
{
  StrandModel model = StrandModel::SuperHelix;
  double timeStep = 1.0 / 30;      ///< s; the projective model steps at most 1 ms (explicit)
  double frameInterval = 1.0 / 30; ///< s between stored frames
  Eigen::Vector3d gravity = Eigen::Vector3d(0, -9.81, 0);
  Eigen::Vector3d wind = Eigen::Vector3d::Zero(); ///< uniform air velocity, m/s
  HeadMotion motion;
  int threads = 1;
  int pointsPerElement = 4; ///< Super-Helix: display points per element
  /// Super-Helix: a priori bound on each element's quadrature error
  /// (StrandSpec::quadratureTolerance, in [1e-15, 1e-2]). The default keeps the quadrature
  /// error far below the 1/30 s step's own; 1e-2 makes curled hair 5–10 % faster and moves
  /// q after 2 s of a head shake by at most 4.6e-3 of its size, 48–230 times less than the
  /// 1/30 s step itself does (docs/benchmarks-superhelix.md, thirteenth revision).
  double quadratureTolerance = QuadratureChooser::defaultTolerance();
  /// Super-Helix: hair–body contacts against the scene's parts (docs/superhelix-contacts.md).
  /// `lookAhead` is set to the time step by the simulation. The projective model keeps its
  /// own reaction constraint (docs/projective-strands.md) and ignores these.
  BodyContactParameters contacts;
  /// Super-Helix: hair–hair contacts between the guides (docs/hair-hair-contacts.md). Before
  /// every step the contacts are found from all strands; when pairs close fast the step is
  /// cut into up to `hairHairMaxUpdates` pieces, each starting with a new search, so that
  /// no pair goes deeper than `hairHair.allowedDepth` of the contact distance within one.
  bool hairHairEnabled = false;
  HairHairParameters hairHair;
  int hairHairMaxUpdates = 8;
  Status validate() const;
};

/// Steps the scene. Frames are kept in memory (frame 0 is the initial state).
class Simulation
{
public:
  Simulation();
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  /// Checks everything and computes frame 0. Refuses no strands, bad parameters, a body
  /// part with an empty table, NaN anywhere, with a message naming the culprit.
  Status initialize(const std::vector<GuideStrand>& strands,
                    const std::vector<SimulationPart>& parts, const SimulationOptions& options);
  /// Computes frames until `frames` of them exist. `progress` (fraction of the requested
  /// frames) may abort; frames computed before the abort are kept. A step that fails stops
  /// with an error naming the strand and the time; the frames before it are kept, and every
  /// later call returns the same error (initialize again to restart).
  Status advanceTo(int frames, const Progress& progress = {});

  int numberOfFrames() const;
  /// Frame `index`; after releaseFrameData(index) only its time and energy are left (its
  /// arrays are empty: read it back from the state file).
  const StateFrame& frame(int index) const;
  /// Frees frame `index`'s per-point arrays, q and q̇, keeping its time and energy: for a
  /// caller that has the frame elsewhere (written to the state file) and streams a run
  /// longer than memory holds. The newest frame is never released (bytesPerFrame()
  /// measures it); an index out of range is ignored.
  void releaseFrameData(int index);
  /// False once releaseFrameData(index) was called.
  bool hasFrameData(int index) const;
  /// Memory one frame takes (bytes): positions, velocities, per-point arrays, q and q̇ of
  /// the newest frame (every frame has the same sizes).
  double bytesPerFrame() const;
  /// Frames are kept in memory: refuses a run of `frames` frames whose frames would need
  /// more than `availableBytes`, with the figures and what to change (call after
  /// initialize(); the caller chooses the budget, e.g. half the machine's memory).
  Status checkMemory(int frames, double availableBytes) const;
  /// The header a state file of this run needs (offsets, per-strand parameters, run
  /// attributes) and the energy terms beyond the required five.
  const StateHeader& header() const;
  const std::vector<std::string>& extraEnergyTerms() const;
  /// Per frame: nodes inside a body part after the step, and the deepest of them (m).
  const std::vector<long>& contacts() const;
  const std::vector<double>& maxDepth() const;

  /// The seam for other contact responses (e.g. hair–hair): a hook called for every
  /// Super-Helix strand at every (sub-)step right after the body's response, with the same
  /// samples and the same response buffer, to which it ADDS its own force, stiffness and
  /// damping (never overwrite: the body's response is already there). It runs on the thread
  /// that steps the strand, so it must be safe to call from several threads at once for
  /// different strands. Set it before initialize() (it is kept across initializations);
  /// an empty hook removes it.
  void setAdditionalContacts(ContactForces hook);

private:
  struct Impl;
  std::unique_ptr<Impl> P;
};

} // namespace hair
