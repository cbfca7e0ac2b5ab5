#pragma once
// Hair–hair contacts between guide strands: dissipative penalty forces between close pieces
// of different strands, as in the Super-Helices paper (Bertails, Audoly, Cani, Querleux,
// Leroy, Lévêque, ACM TOG 25(3), 2006, §4.4: penalty forces between guide strands, each
// standing for a clump with a thickness, closest points tracked with temporal coherence,
// after Plante et al. 2001 and Bertails et al. 2005 "adaptive wisp tree"). The equations,
// the approximations and the defaults are in docs/hair-hair-contacts.md.
//
// Use, once per step (the simulation's seam):
//   contacts.update(strands);                       // one thread, before stepping
//   strand.setContactForces(contacts.hook());       // or, composed with body contacts:
//     [&](int id, double t, const auto& s, auto& r) { body(id, t, s, r);
//                                                     contacts.addResponses(id, s, r); }
//   stepStrands(strands, dt, threads);               // hooks read concurrently
#include "common/Status.h"
#include "contact/ContactResponse.h"
#include "contact/SegmentGeometry.h"

#include <Eigen/Core>

#include <cstdint>
#include <unordered_map>
#include <vector>

namespace hair
{

struct HairHairParameters
{
  /// Contact thickness of a guide, the radius of the clump it stands for [m]: two guides
  /// touch when their centrelines come closer than 2 × thickness.
  double thickness = 2.5e-3;
  /// Normal penalty k [N/m]: force k δ per contact point at penetration δ.
  double stiffness = 0.1;
  /// Normal damping c_n [N·s/m] on the normal relative velocity (only while pressed).
  double damping = 2e-4;
  /// Viscous tangential friction c_t [N·s/m] on the tangential relative velocity.
  double friction = 1e-5;
  /// Cap of a contact's normal force [N]: beyond it the penalty saturates (constant force,
  /// no stiffness). The Super-Helix step treats the load-dependent stiffness of a strand
  /// explicitly and chooses its sub-steps from gravity and root accelerations only, so
  /// contact loads far above the strand's weight make it blow up (measured: deep initial
  /// overlaps, dense clumps); 2e-5 N is the weight of 20 cm of a smooth hair, 20 × the
  /// largest contact force of a settled pair.
  double maxForce = 1e-4;
  /// Per-length penalty: each contact's force, stiffness, damping and energy scaled by
  /// ℓ_c / referenceLength, where ℓ_c is the length of strand in contact for that pair of
  /// pieces (the mean of each piece's length inside the other's contact cylinder, clipped
  /// to the other piece's extent), instead of one contact per pair of pieces (with shared
  /// vertices halved). Then a contact along two strands pushes per unit length whatever
  /// their sample spacing, which follows the curl (docs/hair-hair-contacts.md). Off by
  /// default: the defaults and the clump study were calibrated per contact point.
  bool perLength = false;
  /// ℓ_ref of perLength [m]: the length of contact that gets the per-point force.
  double referenceLength = 0.01;
  /// Temporal coherence: keep the candidate pairs found with this extra distance [m] and
  /// reuse them, without rebuilding the grid, while no sample has moved more than half of
  /// it since they were found. 0 disables it (grid rebuilt every update).
  double margin = 2.5e-3;
  /// The depth, as a fraction of 2 × thickness, a pair may reach within one step at its
  /// current closing speed: what HairHairContacts::updatesPerStep aims at.
  double allowedDepth = 0.3;
  /// Threads of the narrow phase in update() (blocks of 4096 candidate pairs; the result
  /// does not depend on it).
  int threads = 1;
  /// Grid cell size [m]; 0: automatic (longest piece + 2 × thickness + margin).
  double cellSize = 0;

  /// Names the first bad parameter, what is wrong and what to do.
  Status validate() const;
};

/// What the last update() did and found.
struct HairHairStats
{
  int strands = 0;
  long pieces = 0;
  long candidatePairs = 0;    ///< pairs of pieces whose boxes overlap (grid, or reused list)
  long contacts = 0;          ///< pairs closer than 2 × thickness
  bool rebuilt = false;       ///< the grid was rebuilt (false: coherence reused the pairs)
  double maxPenetration = 0;  ///< [m]
  double potentialEnergy = 0; ///< Σ ½ k δ² [J]
  double dissipationRate = 0; ///< Σ c_n v_n² + c_t |v_t|² over pressed contacts [W]
  /// Σ ½ k δ² of the contacts that were not contacts at the previous update: the energy a
  /// penalty detected at the start of a step can give back without having taken it (the
  /// pair went in during a step without force). It bounds the energy the contacts can add.
  double arrivalEnergy = 0; ///< [J]
  /// Largest closing speed / room of the candidate pairs [1/s]: room is the gap to the
  /// contact distance plus allowedDepth of it (for a pair in contact: what is left of that,
  /// at least 5 %).
  /// A step longer than 1 / closingRate lets some pair, at its current speed, go deeper.
  double closingRate = 0;
};

/// One contact between pieces of two strands at the last update() (for tests and studies).
struct HairHairContact
{
  int strandA = 0, strandB = 0; ///< indices in update()'s order, A < B
  double sA = 0, sB = 0;        ///< arc lengths of the closest points [m]
  Eigen::Vector3d pointA, pointB;
  double distance = 0;
  Eigen::Vector3d forceOnA; ///< [N]; B receives −forceOnA
};

class HairHairContacts
{
public:
  /// Validates and keeps the parameters; forgets the coherent pairs.
  Status setParameters(const HairHairParameters& parameters);
  const HairHairParameters& parameters() const { return Params; }

  /// Finds the contacts from every strand's current samples; strand i has id ids[i] (ids
  /// empty: id = i), the id that names it in addResponses. Ids must be distinct.
  Status update(const std::vector<std::vector<StrandSample>>& samples,
                const std::vector<int>& ids = {});

  /// Adds to `response` (one per sample) the hair–hair response of strand `strandId` at its
  /// current `samples`, the other strands held where update() found them. Thread-safe
  /// between updates. A strand unknown to the last update gets nothing.
  void addResponses(int strandId, const std::vector<StrandSample>& samples,
                    std::vector<ContactResponse>& response) const;
  /// Updates (and strand steps of dt / count) per step of dt that keep every candidate pair
  /// of the last update, at its current closing speed, within allowedDepth:
  /// ⌈dt · closingRate⌉, between 1 and maxUpdates. Pairs farther than the boxes' reach
  /// (2 × thickness + margin) are not seen.
  int updatesPerStep(double dt, int maxUpdates = 16) const;
  /// A hook calling addResponses (this object must outlive the strands' use of it).
  ContactForces hook() const;

  const HairHairStats& stats() const { return Stats; }
  const std::vector<HairHairContact>& contacts() const { return Contacts; }
  /// Candidate pairs of pieces (strand, piece) of the last update, sorted, for tests.
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
  // One side of a contact, as a strand sees it: its material point s, the relative position
  // and velocity (own − other's) at the update, its own point and velocity then, and the
  // contact's share (vertex halving).
  struct Side
  {
    double s;
    Eigen::Vector3d gap, relativeVelocity, ownPoint, ownVelocity;
    double share;
  };
  void buildPieces();
  void broadPhase();
  bool canReuse() const;
  void narrowPhase();

  HairHairParameters Params;
  std::vector<std::vector<StrandSample>> Samples;
  std::vector<int> Ids;
  std::unordered_map<int, int> IndexOfId;
  std::vector<Piece> Pieces;
  std::vector<int> PieceStart;                 // first piece of strand i; size strands + 1
  std::vector<std::pair<int, int>> Candidates; // piece indices
  // Coherence: the sample positions when the candidates were found, and the layout.
  std::vector<std::vector<Eigen::Vector3d>> BuildPositions;
  bool HaveBuild = false;
  double BuildInflation = 0;
  // Grid scratch.
  std::vector<std::uint32_t> CellKey, BucketStart;
  std::vector<int> BucketEntries;
  struct Entry
  {
    int piece, strand;
    int ix, iy, iz;
  };
  std::vector<Entry> Entries, Sorted;

  std::vector<std::vector<Side>> Sides;                                         // per strand
  std::vector<std::pair<std::int64_t, std::int64_t>> ContactKeys, PreviousKeys; // sorted
  std::vector<HairHairContact> Contacts;
  HairHairStats Stats;
};

} // namespace hair
