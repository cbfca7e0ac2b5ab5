#pragma once
// Rendered hair from the guides: many strands rooted over the scalp, each following the
// guides near it. Two methods: the semi-interpolation of Bertails, Audoly, Cani et al. 2006
// (§4.1, Figure 4: interpolated between guides near the scalp, following one guide, a
// clump, near the tips, never across guides whose tips have parted), and the clusters of
// Kurihara, Anjyo and Thalmann 1993 (copies of one guide). Offsets are carried in the
// guides' material frames, so a curly guide gives curly rendered hair. docs/hair-interpolation.md.
#include "collision/PosedPart.h"
#include "common/Progress.h"
#include "common/Ranks.h"
#include "common/Status.h"
#include "geometry/TriangleMesh.h"
#include "strands/GuideStrand.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace hair
{

enum class InterpolationMethod
{
  SemiInterpolation = 0, ///< Bertails et al. 2006
  Clusters = 1           ///< Kurihara et al. 1993
};

struct InterpolationOptions
{
  InterpolationMethod method = InterpolationMethod::SemiInterpolation;
  int strands = 50000;      ///< rendered strands
  int pointsPerStrand = 32; ///< points of each, root and tip included
  /// Where clumping begins and where it is complete, as fractions of the strand from the
  /// root; negative: from the guides' hair type (clumpProfile()).
  double clumpStart = -1;
  double clumpEnd = -1;
  double clumpRadius = 0.01; ///< m: the largest distance of a rendered tip from its clump's guide
  /// m: a guide whose tip is farther than this from the clump guide's tip stops weighing
  /// in, fading out between 1× and 2× (no popping).
  double tipDistance = 0.04;
  /// Relative random shortening of rendered strands, in [0, 1): a strand is between
  /// (1 − variation) and 1 times the guides' length.
  double variation = 0.1;
  std::uint32_t seed = 1;
  /// Guides per rendered root for the semi-interpolation (the nearest ones).
  int neighbours = 3;
  int threads = 1;
  Status validate() const;
};

/// Where clumping begins and ends (fractions of the strand) for a hair type: straight hair
/// interpolates over most of its length, curly hair clumps early (Bertails et al. §4.1).
/// From the natural curvature κ of the type's helix, c = min(1, κ / 200 m⁻¹): start
/// 0.75 − 0.55 c, end start + 0.25.
std::pair<double, double> clumpProfile(const HairParameters& hair);

/// The guides at one instant, as the pipeline gives them: a polyline per guide (root
/// first), and per point the unit tangent and the first director of the material frame
/// (perpendicular to the tangent). Empty tangents are taken from the points; empty directors
/// are carried by parallel transport from the rest root frame turned by the roots' rigid
/// motion (rootMotion()).
struct GuideCurves
{
  std::vector<Eigen::Vector3d> points;
  std::vector<std::size_t> offsets; ///< guide k owns points offsets[k] … offsets[k+1]−1
  std::vector<Eigen::Vector3d> tangents;
  std::vector<Eigen::Vector3d> directors;
  /// Per-point scalars carried over to the rendered hair (speed, curvature, …).
  std::map<std::string, std::vector<double>> scalars;
  std::size_t size() const { return offsets.empty() ? 0 : offsets.size() - 1; }
};

/// The rendered hair of one instant: `strands` polylines of `pointsPerStrand` points each.
struct RenderedHair
{
  int pointsPerStrand = 0;
  std::vector<float> points;    ///< 3 per point
  std::vector<float> tangents;  ///< 3 per point, unit
  std::vector<float> parameter; ///< 0 at the root … 1 at the tip of its strand
  std::vector<int> guide;       ///< per strand: the guide it clumps to (or copies)
  std::map<std::string, std::vector<float>> scalars;
  long lookedUp = 0;       ///< points looked up in the tables (the others had room around them)
  long pushedOut = 0;      ///< points that were inside a body part and were pushed out
  double deepest = 0;      ///< m: the deepest of them before the push-out
  long stillInside = 0;    ///< points inside a part after the push-out
  double deepestAfter = 0; ///< m: the deepest of those
  std::size_t strandCount() const { return guide.size(); }
};

/// Where evaluate() writes one instant's rendered hair when the caller owns the arrays (the
/// filter's VTK arrays): strandCount() × pointsPerStrand points, strand after strand.
struct RenderedHairArrays
{
  float* points = nullptr;     ///< 3 per point; required
  float* tangents = nullptr;   ///< 3 per point, unit; may be null
  float* parameter = nullptr;  ///< 1 per point, 0 at the root … 1 at the tip; may be null
  int* guide = nullptr;        ///< 1 per strand: the guide it clumps to; may be null
  std::vector<float*> scalars; ///< 1 per point for each of the guides' scalars, in their order
};

/// What the push-out out of the body did in one evaluation (RenderedHair's fields).
struct PushOutCounts
{
  long lookedUp = 0;
  long pushedOut = 0;
  double deepest = 0;
  long stillInside = 0;
  double deepestAfter = 0;
};

class HairInterpolation
{
public:
  /// Roots the rendered strands on the scalp near the guides' rest roots (triangles
  /// within 1.5 times the guides' typical spacing of a root), seeded, and binds each to
  /// its guides: weights and offsets in their rest root frames. The guides are as grown
  /// (root, growth, normal and hair type: GuideStrand). Refuses no guides, a bad scalp, no
  /// scalp near the roots, bad options.
  Status bind(const std::vector<GuideStrand>& guides, const TriangleMesh& scalp,
              const InterpolationOptions& options);
  /// The same under MPI (collective over `ranks`): `guides` are this rank's piece of the
  /// guides and, where `ghost` is 1, copies of neighbouring ranks' guides (ghost strands).
  /// The rendered strands are rooted on the part of the scalp region whose nearest guide is
  /// one of this rank's own (triangle by triangle: every triangle of the region on exactly
  /// one rank), their number this part's share of options.strands by area, seeded apart per
  /// rank, and each is bound among all the guides given, so that near the piece's edge it
  /// follows the neighbouring pieces' guides as it would on one process. A rank may get no
  /// rendered strand (then isBound() is false); a refusal on one rank is every rank's.
  Status bind(const std::vector<GuideStrand>& guides, const TriangleMesh& scalp,
              const InterpolationOptions& options, const std::vector<std::uint8_t>& ghost,
              const Ranks& ranks);
  /// The same with the rendered roots given (points on or near the scalp, at rest).
  Status bind(const std::vector<GuideStrand>& guides, const std::vector<Eigen::Vector3d>& roots,
              const InterpolationOptions& options);
  bool isBound() const { return !Roots.empty(); }
  std::size_t strandCount() const { return Roots.size(); }

  /// The rendered hair for the guides at one instant, each point pushed out of the parts it
  /// is inside (one table look-up for a point near a part). `guides` must hold the bound
  /// guides, in order. `progress` may abort (then an error and `out` untouched).
  Status evaluate(const GuideCurves& guides, const std::vector<PosedPart>& parts, RenderedHair& out,
                  const Progress& progress = {}) const;

  /// The same, written into the caller's arrays (no copy), the push-out's counts added to
  /// `counts`. The per-point work is in single precision; points agree with a double
  /// evaluation to within 1e-5 m (docs/hair-interpolation.md).
  Status evaluate(const GuideCurves& guides, const std::vector<PosedPart>& parts,
                  const RenderedHairArrays& out, PushOutCounts& counts,
                  const Progress& progress = {}) const;

  /// The rigid motion that takes the guides' roots from rest to where `guides` has them
  /// (least squares over the roots and, where the guides carry them, points a centimetre
  /// along their root tangents and first directors; Kabsch's fit): the pose of the head
  /// that carries them, for the tables that move with it.
  Eigen::Isometry3d rootMotion(const GuideCurves& guides) const;

  /// Per rendered strand: its root at rest, its guides and weights (for tests).
  struct Binding
  {
    Eigen::Vector3d root;
    int guides[8];
    double weights[8];
    Eigen::Vector3d offsets[8]; ///< in each guide's rest root frame
    int count = 0;
    int clump = 0;               ///< index into guides[] of the clump guide (the nearest)
    Eigen::Vector3d clumpOffset; ///< at the tip, in the clump guide's frame, |·| ≤ clumpRadius
    double length = 1;           ///< fraction of the guides' length
  };
  const std::vector<Binding>& bindings() const { return Roots; }
  const InterpolationOptions& options() const { return Options; }

private:
  struct GuideRoots;
  /// One guide sample as the per-point work reads it: position (relative to an origin) and
  /// the frame's three columns, each as 4 floats (the last 0).
  struct GuideSample
  {
    Eigen::Array4f row[4];
  };
  /// Which rendered points need no look-up in the tables: per guide sample and body part,
  /// the part's window reach about the sample for two ball radii (squared, with a margin).
  struct PushOutSkip
  {
    static constexpr int Balls = 2;
    static constexpr double Radius[Balls] = {0.008, 0.025}; ///< m
    static constexpr double FloatMargin = 1e-5;             ///< m: far above a point's float error
    struct Part
    {
      Eigen::Array4f centre, axis; ///< posed, relative to the evaluation's origin
      bool cylindrical = true;
    };
    int parts = 0;
    std::vector<Part> shapes;
    std::vector<float> reach; ///< [sample][part][ball]
    /// Whether `point` (relative) is certainly outside every part, judged from sample k.
    bool outside(std::size_t k, const Eigen::Array4f& point,
                 const std::vector<GuideSample>& samples) const;
  };
  Status fill(const std::vector<GuideSample>& samples, const std::vector<float>& sampleScalars,
              const PushOutSkip& skip, const std::vector<Eigen::Vector3d>& tips,
              const Eigen::Vector3d& origin, const std::vector<PosedPart>& parts,
              const RenderedHairArrays& out, PushOutCounts& counts, const Progress& progress) const;
  static Status guideRoots(const std::vector<GuideStrand>& guides,
                           const InterpolationOptions& options, GuideRoots& out);
  Status bindRoots(const std::vector<GuideStrand>& guides, GuideRoots& set,
                   const std::vector<Eigen::Vector3d>& rendered,
                   const InterpolationOptions& options);

  InterpolationOptions Options;
  std::vector<Binding> Roots;
  std::vector<Eigen::Matrix3d> RestFrames;
  std::vector<Eigen::Vector3d> RestRoots;
  std::vector<double>
      Periods; ///< m: arc length of one turn of each guide's natural helix (0: straight)
  double ClumpStart = 0, ClumpEnd = 1;
};

} // namespace hair
