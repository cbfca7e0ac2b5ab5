#include "render/HairInterpolation.h"

#include "common/Parallel.h"
#include "geometry/UniformGrid.h"
#include "strands/RootSampling.h"

#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>

namespace hair
{

namespace
{

double smoothstep(double x)
{
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3 - 2 * x);
}

float smoothstepf(float x)
{
  x = std::clamp(x, 0.0f, 1.0f);
  return x * x * (3 - 2 * x);
}

/// The `k` guides nearest to x (fewer when there are fewer), nearest first (ties by index),
/// with their distances.
void nearestGuides(const UniformGrid& grid, const std::vector<Eigen::Vector3d>& roots,
                   const Eigen::Vector3d& x, int k, std::vector<int>& scratch,
                   std::vector<std::pair<double, int>>& out)
{
  grid.nearest(x, k, scratch);
  out.resize(scratch.size());
  for (std::size_t i = 0; i < scratch.size(); ++i)
    out[i] = {(roots[scratch[i]] - x).norm(), scratch[i]};
}

/// One guide resampled at evenly spaced fractions of its length.
struct Resampled
{
  std::vector<Eigen::Vector3d> position;
  std::vector<Eigen::Matrix3d> frame; ///< columns: tangent, director 1, director 2
  std::vector<double> scalars;        ///< samples × scalar count
};

/// The guides' typical spacing: the median distance of a root to its nearest other root.
double guideSpacing(const std::vector<Eigen::Vector3d>& roots)
{
  double spacing = 0.02;
  if (roots.size() > 1)
  {
    double extent = 0;
    for (const Eigen::Vector3d& r : roots)
      extent = std::max(extent, (r - roots.front()).norm());
    UniformGrid coarse;
    coarse.build(roots, std::max(extent / std::cbrt(double(roots.size())), 1e-6));
    std::vector<double> nearestOther(roots.size());
    std::vector<std::pair<double, int>> found;
    std::vector<int> scratch;
    for (std::size_t k = 0; k < roots.size(); ++k)
    {
      nearestGuides(coarse, roots, roots[k], 2, scratch, found);
      nearestOther[k] = found.size() > 1 ? found[1].first : extent;
    }
    std::nth_element(nearestOther.begin(), nearestOther.begin() + nearestOther.size() / 2,
                     nearestOther.end());
    spacing = std::max(nearestOther[nearestOther.size() / 2], 1e-6);
  }
  return spacing;
}

} // namespace

Status InterpolationOptions::validate() const
{
  auto bad = [](const std::string& what, double value, const std::string& want)
  {
    std::ostringstream shown;
    shown << value;
    return Status::Error(what + " is " + shown.str() + "; give " + want + ".");
  };
  if (strands < 1 || strands > 10000000)
    return bad("the number of rendered strands", strands, "1 … 10 000 000");
  if (pointsPerStrand < 2 || pointsPerStrand > 1000)
    return bad("the points per strand", pointsPerStrand, "2 … 1000");
  if (std::isnan(clumpStart) || std::isnan(clumpEnd) || clumpStart > 1 || clumpEnd > 1)
    return bad("the clumping profile (start)", clumpStart,
               "fractions of the strand in [0, 1] with start ≤ end, or negative for the hair "
               "type's");
  if (clumpStart >= 0 && clumpEnd >= 0 && clumpEnd < clumpStart)
    return bad("the clumping profile's end", clumpEnd, "an end at or after its start");
  if ((clumpStart >= 0) != (clumpEnd >= 0))
    return bad("the clumping profile's start", clumpStart,
               "both start and end (or both negative, for the hair type's)");
  if (!(std::isfinite(clumpRadius) && clumpRadius >= 0 && clumpRadius <= 1))
    return bad("the clump radius", clumpRadius, "a length in metres in [0, 1]");
  if (!(std::isfinite(tipDistance) && tipDistance > 0))
    return bad("the tip-distance threshold", tipDistance, "a positive length in metres");
  if (!(variation >= 0 && variation < 1))
    return bad("the random variation", variation, "a fraction in [0, 1)");
  if (neighbours < 1 || neighbours > 7)
    return bad("the guides per rendered root", neighbours, "1 … 7");
  if (threads < 1)
    return bad("the number of threads", threads, "at least 1");
  return Status::Ok();
}

std::pair<double, double> clumpProfile(const HairParameters& hair)
{
  const Eigen::Vector3d natural = hair.naturalCurvature();
  const double kappa = std::hypot(natural.y(), natural.z());
  const double c = std::min(1.0, kappa / 200.0);
  const double start = 0.75 - 0.55 * c;
  return {start, std::min(1.0, start + 0.25)};
}

/// The guides' rest roots and root frames, their typical spacing and a grid of the roots:
/// what both ways of binding start from, checked and built once.
struct HairInterpolation::GuideRoots
{
  std::vector<Eigen::Vector3d> roots;
  std::vector<Eigen::Matrix3d> frames;
  double spacing = 0;
  UniformGrid grid;
};

Status HairInterpolation::guideRoots(const std::vector<GuideStrand>& guides,
                                     const InterpolationOptions& options, GuideRoots& out)
{
  if (Status s = options.validate(); !s)
    return s;
  if (guides.empty())
    return Status::Error("there are no guides to interpolate.");
  out.roots.resize(guides.size());
  out.frames.resize(guides.size());
  for (std::size_t k = 0; k < guides.size(); ++k)
  {
    if (Status s = guides[k].validate("guide " + std::to_string(k)); !s)
      return s;
    out.roots[k] = guides[k].root;
    out.frames[k] = guides[k].rootFrame();
  }
  out.spacing = guideSpacing(out.roots);
  out.grid.build(out.roots, out.spacing);
  return Status::Ok();
}

Status HairInterpolation::bind(const std::vector<GuideStrand>& guides, const TriangleMesh& scalp,
                               const InterpolationOptions& options)
{
  return bind(guides, scalp, options, {}, Ranks());
}

Status HairInterpolation::bind(const std::vector<GuideStrand>& guides, const TriangleMesh& scalp,
                               const InterpolationOptions& options,
                               const std::vector<std::uint8_t>& ghost, const Ranks& ranks)
{
  Roots.clear();
  const bool shared = ranks.parallel();
  GuideRoots set;
  // A rank's piece may have no guide at all (more ranks than guides): then no rendered hair.
  Status s = shared && guides.empty() ? Status::Ok() : guideRoots(guides, options, set);
  s = s ? scalp.validate("the scalp surface") : s;
  if (s && !ghost.empty() && ghost.size() != guides.size())
  {
    s = Status::Error("the ghost flags are not one per guide.");
  }

  // The scalp near the roots: triangles whose centroid is within 1.5 spacings of a root
  // (under MPI: whose nearest root is one of this rank's own guides).
  std::vector<std::uint8_t> region(scalp.triangles.size(), 0);
  double area = 0;
  if (s && !guides.empty())
  {
    std::vector<std::pair<double, int>> found;
    std::vector<int> scratch;
    for (std::size_t t = 0; t < scalp.triangles.size(); ++t)
    {
      const auto& tri = scalp.triangles[t];
      const Eigen::Vector3d a = scalp.points[tri[0]], b = scalp.points[tri[1]],
                            c = scalp.points[tri[2]];
      nearestGuides(set.grid, set.roots, (a + b + c) / 3, 1, scratch, found);
      region[t] = found[0].first <= 1.5 * set.spacing &&
                  (ghost.empty() || !ghost[std::size_t(found[0].second)]);
      area += region[t] ? 0.5 * (b - a).cross(c - a).norm() : 0.0;
    }
  }
  // This rank's share of the rendered strands: by its part's area, the counts of the ranks
  // before it rounded on the running total so that they add up to options.strands.
  std::size_t count = std::size_t(options.strands);
  if (shared)
  {
    if (s = ranks.agree(s); !s)
    {
      return s;
    }
    const std::vector<double> areas = ranks.gather(std::vector<double>{area});
    double before = 0, total = 0;
    for (int r = 0; r < ranks.size(); ++r)
    {
      before += r < ranks.rank() ? areas[r] : 0;
      total += areas[r];
    }
    if (total > 0)
    {
      const double S = double(options.strands);
      count =
          std::size_t(std::llround(S * (before + area) / total) - std::llround(S * before / total));
    }
    area = total;
  }
  if (s && !(area > 0))
  {
    s = Status::Error("no part of the scalp surface lies near the guides' roots (within 1.5 × "
                      "their spacing of " +
                      std::to_string(set.spacing) + " m): give the surface the guides grew on.");
  }
  if (s && count > 0)
  {
    std::vector<Root> samples;
    const std::uint32_t seed = options.seed + 0x9E3779B9u * std::uint32_t(ranks.rank());
    s = sampleUniformly(scalp, region, count, seed, samples);
    std::vector<Eigen::Vector3d> positions(samples.size());
    for (std::size_t r = 0; r < samples.size(); ++r)
      positions[r] = samples[r].position;
    s = s ? bindRoots(guides, set, positions, options) : s;
  }
  return shared ? ranks.agree(s) : s;
}

Status HairInterpolation::bind(const std::vector<GuideStrand>& guides,
                               const std::vector<Eigen::Vector3d>& rendered,
                               const InterpolationOptions& options)
{
  Roots.clear();
  GuideRoots set;
  if (Status s = guideRoots(guides, options, set); !s)
    return s;
  return bindRoots(guides, set, rendered, options);
}

Status HairInterpolation::bindRoots(const std::vector<GuideStrand>& guides, GuideRoots& set,
                                    const std::vector<Eigen::Vector3d>& rendered,
                                    const InterpolationOptions& options)
{
  if (rendered.empty())
    return Status::Error("there are no rendered roots.");
  for (const Eigen::Vector3d& x : rendered)
    if (!x.allFinite())
      return Status::Error("a rendered root is not finite.");
  const std::vector<Eigen::Vector3d>& roots = set.roots;
  const std::vector<Eigen::Matrix3d>& frames = set.frames;
  const double spacing = set.spacing;
  const UniformGrid& grid = set.grid;
  std::vector<std::pair<double, int>> found;
  std::vector<int> scratch;
  std::vector<Binding> bound(rendered.size());
  std::mt19937_64 rng(options.seed ^ 0x9e3779b97f4a7c15ull);
  std::uniform_real_distribution<double> U(0, 1);
  const int k = options.method == InterpolationMethod::Clusters ? 1 : options.neighbours;
  for (std::size_t r = 0; r < rendered.size(); ++r)
  {
    Binding& b = bound[r];
    b.root = rendered[r];
    b.length = 1 - options.variation * U(rng);
    nearestGuides(grid, roots, b.root, k + 1, scratch, found);
    b.count = std::min<int>(k, static_cast<int>(found.size()));
    // Modified Shepard weights (Franke and Nielson 1980): ((R − d)₊ / (R d))², R the
    // distance to the next guide beyond those used, so that a weight reaches 0 before its
    // guide leaves the set: the rendered hair is continuous over the scalp.
    const double R = static_cast<int>(found.size()) > b.count ? found[b.count].first : 0;
    double sum = 0;
    int exact = -1;
    for (int i = 0; i < b.count; ++i)
    {
      const double d = found[i].first;
      b.guides[i] = found[i].second;
      if (d < 1e-12 * spacing)
        exact = i;
      const double w = R > 0 ? std::pow(std::max(R - d, 0.0) / (R * d), 2) : 1 / (d * d);
      b.weights[i] = w;
      sum += w;
      b.offsets[i] = frames[b.guides[i]].transpose() * (b.root - roots[b.guides[i]]);
    }
    if (exact >= 0 || !(sum > 0) || !std::isfinite(sum))
    {
      for (int i = 0; i < b.count; ++i)
        b.weights[i] = 0;
      b.weights[exact >= 0 ? exact : 0] = 1;
    }
    else
    {
      for (int i = 0; i < b.count; ++i)
        b.weights[i] /= sum;
    }
    b.clump = 0; // the nearest
  }
  // Clump offsets: the lateral offset from the clump guide, scaled so that the guide's
  // cluster fits within the clump radius at the tips (a disc stays a disc).
  std::vector<double> clusterRadius(guides.size(), 0);
  for (const Binding& b : bound)
  {
    const Eigen::Vector3d& o = b.offsets[b.clump];
    clusterRadius[b.guides[b.clump]] =
        std::max(clusterRadius[b.guides[b.clump]], std::hypot(o.y(), o.z()));
  }
  for (Binding& b : bound)
  {
    const Eigen::Vector3d& o = b.offsets[b.clump];
    const double radius = clusterRadius[b.guides[b.clump]];
    const double scale = radius > options.clumpRadius ? options.clumpRadius / radius : 1.0;
    b.clumpOffset = Eigen::Vector3d(0, o.y() * scale, o.z() * scale);
  }

  Periods.assign(guides.size(), 0);
  for (std::size_t g = 0; g < guides.size(); ++g)
  {
    const HairParameters& h = guides[g].hair;
    if (h.helixRadius > 0)
      Periods[g] = std::hypot(2 * M_PI * h.helixRadius, h.helixStep);
  }
  Options = options;
  RestRoots = std::move(set.roots);
  RestFrames = std::move(set.frames);
  if (options.clumpStart >= 0)
  {
    ClumpStart = options.clumpStart;
    ClumpEnd = options.clumpEnd;
  }
  else
  {
    // The first guide's hair type decides (Hair Strands gives all its guides one type).
    std::tie(ClumpStart, ClumpEnd) = clumpProfile(guides.front().hair);
  }
  Roots = std::move(bound);
  return Status::Ok();
}

Status HairInterpolation::evaluate(const GuideCurves& guides, const std::vector<PosedPart>& parts,
                                   RenderedHair& out, const Progress& progress) const
{
  if (!isBound())
    return Status::Error("bind the rendered strands to guides first.");
  const std::size_t strands = Roots.size(), n = std::size_t(Options.pointsPerStrand);
  RenderedHair hair;
  hair.pointsPerStrand = Options.pointsPerStrand;
  hair.points.resize(strands * n * 3);
  hair.tangents.resize(strands * n * 3);
  hair.parameter.resize(strands * n);
  hair.guide.resize(strands);
  RenderedHairArrays arrays;
  arrays.points = hair.points.data();
  arrays.tangents = hair.tangents.data();
  arrays.parameter = hair.parameter.data();
  arrays.guide = hair.guide.data();
  for (const auto& entry : guides.scalars)
  {
    std::vector<float>& values = hair.scalars[entry.first];
    values.resize(strands * n);
    arrays.scalars.push_back(values.data());
  }
  PushOutCounts counts;
  if (Status s = evaluate(guides, parts, arrays, counts, progress); !s)
    return s;
  hair.pushedOut = counts.pushedOut;
  hair.deepest = counts.deepest;
  hair.stillInside = counts.stillInside;
  hair.deepestAfter = counts.deepestAfter;
  hair.lookedUp = counts.lookedUp;
  out = std::move(hair);
  return Status::Ok();
}

Status HairInterpolation::evaluate(const GuideCurves& guides, const std::vector<PosedPart>& parts,
                                   const RenderedHairArrays& out, PushOutCounts& counts,
                                   const Progress& progress) const
{
  if (!isBound())
    return Status::Error("bind the rendered strands to guides first.");
  if (out.points == nullptr || out.scalars.size() != guides.scalars.size())
    return Status::Error("the rendered hair's arrays are not given (points, and one per guide "
                         "scalar).");
  const std::size_t G = guides.size();
  if (G != RestRoots.size())
    return Status::Error("the rendered hair was bound to " + std::to_string(RestRoots.size()) +
                         " guides, and " + std::to_string(G) +
                         " are given: bind again to these guides.");
  if (guides.offsets.front() != 0 || guides.offsets.back() != guides.points.size())
    return Status::Error("the guides' offsets do not cover their points.");
  for (std::size_t g = 0; g < G; ++g)
    if (guides.offsets[g + 1] < guides.offsets[g] + 2)
      return Status::Error("guide " + std::to_string(g) + " has fewer than 2 points.");
  const std::size_t P = guides.points.size();
  if (!guides.tangents.empty() && guides.tangents.size() != P)
    return Status::Error("the guides have " + std::to_string(P) + " points and " +
                         std::to_string(guides.tangents.size()) + " tangents.");
  if (!guides.directors.empty() && guides.directors.size() != P)
    return Status::Error("the guides have " + std::to_string(P) + " points and " +
                         std::to_string(guides.directors.size()) + " directors.");
  for (const auto& [name, values] : guides.scalars)
    if (values.size() != P)
      return Status::Error("the guides' array " + name + " has " + std::to_string(values.size()) +
                           " values for " + std::to_string(P) + " points.");
  for (const Eigen::Vector3d& x : guides.points)
    if (!x.allFinite())
      return Status::Error("a guide point is not finite (NaN or infinite).");

  const int n = Options.pointsPerStrand;
  const int M = 2 * (n - 1) + 1; // samples per guide
  const int S = static_cast<int>(guides.scalars.size());
  std::vector<const std::vector<double>*> scalarArrays;
  for (const auto& entry : guides.scalars)
    scalarArrays.push_back(&entry.second);

  Eigen::Matrix3d headTurn = Eigen::Matrix3d::Identity();
  if (guides.directors.empty())
    headTurn = rootMotion(guides).linear();
  // Each guide at M even fractions of its length (by chord length along its polyline).
  std::vector<Resampled> curves(G);
  std::vector<Eigen::Vector3d> tips(G);
  parallelBlocks(
      static_cast<std::int64_t>(G), 8, Options.threads,
      [&](std::int64_t begin, std::int64_t end)
      {
        std::vector<double> chord;
        std::vector<Eigen::Vector3d> tangent, director, prefix, axis;
        for (std::int64_t g = begin; g < end; ++g)
        {
          const std::size_t a = guides.offsets[g], m = guides.offsets[g + 1] - a;
          const Eigen::Vector3d* x = &guides.points[a];
          chord.assign(m, 0);
          for (std::size_t i = 1; i < m; ++i)
            chord[i] = chord[i - 1] + (x[i] - x[i - 1]).norm();
          tangent.resize(m);
          director.resize(m);
          for (std::size_t i = 0; i < m; ++i)
          {
            if (!guides.tangents.empty())
              tangent[i] = guides.tangents[a + i];
            else
              tangent[i] = (x[std::min(i + 1, m - 1)] - x[i > 0 ? i - 1 : 0]).normalized();
          }
          if (!guides.directors.empty())
          {
            for (std::size_t i = 0; i < m; ++i)
              director[i] = guides.directors[a + i];
          }
          else
          {
            // The rest root frame turned by the roots' rigid motion, then carried along the
            // curve by parallel transport.
            director[0] = headTurn * RestFrames[g].col(1);
            for (std::size_t i = 1; i < m; ++i)
            {
              const Eigen::Quaterniond turn =
                  Eigen::Quaterniond::FromTwoVectors(tangent[i - 1], tangent[i]);
              director[i] = turn * director[i - 1];
            }
          }
          // The frame that carries the offsets: for curled hair the material frame at the
          // root carried by parallel transport along the guide's axis (its points averaged
          // over one turn of its natural helix), so that an offset translates the guide's
          // curl instead of winding around it at the offset's radius (which, with offsets of
          // the order of the helix radius, made rendered curly hair 30-50 % curlier than its
          // guides); for straight hair the material frame itself.
          const double period = Periods[g];
          if (period > 0 && m > 2)
          {
            prefix.assign(m + 1, Eigen::Vector3d::Zero());
            for (std::size_t i = 0; i < m; ++i)
              prefix[i + 1] = prefix[i] + x[i];
            axis.resize(m);
            std::size_t lo = 0, hi = 0;
            for (std::size_t i = 0; i < m; ++i)
            {
              const double half = std::min({0.5 * period, chord[i], chord[m - 1] - chord[i]});
              while (chord[i] - chord[lo] > half)
                ++lo;
              while (lo > 0 && chord[i] - chord[lo - 1] <= half)
                --lo;
              hi = std::max(hi, i);
              while (hi + 1 < m && chord[hi + 1] - chord[i] <= half)
                ++hi;
              while (hi > i && chord[hi] - chord[i] > half)
                --hi;
              axis[i] = (prefix[hi + 1] - prefix[lo]) / double(hi - lo + 1);
            }
            // Within half a turn of the root and of the tip the window is cut short and the
            // axis follows the curl: there the frame is carried along the axis direction of
            // the nearest point with a whole turn about it, turned smoothly from the root's
            // tangent at the root (following the cut axis wound the offsets around the curl
            // and made the rendered ends half as curly again as their guides).
            const auto axisDirection = [&](std::size_t i)
            {
              Eigen::Vector3d t = axis[std::min(i + 1, m - 1)] - axis[i > 0 ? i - 1 : 0];
              return t.norm() > 0 ? Eigen::Vector3d(t.normalized()) : tangent[i];
            };
            std::size_t whole0 = m, whole1 = 0;
            for (std::size_t i = 0; i < m; ++i)
            {
              if (chord[i] >= 0.5 * period && chord[m - 1] - chord[i] >= 0.5 * period)
              {
                whole0 = std::min(whole0, i);
                whole1 = i;
              }
            }
            Eigen::Matrix3d carry = orthonormalFrame(tangent[0], director[0]);
            Eigen::Vector3d previous = tangent[0];
            director[0] = carry.col(1);
            for (std::size_t i = 1; i < m; ++i)
            {
              Eigen::Vector3d t;
              if (whole0 > whole1)
                t = axisDirection(i); // shorter than a turn: the cut axis throughout
              else if (i < whole0)
              {
                const double w = chord[i] / chord[whole0];
                t = ((1 - w) * tangent[0] + w * axisDirection(whole0)).normalized();
              }
              else
                t = axisDirection(std::min(i, whole1));
              carry = Eigen::Quaterniond::FromTwoVectors(previous, t).toRotationMatrix() * carry;
              previous = t;
              tangent[i] = carry.col(0);
              director[i] = carry.col(1);
            }
          }
          Resampled& c = curves[g];
          c.position.resize(M);
          c.frame.resize(M);
          c.scalars.assign(std::size_t(M) * S, 0);
          const double length = chord[m - 1];
          std::size_t seg = 0;
          for (int j = 0; j < M; ++j)
          {
            const double s = length * j / (M - 1);
            while (seg + 2 < m && chord[seg + 1] < s)
              ++seg;
            const double span = chord[seg + 1] - chord[seg];
            const double f = span > 0 ? std::clamp((s - chord[seg]) / span, 0.0, 1.0) : 0.0;
            c.position[j] = (1 - f) * x[seg] + f * x[seg + 1];
            c.frame[j] = orthonormalFrame((1 - f) * tangent[seg] + f * tangent[seg + 1],
                                          (1 - f) * director[seg] + f * director[seg + 1]);
            for (int q = 0; q < S; ++q)
              c.scalars[std::size_t(j) * S + q] =
                  (1 - f) * (*scalarArrays[q])[a + seg] + f * (*scalarArrays[q])[a + seg + 1];
          }
          tips[g] = x[m - 1];
        }
      });

  // What the per-point work reads, in single precision, once per guide per frame: each
  // sample's position (relative to the first guide's root, so that floats keep ~0.1 µm on a
  // body a metre from the origin) and frame as four 4-float rows, its scalars, and, per
  // body part, the table's window reach about it for two ball radii
  // (CollisionTable::windowReach): a rendered point within the ball about its clump guide's
  // sample and farther from every part's axis or centre than that reach is outside the body,
  // and is not looked up.
  const Eigen::Vector3d origin = guides.points[guides.offsets[0]];
  PushOutSkip skip;
  skip.parts = int(parts.size());
  for (const PosedPart& part : parts)
  {
    const TableSpec& spec = part.table->spec();
    PushOutSkip::Part shape;
    const Eigen::Vector3d centre = part.pose * spec.frame.origin - origin;
    const Eigen::Vector3d axis = part.pose.linear() * spec.frame.axis.normalized();
    shape.centre << float(centre.x()), float(centre.y()), float(centre.z()), 0.0f;
    shape.axis << float(axis.x()), float(axis.y()), float(axis.z()), 0.0f;
    shape.cylindrical = spec.projection == Projection::Cylindrical;
    skip.shapes.push_back(shape);
  }
  std::vector<GuideSample> samples(G * std::size_t(M));
  std::vector<float> sampleScalars(G * std::size_t(M) * S);
  skip.reach.assign(G * std::size_t(M) * parts.size() * PushOutSkip::Balls, 0.0f);
  parallelBlocks(
      static_cast<std::int64_t>(G), 8, Options.threads,
      [&](std::int64_t begin, std::int64_t end)
      {
        for (std::int64_t g = begin; g < end; ++g)
        {
          const Resampled& c = curves[g];
          for (int j = 0; j < M; ++j)
          {
            const std::size_t k = std::size_t(g) * M + j;
            GuideSample& out = samples[k];
            const Eigen::Vector3d x = c.position[j] - origin;
            out.row[0] << float(x.x()), float(x.y()), float(x.z()), 0.0f;
            for (int a = 0; a < 3; ++a)
              out.row[1 + a] << float(c.frame[j](0, a)), float(c.frame[j](1, a)),
                  float(c.frame[j](2, a)), 0.0f;
            for (int q = 0; q < S; ++q)
              sampleScalars[k * S + q] = float(c.scalars[std::size_t(j) * S + q]);
            for (std::size_t part = 0; part < parts.size(); ++part)
            {
              const Eigen::Vector3d rest = parts[part].toRest(c.position[j]);
              for (int ball = 0; ball < PushOutSkip::Balls; ++ball)
              {
                // Squared, with a margin for the float arithmetic of the test.
                const double r = parts[part].table->windowReach(rest, PushOutSkip::Radius[ball]) +
                                 PushOutSkip::FloatMargin;
                skip.reach[(k * parts.size() + part) * PushOutSkip::Balls + ball] =
                    std::isfinite(r) ? float(r * r) : std::numeric_limits<float>::infinity();
              }
            }
          }
        }
      });
  return fill(samples, sampleScalars, skip, tips, origin, parts, out, counts, progress);
}

bool HairInterpolation::PushOutSkip::outside(std::size_t k, const Eigen::Array4f& point,
                                             const std::vector<GuideSample>& samples) const
{
  const float d2 = (point - samples[k].row[0]).matrix().squaredNorm();
  int ball = 0;
  while (ball < Balls && !(d2 < float(Radius[ball] * Radius[ball])))
    ++ball;
  if (ball == Balls)
    return false;
  for (int part = 0; part < parts; ++part)
  {
    const Part& shape = shapes[std::size_t(part)];
    const Eigen::Array4f d = point - shape.centre;
    float rho2 = d.matrix().squaredNorm();
    if (shape.cylindrical)
    {
      const float along = (d * shape.axis).sum();
      rho2 -= along * along;
    }
    if (!(rho2 > reach[(k * std::size_t(parts) + std::size_t(part)) * Balls + ball]))
      return false;
  }
  return true;
}

Status HairInterpolation::fill(const std::vector<GuideSample>& samples,
                               const std::vector<float>& sampleScalars, const PushOutSkip& skip,
                               const std::vector<Eigen::Vector3d>& tips,
                               const Eigen::Vector3d& origin, const std::vector<PosedPart>& parts,
                               const RenderedHairArrays& out, PushOutCounts& counts,
                               const Progress& progress) const
{
  const int n = Options.pointsPerStrand;
  const int M = 2 * (n - 1) + 1;
  const int S = static_cast<int>(out.scalars.size());
  const std::size_t strands = Roots.size();
  const bool clusters = Options.method == InterpolationMethod::Clusters;
  const double T = Options.tipDistance;
  const float clumpStart = float(ClumpStart), clumpEnd = float(ClumpEnd);
  // Strands in chunks, each on all threads, with progress (and abort) between chunks on
  // the calling thread. Per block: its push-out counts, merged in block order.
  const std::int64_t grain = 256;
  const std::int64_t chunk = 64 * grain;
  const std::size_t blocks = std::size_t(blockCount(std::int64_t(strands), grain));
  std::vector<PushOutCounts> perBlock(blocks);
  for (std::int64_t first = 0; first < std::int64_t(strands); first += chunk)
  {
    const std::int64_t last = std::min<std::int64_t>(strands, first + chunk);
    parallelBlocks(
        last - first, grain, Options.threads,
        [&](std::int64_t begin, std::int64_t end)
        {
          PushOutCounts& tally = perBlock[std::size_t((first + begin) / grain)];
          std::vector<Eigen::Array4f> p(n);
          std::vector<float> value(S);
          for (std::int64_t r = first + begin; r < first + end; ++r)
          {
            const Binding& b = Roots[r];
            const int c = b.guides[b.clump];
            // Guides whose tips have parted from the clump guide's stop weighing in.
            float w[8];
            double sum = 0, raw[8];
            for (int i = 0; i < b.count; ++i)
            {
              const double d = (tips[b.guides[i]] - tips[c]).norm();
              raw[i] = b.weights[i] * (1 - smoothstep((d - T) / T));
              sum += raw[i];
            }
            for (int i = 0; i < b.count; ++i)
              w[i] = float(sum > 0 ? raw[i] / sum : (i == b.clump ? 1.0 : 0.0));
            Eigen::Array4f offset[8];
            for (int i = 0; i < b.count; ++i)
              offset[i] << float(b.offsets[i].x()), float(b.offsets[i].y()),
                  float(b.offsets[i].z()), 0.0f;
            Eigen::Array4f clumpOffset;
            clumpOffset << float(b.clumpOffset.x()), float(b.clumpOffset.y()),
                float(b.clumpOffset.z()), 0.0f;
            const float length = float(b.length);
            for (int j = 0; j < n; ++j)
            {
              const float u = length * float(j) / float(n - 1);
              const float x = u * float(M - 1);
              const int i0 = std::min(static_cast<int>(x), M - 2);
              const float f = x - float(i0);
              // 0 where the guides are interpolated, 1 where the strand follows its clump.
              const float profile =
                  smoothstepf(clumpEnd > clumpStart ? (u - clumpStart) / (clumpEnd - clumpStart)
                                                    : (u >= clumpStart ? 1.0f : 0.0f));
              const float blend = clusters ? 1.0f : profile;
              Eigen::Array4f point = Eigen::Array4f::Zero();
              std::fill(value.begin(), value.end(), 0.0f);
              // One guide's sample carried by an offset in its frame, lerped between the two
              // samples about u, weighted by a: four multiply-adds of 4 floats per sample.
              const auto add = [&](int g, const Eigen::Array4f& o, float a)
              {
                const std::size_t k = std::size_t(g) * M + i0;
                const GuideSample& s0 = samples[k];
                const GuideSample& s1 = samples[k + 1];
                const float a0 = a * (1 - f), a1 = a * f;
                point +=
                    a0 * (s0.row[0] + o.x() * s0.row[1] + o.y() * s0.row[2] + o.z() * s0.row[3]) +
                    a1 * (s1.row[0] + o.x() * s1.row[1] + o.y() * s1.row[2] + o.z() * s1.row[3]);
                // data(): with no scalars (S = 0) the vector is empty and [] would bind a
                // reference to nothing (UBSan); data() + 0 is defined.
                const float* v0 = sampleScalars.data() + k * S;
                for (int q = 0; q < S; ++q)
                  value[q] += a0 * v0[q] + a1 * v0[S + q];
              };
              if (blend > 0)
                add(c, (1 - profile) * offset[b.clump] + profile * clumpOffset, blend);
              if (blend < 1)
              {
                for (int i = 0; i < b.count; ++i)
                  if (w[i] != 0)
                    add(b.guides[i], offset[i], (1 - blend) * w[i]);
              }
              // Out of the body: skipped where the point lies in a ball about its clump
              // guide's nearer sample and beyond every part's window reach there; otherwise
              // one look-up where a part is near, and a point moved out of one part into
              // another (the neck, where head and trunk meet) or left inside by the table's
              // curvature is moved again, up to eight times.
              if (!parts.empty())
              {
                const bool clear =
                    skip.outside(std::size_t(c) * M + i0 + (f < 0.5f ? 0 : 1), point, samples);
                // Most points looked up are outside: the inside test alone says so; the
                // full query (depth, normal) only for a point inside a part.
                if (!clear)
                {
                  ++tally.lookedUp;
                  Eigen::Vector3d at = origin + point.head<3>().cast<double>().matrix();
                  if (insideAny(parts, at))
                  {
                    const Eigen::Vector3d before = at;
                    PartContact contact;
                    bool inside = true;
                    for (int pass = 0; pass < 8 && inside; ++pass)
                    {
                      if (!deepestPart(parts, at, 0, contact) || contact.depth <= 0)
                        break;
                      if (pass == 0)
                        tally.deepest = std::max(tally.deepest, contact.depth);
                      at += (contact.depth + 1e-5) * contact.normal;
                      inside = insideAny(parts, at);
                    }
                    ++tally.pushedOut;
                    double depth = 0;
                    if (inside && insideDepth(parts, at, depth))
                    {
                      ++tally.stillInside;
                      tally.deepestAfter = std::max(tally.deepestAfter, depth);
                    }
                    point.head<3>() += (at - before).cast<float>().array();
                  }
                }
              }
              p[j] = point;
              const std::size_t k = std::size_t(r) * n + j;
              if (out.parameter)
                out.parameter[k] = float(j) / float(n - 1);
              for (int q = 0; q < S; ++q)
                out.scalars[q][k] = value[q];
            }
            for (int j = 0; j < n; ++j)
            {
              const std::size_t k = (std::size_t(r) * n + j) * 3;
              // Positions: the float offset from the origin added in double, then rounded.
              for (int a = 0; a < 3; ++a)
                out.points[k + a] = float(origin[a] + double(p[j][a]));
              if (out.tangents)
              {
                Eigen::Vector3f t =
                    (p[std::min(j + 1, n - 1)] - p[std::max(j - 1, 0)]).head<3>().matrix();
                t.normalize();
                for (int a = 0; a < 3; ++a)
                  out.tangents[k + a] = t[a];
              }
            }
            if (out.guide)
              out.guide[r] = c;
          }
        });
    if (progress && !progress(double(last) / strands))
      return Status::Error("aborted.");
  }
  for (const PushOutCounts& b : perBlock)
  {
    counts.pushedOut += b.pushedOut;
    counts.stillInside += b.stillInside;
    counts.lookedUp += b.lookedUp;
    counts.deepest = std::max(counts.deepest, b.deepest);
    counts.deepestAfter = std::max(counts.deepestAfter, b.deepestAfter);
  }
  return Status::Ok();
}

Eigen::Isometry3d HairInterpolation::rootMotion(const GuideCurves& guides) const
{
  std::vector<Eigen::Vector3d> from, to;
  const double arm = 0.01;
  for (std::size_t g = 0; g < std::min(guides.size(), RestRoots.size()); ++g)
  {
    const std::size_t a = guides.offsets[g];
    if (a >= guides.points.size())
      continue;
    from.push_back(RestRoots[g]);
    to.push_back(guides.points[a]);
    if (!guides.tangents.empty() && !guides.directors.empty())
    {
      const Eigen::Matrix3d now = orthonormalFrame(guides.tangents[a], guides.directors[a]);
      for (int c = 0; c < 2; ++c)
      {
        from.push_back(RestRoots[g] + arm * RestFrames[g].col(c));
        to.push_back(guides.points[a] + arm * now.col(c));
      }
    }
  }
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  if (from.empty())
    return motion;
  Eigen::Vector3d cf = Eigen::Vector3d::Zero(), ct = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < from.size(); ++i)
  {
    cf += from[i];
    ct += to[i];
  }
  cf /= double(from.size());
  ct /= double(to.size());
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < from.size(); ++i)
    H += (from[i] - cf) * (to[i] - ct).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  if ((svd.matrixV() * svd.matrixU().transpose()).determinant() < 0)
    D(2, 2) = -1;
  const Eigen::Matrix3d R = svd.matrixV() * D * svd.matrixU().transpose();
  motion.linear() = R;
  motion.translation() = ct - R * cf;
  return motion;
}

} // namespace hair
