#pragma once
// The names of the state file's format (docs/state-file.md), in one place for the writer and
// the reader. Scripts read files by these names: changing one is a new format version.
#include <string>

namespace hair::stateformat
{

/// The value of the root's `format` attribute, and the version this code writes: states at
/// the model's nodes, by one writer or by several MPI ranks together (a shared file has
/// WholeFrames). This code reads versions 1, 2 and 3 (docs/state-file.md).
inline constexpr char Name[] = "HairDynamics states";
inline constexpr int Version = 3;
/// Earlier versions, read: 1, points at display resolution and per-point scalars, one writer;
/// 2, the same written by several MPI ranks together (room for the run's frames from the
/// start, WholeFrames counts the whole ones).
inline constexpr int OneWriterVersion = 1;
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
/// int64 scalar, in a file written by several MPI ranks (version 2, and version 3 when they
/// share it): the number of whole frames (/time is as long as the run).
inline constexpr char WholeFrames[] = "/whole_frames";
/// offsets, then one dataset [S] per strand parameter and one [S, 3] per strand vector.
inline constexpr char Strands[] = "/strands";
inline constexpr char Offsets[] = "/strands/offsets"; ///< int64 [S+1]
/// The datasets below, then one dataset [T, P] per per-point scalar.
inline constexpr char Frames[] = "/frames";
/// [T, P, 3]: version 3, at the model's nodes (float32 for a model drawn from q); versions 1
/// and 2, at the run's display resolution.
inline constexpr char Positions[] = "/frames/positions";
inline constexpr char Velocities[] = "/frames/velocities"; ///< [T, P, 3], as Positions
inline constexpr char Q[] = "/frames/q";                   ///< [T, S, C], absent when C = 0
inline constexpr char QDot[] = "/frames/qdot";             ///< [T, S, C], absent when C = 0
/// [T, S, RootFrameValues] and [T, S, RootVelocityValues] (StateFile.h), optional: each
/// strand's root pose and rates.
inline constexpr char RootFrames[] = "/frames/root_frames";
inline constexpr char RootVelocities[] = "/frames/root_velocities";
/// One dataset [T] per energy term; RequiredEnergyTerms (StateFile.h) are always there.
inline constexpr char Energy[] = "/energy";
/// Optional (StateGroom): the guide curves and the rest shape a run started from, and one
/// dataset [S] per per-strand value of the groom's report.
inline constexpr char Groom[] = "/groom";
inline constexpr char CurveOffsets[] = "/groom/curve_offsets";       ///< int64 [S+1]
inline constexpr char CurvePoints[] = "/groom/curve_points";         ///< [Pc, 3]
inline constexpr char RestCoordinates[] = "/groom/rest_coordinates"; ///< [S, C]

/// Optional (StateHeader::continuationWidth > 0): the continuation of the last frames, in
/// two slots written in turn, so that the last whole frame's is whole while the next one's
/// is written (docs/state-file.md, "Resuming a run").
inline constexpr char Resume[] = "/resume";
inline constexpr char ResumeFrame[] = "/resume/frame"; ///< int64 [2]: each slot's frame, −1 none
inline constexpr char ResumeStrands[] = "/resume/strands"; ///< [2, S, W]: count, then numbers
inline constexpr char ResumeRun[] = "/resume/run";         ///< [2, K]: the model's own numbers

/// The path of the dataset `name` in `group`: inGroup(Frames, "twist") is "/frames/twist".
inline std::string inGroup(const char* group, const std::string& name)
{
  return std::string(group) + "/" + name;
}

} // namespace hair::stateformat
