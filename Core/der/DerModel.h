#pragma once
// Discrete Elastic Rods (Bergou et al. 2008, 2010; der/DerRod.h) behind the StrandModel seam:
// each guide a rod of `elements` edges clamped at its root, stepped by backward Euler in
// whole steps of at most the run's time step per frame, against the body's parts through
// the run's contact law (contact/BodyContacts.h), and with each other through the far field's
// grid (contact/HairGrid.h). docs/discrete-elastic-rods.md.
#include "contact/BodyContacts.h"
#include "contact/HairGrid.h"
#include "contact/HairHairOptions.h"
#include "der/DerRod.h"
#include "model/GroomReport.h"
#include "model/GuideDrawing.h"
#include "model/StrandModel.h"

#include <vector>

namespace hair
{

class DerModel final : public StrandModel
{
public:
  /// `contacts`: the run's body contact law (SimulationOptions::contacts); its lookAhead is
  /// set to the step. `hairHair`: the run's hair–hair interaction
  /// (SimulationOptions::hairHair), the grid or none (initialize refuses the Super-Helix's
  /// pair solvers by name).
  explicit DerModel(const BodyContactParameters& contacts = {},
                    const HairHairOptions& hairHair = {}, const DerSolverOptions& solver = {});

  const char* name() const override { return "discrete-elastic-rods"; }
  /// Refuses a guide of fewer than 2 elements and a sag-free rest shape (not available for
  /// this model yet), naming the strand; and a hair–hair solver other than the grid.
  Status initialize(const std::vector<GuideStrand>& guides, const Scene& scene,
                    const RunSettings& run) override;
  Status advanceTo(double t) override;
  double time() const override { return Time; }
  /// Points per strand: the root, then nodes 1 … N; q per strand: (x_0, φ_0, x_1, φ_1, …,
  /// x_N), the nodes (x_0 half an edge behind the root) and each edge's material angle from
  /// the frame parallel-transported along the strand from the root's (φ_j − φ_{j−1} is the
  /// twist at node j); q̇: the nodes' velocities and each edge's twist rate θ̇_j.
  void describe(StateHeader& header) const override;
  void writeFrame(StateFrame& frame) const override;
  EnergyBudget energy() const override;
  void groomed(std::vector<GuideStrand>& guides, std::vector<GroomReport>& reports) const override;
  /// Its edges: every edge costs the same stencil and the same band of the Newton matrix.
  double stepCost(const GuideStrand& guide) const override { return guide.elements; }
  std::map<std::string, double> stepStatistics() const override;
  std::vector<StepStatisticRule> stepStatisticRules() const override;
  double bytesPerElement() const override;
  std::string continuationRefusal() const override { return {}; }
  std::size_t continuationCapacity(std::size_t k) const override;
  void saveContinuation(StateContinuation& out) const override;
  Status restoreContinuation(const StateContinuation& in) override;

  /// The step a run of `run` takes: at most its time step, in whole steps per frame so that
  /// frames fall on their times.
  static double stepFor(const RunSettings& run);
  /// The rod a guide becomes in `scene`: N = elements edges of length L/(N − ½), the first
  /// clamped along the root tangent with the root at its middle, so that the strand from the
  /// root to its tip is L long and the clamp is the root's (docs/discrete-elastic-rods.md,
  /// "Where the clamp acts"); a groom's curve inscribed through its nodes. `fitError` gets
  /// the largest distance of the curve's points from the rod's polyline (0 without a curve).
  /// (Without a curve the rod is straight here; initialize() starts it in its natural
  /// shape, DerRod::naturalShape.)
  static Status specFor(const GuideStrand& guide, const Scene& scene, DerSpec& spec,
                        double& fitError);
  const std::vector<DerRod>& rods() const { return Rods; }
  /// The far field of the last step (when SimulationOptions::hairHair uses the grid).
  const HairGrid& hairGrid() const { return Grid; }

  /// The edges a guide of `hair` and `length` gets when a tool is asked for no number: at
  /// least 20, and enough for its curl to turn a node by at most 70° (κ̄ l̄ <= RobustTurn),
  /// with a margin on the 90° that DerSpec::validate accepts: on the head under the soak's
  /// shake a fuzzy strand at 86° a node failed within 1 s and held 10 s at 70°
  /// (docs/discrete-elastic-rods.md, "What is missing").
  static int edgesFor(const HairParameters& hair, double length);
  static constexpr double RobustTurn = 1.4; ///< 2 tan(35°): 70° a node
  /// How many times a step that does not converge is halved before the run stops.
  static constexpr int MaxHalvings = 6;

private:
  /// Rod k from guide g (initialize, on the run's threads): its spec, the rod in its
  /// natural shape (grown) or on its groom's curve.
  Status buildRod(std::int64_t k, const GuideStrand& g);
  static Status stepRod(DerRod& rod, double h, int depth, double& iterations);
  void respond(std::size_t k, double t, const std::vector<StrandSample>& samples,
               std::vector<ContactResponse>& response) const;

  /// The far field's grid for a step of h from every rod's root and nodes 1 … N now,
  /// summed over the ranks (collective).
  void buildGrid(double h);

  BodyContactParameters ContactLaw;
  HairHairOptions HairHair;
  DerSolverOptions Solver;
  BodyContacts Body;
  HairGrid Grid;
  /// Per rod: the cross-section of the fibres it stands for (the grid's volume) [m²], and
  /// the polyline and velocities buildGrid splats.
  std::vector<double> ClumpArea;
  std::vector<std::vector<Eigen::Vector3d>> GridPoints, GridVelocities;
  Scene World;
  RunSettings Run;
  double Step = 1.0 / 30;
  double Time = 0;
  long Steps = 0;
  std::vector<DerRod> Rods;
  /// Per strand, its static-friction anchors (BodyContacts::respond), read and written by
  /// the strand's step only.
  mutable std::vector<std::vector<BodyAnchor>> Anchors;
  std::vector<GuideStrand> Built;
  std::vector<GroomReport> Reports;
  /// Newton iterations and strand steps since the last frame (stepStatistics).
  double FrameIterations = 0, FrameSteps = 0;
};

/// The model's drawer (simulation/ModelRegistry.cxx, model/GuideDrawing.h): the strands at
/// their stored points whatever the points per element, each point with the material frame of
/// the edge it starts (rebuilt from the root's frame, the nodes and the material angles φ),
/// the turning angle and the twist φ_j − φ_{j−1} over the Voronoi length at the inner nodes.
Status drawDerFrame(const StateHeader& header, const StateFrame& frame, int pointsPerElement,
                    int threads, GuideDrawing& out);

} // namespace hair
