#include "simulation/SameRun.h"

#include "io/StateFormat.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

namespace hair
{

namespace
{
std::string number(double x)
{
  std::ostringstream s;
  s.precision(17);
  s << x;
  return s.str();
}

bool same(double a, double b)
{
  return a == b || (std::isnan(a) && std::isnan(b));
}

/// The differences found, at most Shown of them named.
struct Differences
{
  static constexpr int Shown = 4;
  std::vector<std::string> named;
  int count = 0;
  void add(const std::string& what)
  {
    if (count++ < Shown)
    {
      named.push_back(what);
    }
  }
};
} // namespace

Status sameRun(const StateHeader& file, int fileVersion, const std::vector<std::string>& fileTerms,
               const StateHeader& run, const std::vector<std::string>& runTerms)
{
  if (fileVersion != stateformat::Version || file.continuationWidth < 1)
  {
    return Status::Error(
        "was written by another version of HairDynamics (state-file format version " +
        std::to_string(fileVersion) +
        (file.continuationWidth < 1 ? ", without the continuation of its frames" : "") +
        "; this one writes version " + std::to_string(stateformat::Version) +
        " and resumes only its own files): it cannot be resumed; start a new run.");
  }
  if (file.model != run.model)
  {
    return Status::Error("holds a run of the " + file.model + " model, and this run is of the " +
                         run.model + " model: it cannot be resumed by this run.");
  }
  if (file.numberOfStrands() != run.numberOfStrands() || file.offsets != run.offsets ||
      file.coordinatesPerStrand != run.coordinatesPerStrand)
  {
    return Status::Error("holds " + std::to_string(file.numberOfStrands()) + " strands of " +
                         std::to_string(file.numberOfPoints()) + " nodes, and this run has " +
                         std::to_string(run.numberOfStrands()) + " strands of " +
                         std::to_string(run.numberOfPoints()) +
                         ": it is another run's file, or the strands changed.");
  }
  Differences d;
  std::set<std::string> names;
  for (const auto& [name, value] : file.attributes)
  {
    names.insert(name);
  }
  for (const auto& [name, value] : run.attributes)
  {
    names.insert(name);
  }
  for (const std::string& name : names)
  {
    const auto f = file.attributes.find(name), r = run.attributes.find(name);
    if (f == file.attributes.end() || r == run.attributes.end())
    {
      d.add("the run attribute '" + name + "' is " +
            (f == file.attributes.end() ? "not in the file" : "not in this run"));
    }
    else if (!same(f->second, r->second))
    {
      d.add(name == "scene_fingerprint"
                ? std::string("the scene (the body parts' tables, their motions, the roots' "
                              "motion, gravity or the air) differs")
                : "'" + name + "' is " + number(f->second) + " in the file and " +
                      number(r->second) + " in this run");
    }
  }
  auto perStrand = [&](const auto& inFile, const auto& inRun, const char* kind)
  {
    for (const auto& [name, values] : inRun)
    {
      const auto f = inFile.find(name);
      if (f == inFile.end() || f->second.size() != values.size())
      {
        d.add(std::string("the strand ") + kind + " '" + name + "' is not in the file");
        continue;
      }
      for (std::size_t k = 0; k < values.size(); ++k)
      {
        if (f->second[k] != values[k])
        {
          d.add(std::string("the strand ") + kind + " '" + name + "' of strand " +
                std::to_string(k) + " differs");
          break;
        }
      }
    }
  };
  perStrand(file.strandParameters, run.strandParameters, "parameter");
  perStrand(file.strandVectors, run.strandVectors, "vector");
  if (file.groom.curveOffsets != run.groom.curveOffsets ||
      file.groom.curvePoints != run.groom.curvePoints ||
      file.groom.restCoordinates != run.groom.restCoordinates)
  {
    d.add("the groom (guide curves or rest shapes) differs");
  }
  if (file.continuationWidth != run.continuationWidth ||
      file.continuationRunValues != run.continuationRunValues)
  {
    d.add("the room for the continuation (" + std::to_string(file.continuationWidth) + " × " +
          std::to_string(file.continuationRunValues) + " in the file, " +
          std::to_string(run.continuationWidth) + " × " +
          std::to_string(run.continuationRunValues) + " here) differs");
  }
  std::vector<std::string> terms(std::begin(RequiredEnergyTerms), std::end(RequiredEnergyTerms));
  terms.insert(terms.end(), runTerms.begin(), runTerms.end());
  std::sort(terms.begin(), terms.end());
  terms.erase(std::unique(terms.begin(), terms.end()), terms.end());
  std::vector<std::string> theirs = fileTerms;
  std::sort(theirs.begin(), theirs.end());
  if (terms != theirs)
  {
    d.add("the energy terms differ");
  }
  if (d.count == 0)
  {
    return Status::Ok();
  }
  std::string m = "is not this run's: ";
  for (std::size_t i = 0; i < d.named.size(); ++i)
  {
    m += (i ? "; " : "") + d.named[i];
  }
  if (d.count > Differences::Shown)
  {
    m += "; and " + std::to_string(d.count - Differences::Shown) + " more";
  }
  return Status::Error(m + ". Resume with the guides, scene and properties the file was "
                           "written with, or start a new run.");
}

} // namespace hair
