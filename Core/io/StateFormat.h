#pragma once
// The names of the state file's format (docs/state-file.md), in one place for the writer and
// the reader. Scripts read files by these names: changing one is a new format version.
#include <string>

namespace hair::stateformat
{

/// The value of the root's `format` attribute, and the version this code writes and reads.
inline constexpr char Name[] = "HairDynamics states";
inline constexpr int Version = 1;
/// The version of a file written by several MPI ranks together: every per-frame dataset has
/// room for the run's frames from the start, and WholeFrames counts the whole ones
/// (docs/state-file.md). This code reads both versions.
inline constexpr int SharedVersion = 2;

// Attributes of the root group. Every other numeric attribute of the root is a run
// attribute (StateHeader::attributes).
inline constexpr char FormatAttribute[] = "format";                      ///< str: Name
inline constexpr char VersionAttribute[] = "format_version";             ///< int: Version
inline constexpr char ModelAttribute[] = "model";                        ///< str
inline constexpr char CoordinatesAttribute[] = "coordinates_per_strand"; ///< int
inline constexpr const char* RootAttributes[] = {FormatAttribute, VersionAttribute, ModelAttribute,
                                                 CoordinatesAttribute};

// Groups and datasets, by absolute path. T counts frames (/frames and /energy may hold one
// more than /time), P points, S strands, C coordinates per strand.
inline constexpr char Time[] = "/time"; ///< [T]; its length is the number of whole frames
/// int64 scalar, version 2 only: the number of whole frames (/time is as long as the run).
inline constexpr char WholeFrames[] = "/whole_frames";
/// offsets, then one dataset [S] per strand parameter and one [S, 3] per strand vector.
inline constexpr char Strands[] = "/strands";
inline constexpr char Offsets[] = "/strands/offsets"; ///< int64 [S+1]
/// The datasets below, then one dataset [T, P] per per-point scalar.
inline constexpr char Frames[] = "/frames";
inline constexpr char Positions[] = "/frames/positions";   ///< [T, P, 3]
inline constexpr char Velocities[] = "/frames/velocities"; ///< [T, P, 3]
inline constexpr char Q[] = "/frames/q";                   ///< [T, S, C], absent when C = 0
inline constexpr char QDot[] = "/frames/qdot";             ///< [T, S, C], absent when C = 0
/// [T, S, RootFrameValues] and [T, S, RootVelocityValues] (StateFile.h), optional: each
/// strand's root pose and rates.
inline constexpr char RootFrames[] = "/frames/root_frames";
inline constexpr char RootVelocities[] = "/frames/root_velocities";
inline constexpr const char* FrameDatasets[] = {Positions, Velocities, Q,
                                                QDot,      RootFrames, RootVelocities};
/// One dataset [T] per energy term; RequiredEnergyTerms (StateFile.h) are always there.
inline constexpr char Energy[] = "/energy";
/// Optional (StateGroom): the guide curves and the rest shape a run started from, and one
/// dataset [S] per per-strand value of the groom's report.
inline constexpr char Groom[] = "/groom";
inline constexpr char CurveOffsets[] = "/groom/curve_offsets";       ///< int64 [S+1]
inline constexpr char CurvePoints[] = "/groom/curve_points";         ///< [Pc, 3]
inline constexpr char RestCoordinates[] = "/groom/rest_coordinates"; ///< [S, C]

/// The path of the dataset `name` in `group`: inGroup(Frames, "twist") is "/frames/twist".
inline std::string inGroup(const char* group, const std::string& name)
{
  return std::string(group) + "/" + name;
}

/// Whether `name` in /frames is one of the FrameDatasets, so not a per-point scalar's.
inline bool isFrameDataset(const std::string& name)
{
  const std::string path = inGroup(Frames, name);
  for (const char* d : FrameDatasets)
  {
    if (path == d)
    {
      return true;
    }
  }
  return false;
}

} // namespace hair::stateformat
