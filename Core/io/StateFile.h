#pragma once
// The HDF5 state file: every frame of a simulation, readable without the plugin (h5py).
// Layout and guarantees are documented in docs/state-file.md; the names here are the
// interface that scripts depend on.
#include "common/Ranks.h"
#include "common/Status.h"

#include <Eigen/Core>

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace hair
{

/// The groom a run started from (optional; the group /groom, docs/state-file.md): each
/// groomed strand's guide curve, every strand's rest shape, and per-strand reports of the
/// fit and of the rest shape, so that a study can be re-run from the file.
struct StateGroom
{
  /// S + 1 offsets into curvePoints: strand k's guide curve is curvePoints[curveOffsets[k]]
  /// … curvePoints[curveOffsets[k + 1] − 1] (none when they are equal). Empty: no curves.
  std::vector<std::int64_t> curveOffsets;
  std::vector<Eigen::Vector3d> curvePoints;
  /// S × coordinatesPerStrand: the rest shape each strand ran with (Super-Helix (τ, κ1, κ2)
  /// per element, projective (θ⁰, φ⁰) per segment). Empty: not recorded.
  std::vector<double> restCoordinates;
  /// Per-strand values, one per strand each (fit_error, rest_status, …).
  std::map<std::string, std::vector<double>> strandValues;
  bool empty() const
  {
    return curveOffsets.empty() && restCoordinates.empty() && strandValues.empty();
  }
};

/// What does not change over a run.
struct StateHeader
{
  std::string model;                 ///< "super-helix" or "projective"
  std::vector<std::int64_t> offsets; ///< strand k owns points offsets[k] … offsets[k+1]−1
  /// Generalized coordinates per strand (3N for Super-Helices; 0: no /frames/q, /frames/qdot).
  int coordinatesPerStrand = 0;
  /// Per-strand parameters, each an array of one value per strand (length, radius, …).
  std::map<std::string, std::vector<double>> strandParameters;
  /// Per-strand vectors, each an array of one 3-vector per strand (rest root, …).
  std::map<std::string, std::vector<Eigen::Vector3d>> strandVectors;
  /// Every frame carries each strand's root pose and rates (StateFrame::rootFrames and
  /// rootVelocities): what redrawing the strands from q needs. Files without them read.
  bool rootFrames = false;
  /// Scalar attributes of the run (time step, gravity components, …), stored on /.
  std::map<std::string, double> attributes;
  /// Names of the per-point scalars every frame carries (/frames/<name>, [T, P]).
  std::vector<std::string> pointData;
  /// The groom and rest shape (optional).
  StateGroom groom;
  /// For a piece of a run (the strands one MPI rank holds, piece()): the run's number of
  /// each strand described here, increasing. Empty: every strand of the run, 0 … S − 1.
  std::vector<std::int64_t> strandIds;

  std::size_t numberOfStrands() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  std::size_t numberOfPoints() const { return offsets.empty() ? 0 : std::size_t(offsets.back()); }
  /// The run's number of strand k of this header.
  std::int64_t strandId(std::size_t k) const
  {
    return strandIds.empty() ? std::int64_t(k) : strandIds[k];
  }
  /// The header of the strands `ids` of this one (increasing, each < numberOfStrands(); of
  /// a whole run's header): their offsets counted from 0, their parameters and vectors,
  /// and `strandIds` = ids. No strand gives offsets {0}.
  StateHeader piece(const std::vector<std::int64_t>& ids) const;
  Status validate() const;
};

/// One frame.
struct StateFrame
{
  double time = 0;
  std::vector<Eigen::Vector3d> positions;  ///< one per point
  std::vector<Eigen::Vector3d> velocities; ///< one per point
  std::vector<double> q, qdot;             ///< numberOfStrands × coordinatesPerStrand
  /// Per strand, when the header's rootFrames: RootFrameValues numbers (the root's
  /// position, then the columns of its material frame: tangent, first and second director)
  /// and RootVelocityValues numbers (its velocity, then its angular velocity). Else empty.
  std::vector<double> rootFrames, rootVelocities;
  /// Per-point scalars, one value per point, named as in the header's pointData.
  std::map<std::string, std::vector<double>> pointData;
  /// Energy terms by name (J). The names kinetic, elastic, gravitational, dissipated and
  /// external_work are always written (0 when absent); any other term is written too.
  std::map<std::string, double> energy;
};

inline constexpr int RootFrameValues = 12;
inline constexpr int RootVelocityValues = 6;

/// The energy terms every state file has.
extern const char* const RequiredEnergyTerms[5];

/// How the MPI ranks of a run share one state file (StateFileWriter::create).
struct FileSharing
{
  Ranks ranks; ///< the ranks that write it together (one rank: not shared)
  /// This rank's strands, increasing: its piece of every frame (its hyperslab).
  std::vector<std::int64_t> strands;
  /// The frames the run will have, frame 0 included: the room every per-frame dataset gets
  /// when the file is created.
  std::int64_t frames = 0;
  bool shared() const { return ranks.parallel(); }
};

/// Writes a state file frame by frame, so that a run killed at any moment (even SIGKILL)
/// leaves a file that reads back up to its last whole frame and a reader can follow a run
/// while it is written. Written by one process (format_version 1): HDF5's
/// single-writer/multiple-reader mode, each frame flushed before append() returns. Shared by
/// the MPI ranks of a run (format_version 2, docs/state-file.md): one file written together
/// with parallel HDF5, every rank its piece; the file's structure is complete and on disk
/// once create() returns, a frame writes raw data only, and the count of whole frames is
/// written after every rank's part of the frame is.
class StateFileWriter
{
public:
  StateFileWriter();
  ~StateFileWriter();
  StateFileWriter(const StateFileWriter&) = delete;
  StateFileWriter& operator=(const StateFileWriter&) = delete;

  /// What create() does with a file that already exists at the path.
  enum class Existing
  {
    Refuse,           ///< keep it, and say so
    ReplaceStateFile, ///< replace it if it is a HairDynamics state file; keep anything else
  };
  /// Creates the file. `extraEnergyTerms` are the names of energy terms beyond the required
  /// five that frames will carry. Never writes over something that is not a HairDynamics
  /// state file (a user's notes, another program's HDF5 file), nor over a state file unless
  /// `existing` says so, nor over one another run is writing: each refused with a message.
  /// Shared (sharing.shared()): collective; `header` is the whole run's (every rank gives
  /// the same) and `sharing` says which strands this rank writes.
  Status create(const std::string& path, const StateHeader& header,
                const std::vector<std::string>& extraEnergyTerms = {},
                Existing existing = Existing::Refuse, const FileSharing& sharing = {});
  /// Appends the next frame. Shared: collective, `frame` is this rank's piece (its strands'
  /// points, q, roots and per-point arrays; its time and energy the same on every rank), and
  /// a frame one rank refuses (NaN, wrong sizes) or fails to write is refused on every rank.
  Status append(const StateFrame& frame);
  /// Shared files: collective, this rank's piece of whole frame `index`, read from the file
  /// being written (a run too long for memory reads released frames back).
  Status readPiece(std::int64_t index, StateFrame& frame) const;
  bool shared() const;
  Status close();
  bool isOpen() const;
  std::int64_t numberOfFrames() const;

private:
  struct Impl;
  std::unique_ptr<Impl> P;
};

/// Reads a state file, including one whose writer was killed or is still writing.
class StateFileReader
{
public:
  StateFileReader();
  ~StateFileReader();
  StateFileReader(const StateFileReader&) = delete;
  StateFileReader& operator=(const StateFileReader&) = delete;

  /// Opens and checks the file: refuses a file that is not HDF5, not a HairDynamics state
  /// file, of an unknown format version, or damaged, with a message that says which.
  Status open(const std::string& path);
  void close();
  const StateHeader& header() const;
  /// Whole frames in the file (a frame being written when the writer stopped is not one).
  std::int64_t numberOfFrames() const;
  const std::vector<double>& times() const;
  /// Every frame's value of each energy term.
  const std::map<std::string, std::vector<double>>& energies() const;
  Status readFrame(std::int64_t index, StateFrame& frame) const;
  /// The strands `strands` (increasing) of frame `index`: their points, q, roots and
  /// per-point arrays, as readFrame gives them for header().piece(strands); its time and
  /// energy. What a rank reads of a file's frame under MPI.
  Status readPiece(std::int64_t index, const std::vector<std::int64_t>& strands,
                   StateFrame& frame) const;
  /// The file's format_version (1: one writer; 2: written by several MPI ranks together).
  int version() const;
  /// The strands of piece `piece` of `pieces` (increasing): when the file has the guides'
  /// rest roots (/strands/rest_root), a compact patch of them, every piece as many strands
  /// to within one (recursive coordinate bisection, common/Partition.h); otherwise a run of
  /// consecutive strands. Every strand is in exactly one piece; a piece may be empty when
  /// there are fewer strands than pieces.
  std::vector<std::int64_t> pieceStrands(int piece, int pieces) const;

private:
  struct Impl;
  std::unique_ptr<Impl> P;
};

} // namespace hair
