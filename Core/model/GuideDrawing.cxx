#include "model/GuideDrawing.h"

namespace hair
{

const std::vector<double>* strandParameter(const StateHeader& header, const char* file)
{
  const auto it = header.strandParameters.find(file);
  return it == header.strandParameters.end() ? nullptr : &it->second;
}

} // namespace hair
