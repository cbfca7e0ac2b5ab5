#pragma once
// Hair–hair contacts between guide strands, solved together with the strands' implicit steps.
// Each guide stands for a clump of radius `thickness` (Bertails, Audoly, Cani, Querleux,
// Leroy, Lévêque, "Super-Helices for predicting the dynamics of natural hair", ACM TOG
// 25(3), 2006, §4.4, after Plante et al. 2001); two pieces of different guides closer than
// 2 × thickness push each other apart with a dissipative penalty, and rub with Coulomb
// friction. The forces are unknowns of the step: every strand's implicit step is solved
// once without them, the contacts are solved in the space of the contact points with each
// strand's compliance (StrandCompliance: how its end-of-step velocities answer point
// forces, from its factorized step), by projected Gauss–Seidel sweeps, and each strand
// then adds their response. The gap a contact sees is the one predicted at the END of the
// step, so a pair closing fast is stopped within the step in which it would cross. The
// equations, the approximations and the defaults are in docs/hair-hair-contacts.md.
//
// Use, once per step of h (superhelix/StepStrands.cxx, stepStrandsWithContacts):
//   per strand i: beginStep(h)                       (its step without these contacts)
//   contacts.detect(every strand's freeSamples(), ids, h);
//   per strand i: compliance(contacts.couplingSamples(i), compliance[i]);
//   contacts.solve(compliance);
//   per strand i: endStep(couplingSamples(i), contacts.forces(i), contacts.response(i));
#include "common/Status.h"
#include "contact/ContactResponse.h"
#include "contact/SegmentGeometry.h"
#include "geometry/UniformGrid.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace hair
{

struct HairHairParameters
{
  /// Contact thickness of a guide, the radius of the clump of fibres it stands for [m]: two
  /// guides touch when their centrelines come closer than R = 2 × thickness. 0: automatic,
  /// automaticThickness() of the guides (resolved by the strand model before use).
  double thickness = 0;
  /// Normal penalty k [N/m]: force k δ per contact point at overlap δ (per referenceLength
  /// of contact with perLength).
  double stiffness = 1;
  /// Normal damping c_n [N·s/m] on the normal relative velocity (only while pressed).
  double damping = 2e-4;
  /// Coulomb friction coefficient μ between guides (dimensionless): a pair sticks while the
  /// tangential force it needs is below μ × its normal force, and slides with μ × the
  /// normal force otherwise. 0: frictionless.
  double friction = 0.3;
  /// Detection margin, a fraction of the contact distance R: pairs of pieces within
  /// R (1 + margin) of each other at the start of the step or where the step takes them are
  /// solved (the others could touch only if the motion over the step departed from the
  /// prediction by more than that).
  double margin = 0.25;
  /// Per-length penalty: each contact's force, stiffness and damping scaled by
  /// ℓ_c / referenceLength, where ℓ_c is the length of strand in contact for that pair of
  /// pieces (the mean of each piece's length inside the other's contact cylinder, clipped to
  /// the other piece's extent), instead of one contact per closest pair of points. Then a
  /// contact along two strands pushes per unit length whatever their sample spacing, which
  /// follows the curl (docs/hair-hair-contacts.md).
  bool perLength = false;
  /// ℓ_ref of perLength [m]: the length of contact that gets the per-point force.
  double referenceLength = 0.01;
  /// Most Gauss–Seidel sweeps over the contacts per solve (1 to 1000).
  int iterations = 10;
  /// The sweeps stop once no pair's own update moved its predicted end-of-step position
  /// relative to its partner by more than this fraction of R in a sweep (in (0, 1)).
  double tolerance = 1e-2;
  /// Threads of the search (1 to 256; the result does not depend on it).
  int threads = 1;
  /// Grid cell size [m]; 0: automatic.
  double cellSize = 0;

  /// Names the first bad parameter, what is wrong and what to do.
  Status validate() const;

  /// Fibres on a head of hair: 120 000, the low end of the 120 000–150 000 of Mizuno,
  /// Luengo and Rutland (Langmuir 29, 5857–5862, 2013).
  static constexpr double HeadFibres = 120000;
  /// The packing of the fibres in a guide's clump: half the cross-section filled.
  static constexpr double ClumpPacking = 0.5;
  /// The automatic thickness: the radius of a clump holding a head's fibres shared among
  /// `guides` guides, of `fibreRadius` each, at ClumpPacking: r √(HeadFibres / (guides ×
  /// ClumpPacking)) [m] (1.2 mm for 200 guides of the wavy preset's 35 µm fibres).
  static double automaticThickness(double fibreRadius, int guides);
};

/// What the last detect() and solve() did and found.
struct HairHairStats
{
  int strands = 0;
  long pieces = 0;
  long candidatePairs = 0;      ///< pairs of pieces whose swept boxes overlap
  long contacts = 0;            ///< pairs solved (within reach over the step)
  long active = 0;              ///< of them, pressed (normal force > 0) after solve()
  long sticking = 0;            ///< of the active, held by friction (inside the Coulomb cone)
  int sweeps = 0;               ///< Gauss–Seidel sweeps of the last solve()
  long guarded = 0;             ///< pairs swept again by the guard (summed over its rounds)
  double change = 0;            ///< the last sweep's largest move / (2 × thickness)
  double maxPenetration = 0;    ///< deepest overlap of a pair at the start of the step [m]
  double maxEndPenetration = 0; ///< deepest overlap predicted at the end of the step [m]
  double potentialEnergy = 0;   ///< Σ ½ k δ² of the predicted end overlaps [J]
  double work = 0;              ///< work of the contact forces on the strands over the step [J]
  double dissipated = 0;        ///< of which damping and friction dissipated (≥ 0) [J]
  int rounds = 0;               ///< detections in the step (detect() and the extend()s that ran)
  double searchSeconds = 0;     ///< wall time of the step's detections [s]
  double solveSeconds = 0;      ///< wall time of the step's solves [s]
};

/// One contact solved by the last solve() (for tests and studies).
struct HairHairContact
{
  int strandA = 0, strandB = 0;                       ///< indices in detect()'s order, A < B
  double sA = 0, sB = 0;                              ///< arc lengths of the closest points [m]
  Eigen::Vector3d pointA, pointB;                     ///< closest points at the start of the step
  double distance = 0;                                ///< their distance [m]
  Eigen::Vector3d normal;                             ///< (pointA − pointB) / distance
  Eigen::Vector3d forceOnA = Eigen::Vector3d::Zero(); ///< [N]; B receives −forceOnA
  Eigen::Vector3d relativeVelocity = Eigen::Vector3d::Zero(); ///< A − B at the end [m/s]
};

class HairHairContacts
{
public:
  /// Validates and keeps the parameters; forgets the previous step's forces.
  Status setParameters(const HairHairParameters& parameters);
  const HairHairParameters& parameters() const { return Params; }

  /// Finds the pairs of pieces of different strands that may come within 2 × thickness over
  /// a step of h [s], from every strand's samples: their positions at the start of the step
  /// and the velocities the step gives them without these contacts (each point moves to
  /// x + h v). Strand i has id ids[i] (ids empty: id = i). Ids must be distinct.
  Status detect(const std::vector<std::vector<StrandSample>>& samples, const std::vector<int>& ids,
                double h);
  /// After solve(): the detection again from `samples` whose velocities are those the solve
  /// gives (SuperHelix::predictedSamples), keeping every pair found so far with its force;
  /// `grew` tells whether it found new pairs (then solve() again).
  Status extend(const std::vector<std::vector<StrandSample>>& samples, bool& grew);
  /// The samples of strand i (detect()'s order) that carry a contact, increasing: the
  /// coupling samples its StrandCompliance must describe.
  const std::vector<int>& couplingSamples(int strand) const { return Coupling[strand]; }

  /// Solves the contacts found by detect(), given every strand's compliance (one per strand
  /// in detect()'s order; a strand without coupling samples may leave it empty).
  Status solve(const std::vector<StrandCompliance>& compliance);
  /// After solve(): the force on strand i at each of its coupling samples [N], and the
  /// change of its coordinate velocities they cause (Σ Y_k F_k).
  const std::vector<Eigen::Vector3d>& forces(int strand) const { return Forces[strand]; }
  const Eigen::VectorXd& response(int strand) const { return Response[strand]; }

  const HairHairStats& stats() const { return Stats; }
  /// The contacts of the last solve(), pressed or not.
  const std::vector<HairHairContact>& contacts() const { return Report; }
  /// Candidate pairs of pieces (strand, piece) of the last detect(), sorted, for tests.
  std::vector<std::pair<std::int64_t, std::int64_t>> candidatePairs() const;
  /// Piece k of strand i joins samples k and k + 1; its key is i << 32 | k.
  static std::int64_t pieceKey(int strand, int piece)
  {
    return (static_cast<std::int64_t>(strand) << 32) | static_cast<std::uint32_t>(piece);
  }

private:
  struct Piece
  {
    int strand, index; // joins samples index and index + 1 of strand
    Eigen::Vector3d lo, hi;
  };
  // One side of a contact: its strand, the coupling slots of its two samples (−1: weight 0)
  // and their weights (1 − u, u).
  struct Side
  {
    int strand, piece;
    double u;
    int slot[2];
    double phi[2];
  };
  struct Contact
  {
    Side a, b;
    Eigen::Vector3d n;               // from B to A at the start
    double d0;                       // start distance [m]
    double share;                    // vertex share, or ℓ_c / ℓ_ref
    Eigen::Vector3d pa, pb;          // closest points at the start
    std::int64_t keyA, keyB;         // piece keys (warm start)
    std::int64_t featureA, featureB; // the sample or piece the closest point is on
    // solve(): the pair's own compliance W, its force on A [N] and its relative velocity
    // without contact forces (w = wFree + Σ ±φ J_k Δ over its sides' samples).
    Eigen::Matrix3d W;
    Eigen::Vector3d r;
    Eigen::Vector3d wFree;
    bool solved; // r holds this step's force from an earlier solve()
  };
  // The guard after the sweeps: rounds, and sweeps over the pairs it found in each.
  static constexpr int GuardRounds = 4, GuardSweeps = 5;
  void buildPieces(double h);
  void broadPhase();
  std::vector<Contact> narrowPhase(double h);
  void assignSlots();
  Eigen::Vector3d relativeVelocity(const Contact& c) const;
  void apply(const Contact& c, const Eigen::Vector3d& dr);
  void localSolve(Contact& c, const Eigen::Vector3d& w) const;

  HairHairParameters Params;
  double StepSize = 0;
  std::vector<std::vector<StrandSample>> Samples;
  std::vector<int> Ids;
  std::vector<Piece> Pieces;
  std::vector<std::pair<int, int>> Candidates; // piece indices
  // The broad phase's grid of the pieces' boxes, grouped by strand (kept for its storage).
  std::vector<Box3> Boxes;
  std::vector<int> StrandOf;
  UniformGrid Grid;

  std::vector<Contact> Found;
  std::vector<std::vector<int>> Coupling;                    // per strand
  std::vector<std::vector<Eigen::Vector3d>> Forces;          // per strand, per coupling sample
  std::vector<Eigen::VectorXd> Response;                     // per strand
  const std::vector<StrandCompliance>* Compliance = nullptr; // during solve()
  // Warm start: the previous step's forces by piece keys (sorted by keys), kept by detect().
  struct Previous
  {
    std::int64_t keyA, keyB;
    Eigen::Vector3d r;
  };
  std::vector<Previous> Last;
  std::vector<HairHairContact> Report;
  HairHairStats Stats;
};

} // namespace hair
