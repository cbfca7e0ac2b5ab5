#pragma once
// The seam between the frame loop (simulation/) and a model of hair strands. A model takes
// the guides and the scene, advances in its own steps, and describes its frames and its
// energy in the same terms as every other model; the frame loop, the state file, the
// penetration measure and the filters know nothing else of it. superhelix/ and projective/
// implement it; a third model is a third implementation with one entry in
// simulation/ModelRegistry.cxx (docs/architecture.md, "Adding a model").
#include "common/Ranks.h"
#include "common/Status.h"
#include "io/StateFile.h"
#include "model/EnergyBudget.h"
#include "model/GroomReport.h"
#include "model/StepStatistics.h"
#include "scene/Scene.h"
#include "strands/GuideStrand.h"

#include <map>
#include <string>
#include <vector>

namespace hair
{

/// What every model takes from the run.
struct RunSettings
{
  /// s: the model's step; an upper bound for a model whose scheme needs smaller ones.
  double timeStep = 1.0 / 30;
  double frameInterval = 1.0 / 30; ///< s between stored frames
  int threads = 1;
  /// The run's number of each guide given to initialize(), increasing; empty: 0, 1, … in
  /// order. Under MPI a model is given its rank's share of the run's guides: a strand's
  /// name, id and seeded variation follow its number in the run, not its place in the share,
  /// so that it is the same strand on any number of ranks.
  std::vector<int> strandIds;
  /// The ranks the run's strands are shared among (one: this process alone). A model whose
  /// strands interact (hair–hair contacts) exchanges what it needs of the others' strands.
  Ranks ranks;
  Status validate() const;
  int strandId(std::size_t k) const { return strandIds.empty() ? int(k) : strandIds[k]; }
};

class StrandModel
{
public:
  virtual ~StrandModel() = default;

  /// What the state file records as its "model" attribute ("super-helix", "projective").
  virtual const char* name() const = 0;
  /// Builds the strands from the guides (validated by the caller), at rest in their natural
  /// or styled shape at t = 0, in the scene, which the model keeps a copy of.
  virtual Status initialize(const std::vector<GuideStrand>& guides, const Scene& scene,
                            const RunSettings& run) = 0;
  /// Advances to time t (≥ time()) in the model's own steps. A failed step returns an error
  /// naming the strand and the time; the model must not be advanced after that.
  virtual Status advanceTo(double t) = 0;
  virtual double time() const = 0;

  /// The layout of its frames: model, offsets (points per strand), coordinatesPerStrand,
  /// and its own run attributes (added to those the frame loop writes).
  virtual void describe(StateHeader& header) const = 0;
  /// The current state into `frame`, as the state file keeps it: the positions and
  /// velocities of the model's nodes (describe()'s offsets: a Super-Helix's element ends, a
  /// projective strand's segment ends), q and q̇, and each strand's root pose and rates
  /// (appendRoot, model/StrandPoints.h: the orientation's columns the material frame at the
  /// root, tangent first), from which simulation/GuideDrawing.cxx draws the strand at any
  /// resolution (frame.time and the per-point scalars are the caller's). A frame given back
  /// from an earlier call is refilled in place.
  virtual void writeFrame(StateFrame& frame) const = 0;
  /// The energy budget now (works and dissipations since t = 0).
  virtual EnergyBudget energy() const = 0;
  /// What the model made of the guides it was initialized with: `guides` (a copy of them)
  /// as built — a groomed guide's length and root tangent are those of the model's fit to
  /// its curve — and a report per strand (the fit's error, the rest shape's outcome). The
  /// default leaves the guides as given and reports nothing.
  virtual void groomed(std::vector<GuideStrand>& guides, std::vector<GroomReport>& reports) const
  {
    (void)guides;
    reports.clear();
  }
  /// The rest shape of every strand, describe()'s coordinatesPerStrand values each (the state
  /// file's /groom/rest_coordinates); empty when the model has none to give.
  virtual void restCoordinates(std::vector<double>& values) const { values.clear(); }

  /// The cost of a step of `guide` relative to the other guides of a run (any unit): what the
  /// strands are shared among MPI ranks by (common/Partition.h). Called before initialize().
  virtual double stepCost(const GuideStrand& guide) const = 0;
  /// How the model stepped since the previous frame, as named numbers for the energy table
  /// (the Super-Helix model: sub-steps and their error estimate, simulation/Simulation.h);
  /// empty for a model that reports none.
  virtual std::map<std::string, double> stepStatistics() const { return {}; }
  /// How each of stepStatistics' numbers becomes the whole run's under MPI (one rule per
  /// name, the same on every rank; a number without a rule is a mean over the strands).
  virtual std::vector<StepStatisticRule> stepStatisticRules() const { return {}; }
  /// The memory the model takes per element of a guide (bytes, as measured), which a run is
  /// checked against before anything is allocated (checkRunMemory). Called before
  /// initialize().
  virtual double bytesPerElement() const = 0;

  /// Why this run cannot be continued from a saved continuation (it keeps state the
  /// continuation does not hold), or empty when it can. After initialize().
  virtual std::string continuationRefusal() const = 0;
  /// The most numbers saveContinuation gives strand k over the whole run (the room the
  /// state file keeps for it). After initialize().
  virtual std::size_t continuationCapacity(std::size_t k) const = 0;
  /// What its steps from now on (at a frame, after advanceTo) depend on beyond the guides,
  /// scene and settings it was initialized with, as numbers (StateContinuation: per strand,
  /// and the model's own, its clock and step controller, the same on every rank; `out` is
  /// refilled, its frame left as it is). Restored into a model initialized as this one was,
  /// the run goes on as if it had never stopped, bit for bit (Simulation's resume).
  virtual void saveContinuation(StateContinuation& out) const = 0;
  /// Puts back what saveContinuation gave, into a model initialized with the same guides,
  /// scene and settings; refuses numbers that do not fit its strands.
  virtual Status restoreContinuation(const StateContinuation& in) = 0;
};

} // namespace hair
