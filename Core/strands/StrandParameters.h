#pragma once
// The per-strand parameters of a guide, named once: the cell array of the pipeline (Hair
// Strands writes it, Hair Simulation reads it, both outputs carry it) and the dataset of
// the state file (/strands/<name>), with the unit and the field of GuideStrand it holds.
// The scalars (one value per strand) and the vectors (three components per strand: where
// the guide roots, its scalp normal and growth direction) have one table each.
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
  /// May be missing from Hair Simulation's strands input (the field keeps its default):
  /// parameters added after strands without them were made.
  bool optional = false;
};

/// Every per-strand parameter, in the order they are written.
const std::array<StrandParameter, 14>& strandParameters();

/// The cell array that marks a groomed guide (1: its polyline is its guide curve,
/// GuideStrand::curve; 0 or missing: the strand grows straight along its growth direction
/// and the polyline only gives its root). The curves themselves are stored in the state
/// file's /groom group (docs/state-file.md).
inline constexpr char GroomedArray[] = "Groomed";

struct StrandVector
{
  const char* array; ///< VTK cell array name, 3 components
  const char* file;  ///< state-file dataset under /strands, [S, 3]
  const char* unit;
  /// Read from Hair Simulation's strands input. The rest root is not: a strand's root is
  /// its polyline's first point there, and RestRoot only carries it through to the outputs.
  bool input;
  Eigen::Vector3d (*get)(const GuideStrand&);
  void (*set)(GuideStrand&, const Eigen::Vector3d&);
};

/// The rest root (GuideStrand::root), the scalp normal and the growth direction: with them
/// GuideStrand::rootFrame() gives a guide's root frame as grown.
const std::array<StrandVector, 3>& strandVectors();

} // namespace hair
