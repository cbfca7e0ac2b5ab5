#include "simulation/FrameStore.h"

#include "simulation/GuideDrawing.h"

#include <cmath>
#include <cstdio>

namespace hair
{

namespace
{
std::string inBytes(double bytes)
{
  char s[32];
  if (bytes >= 1024.0 * 1024 * 1024)
  {
    std::snprintf(s, sizeof s, "%.1f GiB", bytes / (1024.0 * 1024 * 1024));
  }
  else
  {
    std::snprintf(s, sizeof s, "%.2f MiB", bytes / (1024.0 * 1024));
  }
  return s;
}
} // namespace

FrameStore::FrameStore() = default;
FrameStore::~FrameStore() = default;

double FrameStore::bytesOf(const StateFrame& f)
{
  double bytes = sizeof(StateFrame);
  for (const FrameField& field : frameFields())
  {
    bytes += sizeof(double) * double(field.count(f));
  }
  for (const auto& [name, values] : f.pointData)
  {
    bytes += name.size() + sizeof(double) * double(values.size());
  }
  for (const auto& [name, value] : f.energy)
  {
    bytes += name.size() + sizeof(value);
  }
  return bytes;
}

Status FrameStore::checkMemory(int frames, double perFrame, double budget, std::size_t points)
{
  const double need = perFrame * std::max(frames, 0);
  if (need <= budget)
  {
    return Status::Ok();
  }
  return Status::Error("the run's " + std::to_string(frames) + " frames of " +
                       std::to_string(points) + " points would need " + inBytes(need) +
                       " of memory (" + inBytes(perFrame) + " per frame), more than the " +
                       inBytes(budget) +
                       " allowed; run fewer frames, use fewer strands or elements, allow more "
                       "memory, or give a state file: the frames beyond the budget are then "
                       "kept in the file only, and read back from it when asked for.");
}

Status FrameStore::plan(const StateFrame& first, const StorageOptions& options, const Ranks& ranks)
{
  close();
  Frames.clear();
  Window = std::numeric_limits<int>::max();
  First = 0;
  const double perFrame = bytesOf(first);
  double window = std::numeric_limits<double>::infinity();
  Status fits = Status::Ok();
  if (options.frames > 0)
  {
    if (Status s =
            checkMemory(options.frames, perFrame, options.memoryBudget, first.positions.size());
        !s)
    {
      window = std::floor(options.memoryBudget / std::max(perFrame, 1.0));
      if (options.stateFile.empty())
      {
        fits = s;
      }
      else if (window < 2)
      {
        fits = Status::Error(s.message() + " Even streaming to the state file needs two "
                                           "frames in memory.");
      }
    }
  }
  // Every rank keeps the same frames in memory: the smallest window any rank needs.
  if (Status s = ranks.agree(fits); !s)
  {
    return s;
  }
  ranks.min(&window, 1);
  if (std::isfinite(window))
  {
    Window = static_cast<int>(std::min(window, double(options.frames)));
  }
  return Status::Ok();
}

Status FrameStore::open(const StateHeader& header, const std::vector<std::string>& extra,
                        StateFrame first, const StorageOptions& options, const FileSharing& sharing,
                        const StateContinuation* continuation)
{
  const Ranks& ranks = sharing.ranks;
  if (Status s = plan(first, options, ranks); !s)
  {
    return s;
  }
  if (!options.stateFile.empty())
  {
    auto writer = std::make_unique<StateFileWriter>();
    FileSharing file = sharing;
    file.frames = options.frames;
    Status s = writer->create(options.stateFile, header, extra,
                              options.replaceStateFile ? StateFileWriter::Existing::ReplaceStateFile
                                                       : StateFileWriter::Existing::Refuse,
                              file);
    s = s ? writer->append(first, continuation) : s;
    if (!s)
    {
      return s;
    }
    Writer = std::move(writer);
  }
  keep(header, options, sharing);
  Frames.push_back(std::move(first));
  return Status::Ok();
}

void FrameStore::keep(const StateHeader& header, const StorageOptions& options,
                      const FileSharing& sharing)
{
  Header = header;
  Piece = sharing.shared() ? header.piece(sharing.strands) : header;
  Shared = sharing.ranks;
  Options = options;
}

Status FrameStore::resume(const StateHeader& header, const std::vector<std::string>& extra,
                          std::vector<StateFrame> frames, const StorageOptions& options,
                          const FileSharing& sharing)
{
  const Ranks& ranks = sharing.ranks;
  if (frames.empty())
  {
    return Status::Error("a resumed run needs the frames it resumes after.");
  }
  if (Status s = plan(frames.back(), options, ranks); !s)
  {
    return s;
  }
  auto writer = std::make_unique<StateFileWriter>();
  FileSharing file = sharing;
  file.frames = options.frames;
  if (Status s = writer->reopen(options.stateFile, header, extra,
                                static_cast<std::int64_t>(frames.size()), file);
      !s)
  {
    return s;
  }
  Writer = std::move(writer);
  keep(header, options, sharing);
  Frames = std::move(frames);
  First = size() - 1;
  return Status::Ok();
}

Status FrameStore::add(StateFrame frame, const StateContinuation* continuation)
{
  Status written = Status::Ok();
  if (Writer)
  {
    written = Writer->append(frame, continuation);
    if (!written)
    {
      Writer.reset();
    }
  }
  Frames.push_back(std::move(frame));
  if (Window < std::numeric_limits<int>::max())
  {
    if (!written || !Writer)
    {
      // Streaming without a file would lose the frames that leave the window: keep them
      // and stop.
      return Status::Error(
          (written ? std::string("the state file ") + Options.stateFile + " is closed"
                   : written.message()) +
          "; this run does not fit in memory without it: stopped at t = " +
          std::to_string(Frames.back().time) + " s (the frames before it are in the file).");
    }
    release(size() - 1 - Window);
  }
  return written;
}

void FrameStore::close()
{
  if (Writer)
  {
    Writer->close();
    Writer.reset();
  }
}

bool FrameStore::inMemory(int index) const
{
  // The frames older than the window are released (the same ones on every rank).
  (void)Frames.at(index);
  return index >= First && (Window == std::numeric_limits<int>::max() || index >= size() - Window);
}

void FrameStore::release(int index)
{
  if (index < 0 || index + 1 >= size())
  {
    return; // unknown, or the newest frame
  }
  // Its time and energy stay; its arrays become the spare frame the next one is written
  // into (spare()), so that a run streaming to its file touches no new memory per frame.
  StateFrame& f = Frames[index];
  StateFrame kept;
  kept.time = f.time;
  kept.energy.swap(f.energy);
  Spare = std::move(f);
  f = std::move(kept);
}

StateFrame FrameStore::spare()
{
  StateFrame s = std::move(Spare);
  Spare = StateFrame();
  return s;
}

Status FrameStore::read(int index, StateFrame& out) const
{
  if (index < 0 || index >= size())
  {
    return Status::Error("there is no frame " + std::to_string(index) + " (the run has " +
                         std::to_string(size()) + ").");
  }
  if (inMemory(index))
  {
    out = Frames[index];
    return Status::Ok();
  }
  Status s = Status::Ok();
  if (Writer && Writer->shared())
  {
    // Read through the file the ranks write (collective: every rank its piece).
    s = Writer->readPiece(index, out);
  }
  else
  {
    // Opened for each such request: the file grows while the run goes on.
    StateFileReader reader;
    s = reader.open(Options.stateFile);
    s = s ? reader.readFrame(index, out) : s;
  }
  // The file keeps a Super-Helix's nodes in single precision: drawn again from the state,
  // the frame is the one the run kept, bit for bit.
  s = s ? restoreNodes(Piece, out) : s;
  if (!s)
  {
    return Status::Error("frame " + std::to_string(index) +
                         " (t = " + std::to_string(Frames[index].time) +
                         " s) is no longer in memory and could not be read back from " +
                         Options.stateFile + ": " + s.message());
  }
  return Status::Ok();
}

} // namespace hair
