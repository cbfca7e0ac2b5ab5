#include "simulation/GuidesFromState.h"

#include "strands/StrandParameters.h"

namespace hair
{

Status guidesFromState(const StateHeader& header, std::vector<GuideStrand>& guides)
{
  const std::size_t S = header.numberOfStrands();
  std::vector<GuideStrand> out(S);
  for (const StrandParameter& p : strandParameters())
  {
    const auto it = header.strandParameters.find(p.file);
    if (it == header.strandParameters.end() || it->second.size() != S)
    {
      if (p.optional)
      {
        continue;
      }
      return Status::Error(std::string("the state file has no per-strand '") + p.file +
                           "': it was written before the guides were stored, and its run cannot "
                           "be made again from it.");
    }
    for (std::size_t k = 0; k < S; ++k)
    {
      p.set(out[k], it->second[k]);
    }
  }
  for (const StrandVector& v : strandVectors())
  {
    const auto it = header.strandVectors.find(v.file);
    if (it == header.strandVectors.end() || it->second.size() != S)
    {
      return Status::Error(std::string("the state file has no per-strand '") + v.file +
                           "': it was written before the guides were stored, and its run cannot "
                           "be made again from it.");
    }
    for (std::size_t k = 0; k < S; ++k)
    {
      v.set(out[k], it->second[k]);
    }
  }
  const StateGroom& g = header.groom;
  if (g.curveOffsets.size() == S + 1)
  {
    for (std::size_t k = 0; k < S; ++k)
    {
      out[k].curve.assign(g.curvePoints.begin() + g.curveOffsets[k],
                          g.curvePoints.begin() + g.curveOffsets[k + 1]);
    }
  }
  guides = std::move(out);
  return Status::Ok();
}

} // namespace hair
