#pragma once
// A run, frame by frame, for any strand model: the one place where Hair Simulation meets
// the models. Guides, a scene and options in; frames of positions, velocities, generalized
// coordinates, energy terms and the penetration into the body out, kept by a FrameStore
// (memory, state file, read-back).
#include "common/Progress.h"
#include "common/Status.h"
#include "contact/HairHairOptions.h"
#include "io/StateFile.h"
#include "model/StrandModel.h"
#include "projective/ProjectiveStrands.h"
#include "scene/Scene.h"
#include "simulation/FrameStore.h"
#include "simulation/GhostStrands.h"
#include "simulation/GuideDrawing.h"
#include "simulation/ModelRegistry.h"
#include "strands/GuideStrand.h"
#include "superhelixmodel/SuperHelixModel.h"

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace hair
{

struct SimulationOptions
{
  ModelType model = ModelType::SuperHelix; ///< a registered model (simulation/ModelRegistry.h)
  double timeStep = 1.0 / 30;      ///< s; the projective model steps at most 1 ms (explicit)
  double frameInterval = 1.0 / 30; ///< s between stored frames
  int threads = 1;
  /// The MPI ranks the strands are shared among (Simulation: by their roots, balanced by
  /// each strand's step cost); one (the default): this process steps every strand.
  Ranks ranks;
  /// The body's contact law, the one a user gives for every model: the Super-Helix's penalty
  /// and friction (docs/superhelix-contacts.md); the projective model takes its friction from
  /// it (Coulomb's law with static friction only: on with μ, μ_s and the anisotropy when
  /// μ_s > 0, off otherwise; its normal response is its own reaction constraint).
  BodyContactParameters contacts;
  /// Hair–hair interaction, for every model that has it (docs/hair-hair-interaction.md): the
  /// grid's volume and friction by default, for the Super-Helix and the discrete elastic
  /// rods; the near field and the coupled pairs are the Super-Helix's. The projective
  /// model has none and runs without it.
  HairHairOptions hairHair;
  /// Read by the Super-Helix model only (not its contacts, not hair–hair).
  SuperHelixOptions superHelix;
  ProjectiveOptions projective; ///< read by the projective model only (not its step, threads)
  SagFreeOptions sagFree;       ///< for guides whose rest shape is sag-free, either model

  RunSettings run() const { return {timeStep, frameInterval, threads, {}, ranks}; }
};

/// Where a run's time went on this rank, summed over the frames computed by advanceTo
/// (seconds of wall time on the calling thread, and of the process's CPU time): stepping
/// its strands, waiting for every rank's step (agree: the other ranks' longer steps), the
/// frame's record (drawing the points, the penetration measure, the whole run's energy and
/// penetration summed over the ranks) and storing it (the state file, shared or not).
struct SimulationTimings
{
  int frames = 0;
  double stepWall = 0, stepCpu = 0;
  double waitWall = 0;
  double recordWall = 0, recordCpu = 0;
  double storeWall = 0, storeCpu = 0;
};

/// Which rank steps each of `guides` under `model` shared among `ranks` ranks: the roots'
/// Hilbert curve cut into ranges weighted by model.stepCost (common/Partition.h), so that
/// each rank's strands are a compact patch of the scalp, their steps cost the same, and,
/// for guides numbered along the curve as grown guides are, their numbers are consecutive.
std::vector<int> shareStrands(const std::vector<GuideStrand>& guides, const StrandModel& model,
                              int ranks);
/// Refuses a run whose model and first frame would need more than three quarters of
/// `availableBytes`, with the figures (the model's memory per element as measured,
/// StrandModel::bytesPerElement, the frame's points), before anything is allocated: Hair Strands
/// allows 10^5 strands of 100 elements, about 26 GB for the Super-Helix model alone.
/// Simulation::initialize calls it with this machine's memory.
Status checkRunMemory(const std::vector<GuideStrand>& strands, const SimulationOptions& options,
                      double availableBytes);

/// Steps the scene. Frame 0 is the initial state.
///
/// Under MPI (options.ranks of more than one rank) every call is collective, every rank is
/// given the same guides, scene and options, and each steps its share of the strands
/// (shareStrands): the frames a rank keeps and readFrame gives are its piece (piece() says
/// which strands), the energy terms, the penetration measure and the times are the whole
/// run's on every rank, and the state file is one, written by all. A failure on one rank
/// (a strand that blows up, a write) stops every rank with that rank's message.
class Simulation
{
public:
  Simulation();
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  /// Checks everything, builds the model and computes (and stores) frame 0. Refuses no
  /// strands, bad parameters, a scene that does not validate, a run that cannot be stored,
  /// NaN anywhere, and under MPI guides that differ between ranks, with a message naming the
  /// culprit. On error the simulation is left uninitialized.
  Status initialize(const std::vector<GuideStrand>& strands, const Scene& scene,
                    const SimulationOptions& options, const StorageOptions& storage = {});
  /// Computes frames until `frames` of them exist. `progress` (fraction of the requested
  /// frames) may abort (under MPI: an abort on any rank stops every rank at the same frame);
  /// frames computed before the abort are kept. A step (or a write) that fails stops with
  /// an error naming the strand and the time; the frames before it are kept, and every
  /// later call returns the same error (initialize again to restart).
  Status advanceTo(int frames, const Progress& progress = {});

  int numberOfFrames() const;
  /// Frame `index` as kept in memory: whole when hasFrameData(index), else only its time
  /// and energy (readFrame reads it back). Under MPI, this rank's piece.
  const StateFrame& frame(int index) const;
  bool hasFrameData(int index) const;
  /// Frame `index` whole, from memory or from the state file (under MPI this rank's piece;
  /// collective when the frame has left memory).
  Status readFrame(int index, StateFrame& out) const;
  /// Frame `index` drawn at `pointsPerElement` Super-Helix points per element (drawGuides:
  /// the projective model's nodes whatever it says), from memory or the state file (under
  /// MPI this rank's piece; collective when the frame has left memory).
  Status drawFrame(int index, int pointsPerElement, GuideDrawing& out) const;
  /// The header of this rank's strands (piece().strandIds: their numbers in the run); the
  /// whole run's header() without MPI.
  const StateHeader& piece() const;
  /// Under MPI, collective: frame `index` of the ghost strands of `levels` levels, the other
  /// ranks' strands whose roots lie within `levels` × 3 typical root spacings
  /// (typicalSpacing of every guide's root) of one of this rank's roots, and their header
  /// (header().piece of them). Three spacings keep the four guides nearest to any point
  /// of this rank's patch of scalp among its strands and ghosts. None without MPI or levels.
  Status ghostFrame(int index, int levels, StateHeader& header, StateFrame& frame) const;
  /// Memory one frame takes (bytes).
  double bytesPerFrame() const;
  /// Refuses a run of `frames` frames that would need more than `availableBytes`, with the
  /// figures and what to change (call after initialize()).
  Status checkMemory(int frames, double availableBytes) const;

  /// The header of this run's state file (the whole run's) and the energy terms beyond the
  /// required five.
  const StateHeader& header() const;
  const std::vector<std::string>& extraEnergyTerms() const;
  /// Per frame: nodes inside a body part (the scene's parts at the frame's time), and the
  /// deepest of them (m).
  const std::vector<long>& contacts() const;
  const std::vector<double>& maxDepth() const;
  /// One row per frame so far: the frames' times and, by column, every energy term, the
  /// penetration ("nodes_inside", "max_depth") and the model's step statistics since the
  /// previous frame (StrandModel::stepStatistics; the Super-Helix model: "substeps",
  /// "rejected_substeps", "first_order_share", "error_estimate"; zero in frame 0).
  void energyTable(std::vector<double>& times,
                   std::map<std::string, std::vector<double>>& columns) const;
  /// The model being run (for tests and studies that look inside it).
  const StrandModel& model() const;
  /// Per strand, what the model made of its groom and rest shape (StrandModel::groomed):
  /// the fit's error, the rest shape's outcome and, where it could not hold the shape, why.
  /// Empty for a model that reports none.
  const std::vector<GroomReport>& groomReports() const;
  /// Where this rank's time went in advanceTo (benchmarks, docs/benchmarks.md).
  const SimulationTimings& timings() const;

private:
  struct Impl;
  std::unique_ptr<Impl> P;
};

} // namespace hair
