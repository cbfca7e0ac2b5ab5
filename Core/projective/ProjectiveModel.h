#pragma once
// The projective model of Kurihara, Anjyo and Thalmann (1993) behind the StrandModel seam:
// each guide a chain of rigid segments grown straight along its growth direction, stepped
// explicitly in whole steps of at most 1 ms per frame.
#include "model/GroomReport.h"
#include "model/GuideDrawing.h"
#include "model/StrandModel.h"
#include "projective/ProjectiveStrands.h"

namespace hair
{

class ProjectiveModel final : public StrandModel
{
public:
  /// `options.timeStep` and `options.threads` are taken from the run at initialize().
  explicit ProjectiveModel(const ProjectiveOptions& options = {},
                           const SagFreeOptions& sagFree = {});

  const char* name() const override { return "projective"; }
  Status initialize(const std::vector<GuideStrand>& guides, const Scene& scene,
                    const RunSettings& run) override;
  Status advanceTo(double t) override;
  double time() const override { return Strands.time(); }
  void describe(StateHeader& header) const override;
  void writeFrame(StateFrame& frame) const override;
  EnergyBudget energy() const override;
  void groomed(std::vector<GuideStrand>& guides, std::vector<GroomReport>& reports) const override;
  void restCoordinates(std::vector<double>& values) const override;
  std::string continuationRefusal() const override { return {}; }
  std::size_t continuationCapacity(std::size_t k) const override;
  void saveContinuation(StateContinuation& out) const override;
  Status restoreContinuation(const StateContinuation& in) override;
  /// Its segments: every segment of every strand costs the same explicit update.
  double stepCost(const GuideStrand& guide) const override { return guide.elements; }
  /// Measured with hair_study scene (200 and 400 wavy strands of 10, 50 and 100 segments,
  /// two frames, maximum resident memory): about 0.7 kB per segment.
  double bytesPerElement() const override { return 700; }

  /// The explicit scheme's step: at most 1 ms, in whole steps per frame so that frames fall
  /// on their times.
  static double stepFor(const RunSettings& run);
  /// The material of a guide's hair type: ρS, the mean bending stiffness of the section and
  /// its diameter for the drag.
  static ProjectiveParameters material(const HairParameters& hair);
  const ProjectiveStrands& strands() const { return Strands; }

private:
  ProjectiveOptions Options;
  SagFreeOptions SagFree;
  ProjectiveStrands Strands;
  std::vector<GuideStrand> Built;   ///< the guides as built (groomed: the chain's length, tangent)
  std::vector<GroomReport> Reports; ///< per strand: the chain's fit and the rest shape
};

/// The model's drawer (simulation/ModelRegistry.cxx, model/GuideDrawing.h): the strands at
/// their nodes whatever the points per element, each segment's frame from the root's and the
/// angles, the turning angle over the segment length as curvature, no twist.
Status drawProjectiveFrame(const StateHeader& header, const StateFrame& frame, int pointsPerElement,
                           int threads, GuideDrawing& out);

} // namespace hair
