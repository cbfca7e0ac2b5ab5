// What the writer and the reader share: the header's check and the required energy terms.
// The writer is in StateFileWriter.cxx, the reader in StateFileReader.cxx, the format's
// names in StateFormat.h.
#include "io/StateFile.h"

#include "io/StateFormat.h"

#include <algorithm>
#include <functional>

namespace hair
{

const char* const RequiredEnergyTerms[5] = {"kinetic", "elastic", "gravitational", "dissipated",
                                            "external_work"};

namespace
{
double* flat(std::vector<Eigen::Vector3d>& v)
{
  return v.empty() ? nullptr : v.front().data();
}
bool always(const StateHeader&)
{
  return true;
}
bool withCoordinates(const StateHeader& h)
{
  return h.coordinatesPerStrand > 0;
}
bool withRoots(const StateHeader& h)
{
  return h.rootFrames;
}
} // namespace

const std::vector<FrameField>& frameFields()
{
  namespace sf = stateformat;
  using R = FrameField::Rows;
  static const std::vector<FrameField> fields{
      {sf::Positions, "the position of point", R::Point, 3, "m",
       "StrandModel::writeFrame (the model's nodes)",
       [](StateFrame& f) { return flat(f.positions); },
       [](const StateFrame& f) { return 3 * f.positions.size(); },
       [](StateFrame& f, std::size_t n) { f.positions.resize(n / 3); }, always},
      {sf::Velocities, "the velocity of point", R::Point, 3, "m/s", "StrandModel::writeFrame",
       [](StateFrame& f) { return flat(f.velocities); },
       [](const StateFrame& f) { return 3 * f.velocities.size(); },
       [](StateFrame& f, std::size_t n) { f.velocities.resize(n / 3); }, always},
      {sf::Q, "q of strand", R::Strand, 0, "model's coordinates (1/m, rad)",
       "StrandModel::writeFrame", [](StateFrame& f) { return f.q.data(); },
       [](const StateFrame& f) { return f.q.size(); },
       [](StateFrame& f, std::size_t n) { f.q.resize(n); }, withCoordinates},
      {sf::QDot, "qdot of strand", R::Strand, 0, "their rates (per s)", "StrandModel::writeFrame",
       [](StateFrame& f) { return f.qdot.data(); },
       [](const StateFrame& f) { return f.qdot.size(); },
       [](StateFrame& f, std::size_t n) { f.qdot.resize(n); }, withCoordinates},
      {sf::RootFrames, "the root pose of strand", R::Strand, RootFrameValues,
       "m, then unit vectors", "StrandModel::writeFrame (appendRoot)",
       [](StateFrame& f) { return f.rootFrames.data(); },
       [](const StateFrame& f) { return f.rootFrames.size(); },
       [](StateFrame& f, std::size_t n) { f.rootFrames.resize(n); }, withRoots},
      {sf::RootVelocities, "the root velocity of strand", R::Strand, RootVelocityValues,
       "m/s, then rad/s", "StrandModel::writeFrame (appendRoot)",
       [](StateFrame& f) { return f.rootVelocities.data(); },
       [](const StateFrame& f) { return f.rootVelocities.size(); },
       [](StateFrame& f, std::size_t n) { f.rootVelocities.resize(n); }, withRoots},
  };
  return fields;
}

bool isFrameField(const std::string& name)
{
  const std::string path = stateformat::inGroup(stateformat::Frames, name);
  for (const FrameField& f : frameFields())
  {
    if (path == f.path)
    {
      return true;
    }
  }
  return false;
}

StateHeader StateHeader::piece(const std::vector<std::int64_t>& ids) const
{
  StateHeader p;
  p.model = model;
  p.coordinatesPerStrand = coordinatesPerStrand;
  p.rootFrames = rootFrames;
  p.attributes = attributes;
  p.pointData = pointData;
  p.singlePrecisionPoints = singlePrecisionPoints;
  p.continuationWidth = continuationWidth;
  p.continuationRunValues = continuationRunValues;
  p.strandIds = ids;
  p.offsets.assign(1, 0);
  for (std::int64_t k : ids)
  {
    p.offsets.push_back(p.offsets.back() + offsets[k + 1] - offsets[k]);
  }
  for (const auto& [name, values] : strandParameters)
  {
    std::vector<double>& mine = p.strandParameters[name];
    for (std::int64_t k : ids)
    {
      mine.push_back(values[k]);
    }
  }
  for (const auto& [name, values] : strandVectors)
  {
    std::vector<Eigen::Vector3d>& mine = p.strandVectors[name];
    for (std::int64_t k : ids)
    {
      mine.push_back(values[k]);
    }
  }
  return p;
}

Status StateHeader::validate() const
{
  if (offsets.size() < 2 || offsets.front() != 0)
  {
    return Status::Error("the state has no strands (offsets must start at 0 and name at least "
                         "one strand): grow strands before simulating.");
  }
  for (std::size_t k = 1; k < offsets.size(); ++k)
  {
    if (offsets[k] <= offsets[k - 1])
    {
      return Status::Error("strand " + std::to_string(k - 1) + " has no points in the state.");
    }
  }
  if (!strandIds.empty() &&
      (strandIds.size() != numberOfStrands() ||
       !std::is_sorted(strandIds.begin(), strandIds.end(), std::less_equal<std::int64_t>())))
  {
    return Status::Error("the strand numbers of a piece must be one per strand, increasing.");
  }
  if (coordinatesPerStrand < 0)
  {
    return Status::Error("a negative number of coordinates per strand.");
  }
  for (const auto& [name, values] : strandParameters)
  {
    if (values.size() != numberOfStrands())
    {
      return Status::Error("the strand parameter '" + name + "' has " +
                           std::to_string(values.size()) + " values for " +
                           std::to_string(numberOfStrands()) + " strands.");
    }
  }
  for (const auto& [name, values] : strandVectors)
  {
    if (values.size() != numberOfStrands())
    {
      return Status::Error("the strand vector '" + name + "' has " + std::to_string(values.size()) +
                           " values for " + std::to_string(numberOfStrands()) + " strands.");
    }
  }
  const StateGroom& g = groom;
  if (!g.curveOffsets.empty())
  {
    bool ordered = g.curveOffsets.size() == numberOfStrands() + 1 && g.curveOffsets.front() == 0 &&
                   g.curveOffsets.back() == std::int64_t(g.curvePoints.size());
    for (std::size_t k = 1; ordered && k < g.curveOffsets.size(); ++k)
    {
      ordered = g.curveOffsets[k] >= g.curveOffsets[k - 1];
    }
    if (!ordered)
    {
      return Status::Error("the guide curves' offsets do not name " +
                           std::to_string(numberOfStrands()) + " curves of " +
                           std::to_string(g.curvePoints.size()) + " points.");
    }
  }
  if (!g.restCoordinates.empty() &&
      g.restCoordinates.size() != numberOfStrands() * std::size_t(coordinatesPerStrand))
  {
    return Status::Error("the rest shape has " + std::to_string(g.restCoordinates.size()) +
                         " values; it needs " + std::to_string(coordinatesPerStrand) +
                         " per strand.");
  }
  for (const auto& [name, values] : g.strandValues)
  {
    if (values.size() != numberOfStrands())
    {
      return Status::Error("the groom's value '" + name + "' has " + std::to_string(values.size()) +
                           " values for " + std::to_string(numberOfStrands()) + " strands.");
    }
  }
  return Status::Ok();
}

} // namespace hair
