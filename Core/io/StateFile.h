#pragma once
// The HDF5 state file: every frame of a simulation, readable without the plugin (h5py).
// Layout and guarantees are documented in docs/state-file.md; the names here are the
// interface that scripts depend on.
#include "common/Ranks.h"
#include "common/Status.h"
#include "io/StateFormat.h"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>

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
  /// The points are the model's nodes and are drawn again from q and the roots (the
  /// Super-Helix): the file keeps their positions and velocities in single precision, a view
  /// for scripts; the frames in memory keep them in double.
  bool singlePrecisionPoints = false;
  /// The groom and rest shape (optional).
  StateGroom groom;
  /// The room the file keeps for the continuation of its last frames (/resume: what a
  /// resumed run restores, docs/state-file.md): numbers per strand (its count first) and
  /// the model's own numbers. 0: the file keeps none (it cannot be resumed).
  int continuationWidth = 0;
  int continuationRunValues = 0;
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

/// What a run's model needs to go on from a frame (StrandModel::saveContinuation), kept in
/// the file with the frame: per strand described by the header (a rank: its piece), its
/// numbers, and the model's own, as many as the header's continuationRunValues.
struct StateContinuation
{
  std::int64_t frame = -1; ///< the frame it belongs to
  std::vector<std::vector<double>> strands;
  std::vector<double> run;
};

inline constexpr int RootFrameValues = 12;
inline constexpr int RootVelocityValues = 6;

/// One per-frame array of StateFrame and its dataset in /frames: the frame's schema, declared
/// once (frameFields()) and iterated by the writer, the reader (whole and piece), the frame
/// store and the ghost exchange. The per-point scalars (StateHeader::pointData) are
/// per-point rows of width 1 named by the header; forEachArray visits both.
struct FrameField
{
  enum class Rows
  {
    Point, ///< one row per point (the model's nodes)
    Strand ///< one row per strand
  };
  const char* path; ///< the dataset (io/StateFormat.h)
  const char* what; ///< a row in messages: "the position of point" (then its number)
  Rows rows;
  int width;            ///< numbers per row; 0: the header's coordinatesPerStrand
  const char* unit;     ///< of its numbers (docs/state-file.md)
  const char* filledBy; ///< who fills it in a run
  /// The frame's numbers of the field, row after row, and their count.
  double* (*values)(StateFrame&);
  std::size_t (*count)(const StateFrame&);
  /// Gives the frame room for `numbers` numbers of the field.
  void (*resize)(StateFrame&, std::size_t numbers);
  /// Whether a file or a frame of `header` has the field.
  bool (*present)(const StateHeader&);
  /// Kept in single precision in a file of `header` (the points of a model drawn from q).
  bool singlePrecision(const StateHeader& h) const
  {
    return rows == Rows::Point && h.singlePrecisionPoints;
  }
  std::size_t rowsOf(const StateHeader& h) const
  {
    return rows == Rows::Point ? h.numberOfPoints() : h.numberOfStrands();
  }
  std::size_t widthOf(const StateHeader& h) const
  {
    return width > 0 ? std::size_t(width) : std::size_t(std::max(0, h.coordinatesPerStrand));
  }
};

/// The frame's schema: positions, velocities, q, q̇, root frames, root velocities.
const std::vector<FrameField>& frameFields();
/// Whether `name` in /frames is a field of frameFields(), so not a per-point scalar's.
bool isFrameField(const std::string& name);

/// One array of a frame as forEachArray gives it: a field of frameFields() or a per-point
/// scalar (field null, name its name).
struct FrameArray
{
  const FrameField* field = nullptr;
  std::string name; ///< the dataset's path in /frames
  std::string what; ///< a row in messages (FrameField::what; "'name' at point")
  bool perPoint = true;
  std::size_t width = 1;
  double* data = nullptr;
  std::size_t size = 0; ///< numbers held
  /// The rows a frame of `h` has of it: one per point, or one per strand.
  std::size_t rowsIn(const StateHeader& h) const
  {
    return perPoint ? h.numberOfPoints() : h.numberOfStrands();
  }
  /// Strand k's numbers in `data`, for a frame of `h`: the first one's index and their count.
  std::pair<std::size_t, std::size_t> strandSpan(const StateHeader& h, std::size_t k) const
  {
    const std::size_t first = perPoint ? std::size_t(h.offsets[k]) : k;
    const std::size_t rows = perPoint ? std::size_t(h.offsets[k + 1] - h.offsets[k]) : 1;
    return {first * width, rows * width};
  }
  /// The index of the first number that is NaN or infinite; `size` when there is none.
  std::size_t firstNonFinite() const
  {
    std::size_t i = 0;
    while (i < size && std::isfinite(data[i]))
    {
      ++i;
    }
    return i;
  }
};

/// Calls fn(FrameArray) for every array `header` says a frame has: the present fields of
/// frameFields(), then the per-point scalars in the header's order. With `resize`, gives
/// each the room `header` says first (a frame to be filled).
template <class Fn>
void forEachArray(const StateHeader& header, StateFrame& frame, bool resize, Fn&& fn);

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
  /// Opens the state file at `path`, which a run of `header` wrote (checked by the caller:
  /// Simulation's resume), to go on after its first `keep` frames: the frames after them
  /// are dropped, the next append() writes frame `keep`. Shared: collective, and the file
  /// must have room for sharing.frames frames.
  Status reopen(const std::string& path, const StateHeader& header,
                const std::vector<std::string>& extraEnergyTerms, std::int64_t keep,
                const FileSharing& sharing = {});
  /// Appends the next frame. Shared: collective, `frame` is this rank's piece (its strands'
  /// points, q, roots and per-point arrays; its time and energy the same on every rank), and
  /// a frame one rank refuses (NaN, wrong sizes) or fails to write is refused on every rank.
  /// `continuation` (when the header keeps room for it): the frame's, written before the
  /// frame is whole, into the slot that does not hold the previous frame's, so that the last
  /// whole frame's continuation is always whole in the file. A continuation too large for
  /// the room is not kept (the slot says none), and `continuationKept` says so.
  Status append(const StateFrame& frame, const StateContinuation* continuation = nullptr,
                bool* continuationKept = nullptr);
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
  /// The continuation of the newest whole frame that has one (StateContinuation::frame
  /// says which; the last whole frame unless a continuation did not fit its room), of the
  /// strands `strands` (increasing; null: every strand). Refused, with why, when the file
  /// keeps none.
  Status readContinuation(const std::vector<std::int64_t>* strands, StateContinuation& out) const;
  /// Written by several MPI ranks together (/whole_frames counts its whole frames; version
  /// 2, or 3 with it), rather than by one process.
  bool sharedByRanks() const;
  /// The file's format_version (1: one writer; 2: written by several MPI ranks together).
  int version() const;
  /// The strands of piece `piece` of `pieces` (increasing): when the file has the guides'
  /// rest roots (/strands/rest_root), a compact patch of them, every piece as many strands
  /// to within one (a range of their Hilbert curve, common/Partition.h); otherwise a run of
  /// consecutive strands. Every strand is in exactly one piece; a piece may be empty when
  /// there are fewer strands than pieces.
  std::vector<std::int64_t> pieceStrands(int piece, int pieces) const;

private:
  struct Impl;
  std::unique_ptr<Impl> P;
};

template <class Fn>
void forEachArray(const StateHeader& header, StateFrame& frame, bool resize, Fn&& fn)
{
  for (const FrameField& field : frameFields())
  {
    if (!field.present(header))
    {
      continue;
    }
    const std::size_t width = field.widthOf(header);
    if (resize)
    {
      field.resize(frame, field.rowsOf(header) * width);
    }
    FrameArray a;
    a.field = &field;
    a.name = field.path;
    a.what = field.what;
    a.perPoint = field.rows == FrameField::Rows::Point;
    a.width = width;
    a.data = field.values(frame);
    a.size = field.count(frame);
    fn(a);
  }
  for (const std::string& name : header.pointData)
  {
    FrameArray a;
    a.name = stateformat::inGroup(stateformat::Frames, name);
    a.what = "'" + name + "' at point";
    auto it = frame.pointData.find(name);
    if (resize)
    {
      it = frame.pointData.emplace(name, std::vector<double>()).first;
      it->second.resize(header.numberOfPoints());
    }
    if (it != frame.pointData.end())
    {
      a.data = it->second.data();
      a.size = it->second.size();
    }
    fn(a);
  }
}

/// forEachArray of a frame that is only looked at (a missing per-point scalar: size 0).
template <class Fn>
void forEachArray(const StateHeader& header, const StateFrame& frame, Fn&& fn)
{
  forEachArray(header, const_cast<StateFrame&>(frame), false,
               [&](const FrameArray& a) { fn(static_cast<const FrameArray&>(a)); });
}

} // namespace hair
