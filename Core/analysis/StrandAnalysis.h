#pragma once
// Measurements of strands over time, one set per frame: tip positions, the span of a group
// of tips, extreme curvature and twist, the tips' lateral deflection and displacement, and
// contacts. Plain arrays in, numbers out; the definitions (and units) are documented in
// docs/hair-analysis.md, which scripts and the Hair Analysis filter's columns rely on.
#include "common/Ranks.h"
#include "common/Status.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace hair
{

/// One frame of strands: strand k owns points offsets[k] … offsets[k+1]−1, its root first
/// and its tip last (the layout of the state file, docs/state-file.md).
struct StrandsFrame
{
  std::vector<std::int64_t> offsets;
  std::vector<Eigen::Vector3d> positions; ///< m, one per point
  std::vector<double> curvature;          ///< 1/m, one per point
  std::vector<double> twist;              ///< 1/m, one per point (signed)
  std::vector<double> contactDepth;       ///< m inside a body part, 0 outside; one per point
  /// Each strand's number (the pipeline's StrandId), by which options name strands; empty:
  /// 0 … S − 1. Under MPI a frame is one rank's piece, and its strands' numbers are the run's.
  std::vector<std::int64_t> ids;

  std::size_t numberOfStrands() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  std::int64_t id(std::size_t k) const { return ids.empty() ? std::int64_t(k) : ids[k]; }
  /// Refuses offsets that do not start at 0, decrease, leave a strand with fewer than two
  /// points or disagree with the arrays' lengths, and non-finite values; `empty` allows a
  /// frame without strands (a rank's piece under MPI).
  Status validate(bool empty = false) const;
};

struct StrandAnalysisOptions
{
  /// Up (against gravity). The span and the lateral deflection are measured in the plane
  /// perpendicular to it. Need not be unit; must not be zero.
  Eigen::Vector3d vertical{0, 1, 0};
  /// Strands whose tips are reported one by one (by number: StrandsFrame::ids, or their
  /// indices when the frame has none).
  std::vector<std::int64_t> tracked;
  /// Strands whose span is measured (by number); empty: every strand.
  std::vector<std::int64_t> group;
};

/// Everything measured on one frame.
struct StrandMeasures
{
  Eigen::Vector3d meanTip = Eigen::Vector3d::Zero(); ///< mean of every strand's tip, m
  std::vector<Eigen::Vector3d> trackedTips;          ///< the tips of options.tracked, in order
  double span = 0;                ///< diameter of the group's tips seen from above, m
  double maxCurvature = 0;        ///< max |κ| over every point, 1/m
  double maxTwist = 0;            ///< max |τ| over every point, 1/m
  double maxDeflection = 0;       ///< max over strands of the tip's distance from the
                                  ///< vertical through its root, m
  double meanDeflection = 0;      ///< mean of the same, m
  double maxTipDisplacement = 0;  ///< max over strands of |tip − tip at the first frame|, m
  double meanTipDisplacement = 0; ///< mean of the same, m
  std::int64_t contacts = 0;      ///< points with contact depth > 0
  double maxContactDepth = 0;     ///< the deepest of them, m (0 without contacts)
};

/// The diameter of `points` projected on the plane perpendicular to `vertical`: the largest
/// distance between two projections (0 for fewer than two points). Exact up to rounding,
/// in O(n log n): the two farthest points are vertices of the projections' convex hull.
double horizontalDiameter(const std::vector<Eigen::Vector3d>& points,
                          const Eigen::Vector3d& vertical);

/// The distance of `tip` from the line through `root` along `vertical`.
double lateralDeflection(const Eigen::Vector3d& root, const Eigen::Vector3d& tip,
                         const Eigen::Vector3d& vertical);

/// Measures frames one after the other; the first frame given after configure() is the
/// reference of the tip displacements.
class StrandAnalysis
{
public:
  /// Checks the options (a non-zero vertical, no negative index) and forgets any reference.
  Status configure(const StrandAnalysisOptions& options);
  /// Measures `frame`. Refuses an invalid frame, tracked or group strands it does not have,
  /// and a frame whose number of strands differs from the reference frame's.
  ///
  /// Under MPI (`ranks` of more than one rank; collective), `frame` is this rank's piece of
  /// the strands (possibly none) and `out` the whole frame's measures on every rank: sums,
  /// counts and maxima reduced over the ranks, a tracked tip from the rank that has it, and
  /// the span from every piece's hull vertices (a farthest pair of the whole group is a pair
  /// of its hull's vertices, each a vertex of its own piece's hull). A refusal on one rank
  /// is every rank's.
  Status measure(const StrandsFrame& frame, StrandMeasures& out, const Ranks& ranks = Ranks());
  /// Forgets the reference frame: the next frame measured becomes it.
  void restart() { ReferenceTips.clear(); }

private:
  StrandAnalysisOptions Options;
  std::vector<Eigen::Vector3d> ReferenceTips;
};

} // namespace hair
