#pragma once
// Where a run's frames live: in memory while they fit in the memory budget, in the state
// file as they are computed (written and flushed one by one), and, for a run longer than
// memory holds, only the newest in memory with earlier ones read back from the file.
// Every frame keeps its time and energy in memory (the energy table shows them all).
#include "common/Status.h"
#include "io/StateFile.h"

#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace hair
{

struct StorageOptions
{
  /// Where every frame is written (docs/state-file.md); empty: nowhere.
  std::string stateFile;
  /// Replace a state file already at stateFile (anything else there is never written over).
  bool replaceStateFile = false;
  /// Continue the run whose state file is at stateFile from its last whole frame
  /// (Simulation::initialize: the guides, scene and options must be those it was written
  /// with; the frames after that one are dropped), instead of creating the file.
  bool resume = false;
  /// Bytes the frames may take in memory (∞: no limit).
  double memoryBudget = std::numeric_limits<double>::infinity();
  /// The frames the run will have, frame 0 included (0: unknown, no budget check). A run
  /// whose frames do not fit in the budget is refused before it starts unless there is a
  /// state file to stream them to.
  int frames = 0;
};

class FrameStore
{
public:
  FrameStore();
  ~FrameStore();
  FrameStore(const FrameStore&) = delete;
  FrameStore& operator=(const FrameStore&) = delete;

  /// Memory one frame takes (bytes): its arrays, per-point scalars and energy terms.
  static double bytesOf(const StateFrame& frame);
  /// Refuses `frames` frames of `perFrame` bytes that need more than `budget`, with the
  /// figures and what to change.
  static Status checkMemory(int frames, double perFrame, double budget, std::size_t points);

  /// Starts a run's store with its first frame: creates (truncates) the state file, if any,
  /// and writes the frame to it; decides how many frames stay in memory. On error nothing
  /// is kept. Under MPI (sharing.shared()), collective: `header` is the whole run's, the
  /// frames this rank's piece (sharing.strands), the state file shared by the ranks, and the
  /// memory window the smallest any rank needs, so that the ranks release and read back
  /// the same frames.
  /// `continuation`: the first frame's, kept in the file with it (StateFileWriter::append).
  Status open(const StateHeader& header, const std::vector<std::string>& extraEnergyTerms,
              StateFrame first, const StorageOptions& options, const FileSharing& sharing = {},
              const StateContinuation* continuation = nullptr);
  /// Starts the store of a run resumed after `frames` (its frames so far, read from its state
  /// file at options.stateFile: the last one whole, the others by time and energy only, left
  /// in the file), and opens the file to go on after them. As open() otherwise.
  Status resume(const StateHeader& header, const std::vector<std::string>& extraEnergyTerms,
                std::vector<StateFrame> frames, const StorageOptions& options,
                const FileSharing& sharing = {});
  /// Adds the next frame: written and flushed to the state file (with `continuation`, as
  /// open()), kept in memory, and the frame that leaves the memory window (already in the
  /// file) released. A write that fails closes the file and is returned; the frame stays in
  /// memory. Under MPI, collective.
  Status add(StateFrame frame, const StateContinuation* continuation = nullptr);
  /// Whether the state file is written (a run with one that has not failed).
  bool writing() const { return Writer != nullptr; }
  void close();
  /// A frame to write the next one into: the arrays of the last frame released from memory
  /// (their memory kept), or an empty frame.
  StateFrame spare();

  int size() const { return static_cast<int>(Frames.size()); }
  /// Frames kept whole in memory at most (the others only by time and energy).
  int window() const { return Window; }
  bool inMemory(int index) const;
  /// Frame `index` as kept: whole when inMemory(index), else only its time and energy.
  const StateFrame& frame(int index) const { return Frames.at(index); }
  /// Frame `index` whole, from memory or read back from the state file (under MPI,
  /// collective when it is not in memory: every rank reads its piece).
  Status read(int index, StateFrame& out) const;
  /// The newest frame's size (every frame has the same).
  double bytesPerFrame() const { return Frames.empty() ? 0 : bytesOf(Frames.back()); }
  /// The whole run's header, and that of this rank's strands (the same without MPI).
  const StateHeader& header() const { return Header; }
  const StateHeader& piece() const { return Piece; }

private:
  void release(int index);
  /// open()'s and resume()'s: how many frames stay in memory for a run of options.frames
  /// frames of `first`'s size (collective); refuses a run that does not fit.
  Status plan(const StateFrame& first, const StorageOptions& options, const Ranks& ranks);
  /// open()'s and resume()'s: the run's header, this rank's piece of it, ranks and options.
  void keep(const StateHeader& header, const StorageOptions& options, const FileSharing& sharing);
  StateHeader Header, Piece;
  StorageOptions Options;
  Ranks Shared; ///< the ranks of the run (one: this process)
  std::vector<StateFrame> Frames;
  StateFrame Spare; ///< the arrays of the last released frame
  int Window = std::numeric_limits<int>::max();
  int First = 0; ///< the first frame kept whole in memory (a resumed run's are in the file)
  std::unique_ptr<StateFileWriter> Writer;
};

} // namespace hair
