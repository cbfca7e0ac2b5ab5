#pragma once
// The per-strand parameters of a guide, named once: the cell array of the pipeline (Hair
// Strands writes it, Hair Simulation reads it, both outputs carry it) and the dataset of
// the state file (/strands/<name>), with the unit and the field of GuideStrand it holds.
#include "strands/GuideStrand.h"

#include <array>

namespace hair
{

struct StrandParameter
{
  const char* array; ///< VTK cell array name (CamelCase, like every array of the pipeline)
  const char* file;  ///< state-file dataset under /strands (snake_case, docs/state-file.md)
  const char* unit;
  double (*get)(const GuideStrand&);
  void (*set)(GuideStrand&, double);
};

/// Every per-strand parameter, in the order they are written.
const std::array<StrandParameter, 13>& strandParameters();

} // namespace hair
