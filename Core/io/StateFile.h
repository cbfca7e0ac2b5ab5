#pragma once
// The HDF5 state file: every frame of a simulation, readable without the plugin (h5py).
// Layout and guarantees are documented in docs/state-file.md; the names here are the
// interface that scripts depend on.
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

  std::size_t numberOfStrands() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  std::size_t numberOfPoints() const { return offsets.empty() ? 0 : std::size_t(offsets.back()); }
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

/// Writes a state file frame by frame. Each frame is flushed before append() returns, and
/// the file is written in HDF5's single-writer/multiple-reader mode, so a run killed at any
/// moment (even SIGKILL) leaves a file that reads back up to its last whole frame, and a
/// reader can follow a run while it is written.
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
  Status create(const std::string& path, const StateHeader& header,
                const std::vector<std::string>& extraEnergyTerms = {},
                Existing existing = Existing::Refuse);
  Status append(const StateFrame& frame);
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

private:
  struct Impl;
  std::unique_ptr<Impl> P;
};

} // namespace hair
