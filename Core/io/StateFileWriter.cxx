// StateFileWriter (StateFile.h): creates the layout that StateFormat.h names, and appends
// frames in an order that leaves a killed run's file readable up to its last whole frame.
#include "io/StateFile.h"

#include "io/Hdf5.h"
#include "io/StateFormat.h"
#include "io/StateGroom.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace hair
{

using namespace hdf5;
namespace sf = stateformat;

namespace
{
/// Creates (truncates) the file for one writer; an invalid handle if it cannot.
Handle createFile(const std::string& path)
{
  Handle file;
  H5E_BEGIN_TRY
  {
    Handle fapl(H5Pcreate(H5P_FILE_ACCESS));
    // The latest format is what single-writer/multiple-reader mode needs.
    H5Pset_libver_bounds(fapl.get(), H5F_LIBVER_LATEST, H5F_LIBVER_LATEST);
    file = Handle(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get()));
  }
  H5E_END_TRY;
  return file;
}

/// The access of a file shared by `ranks`, collectively: parallel HDF5 (MPI-IO) in
/// the library's earliest format, whose superblock has no "open for writing" flag, so that a
/// file whose writers were killed opens in any reader; every object 8-byte aligned, so that
/// the count of whole frames is written in one piece.
Handle sharedAccess(const Ranks& ranks)
{
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS));
  H5Pset_fapl_mpio(fapl.get(), ranks.comm(), MPI_INFO_NULL);
  H5Pset_alignment(fapl.get(), 0, 8);
  H5Pset_all_coll_metadata_ops(fapl.get(), 1);
  H5Pset_coll_metadata_write(fapl.get(), 1);
  return fapl;
}

/// Creates (truncates) the file shared by `ranks`, collectively (sharedAccess).
Handle createSharedFile(const std::string& path, const Ranks& ranks)
{
  Handle file;
  H5E_BEGIN_TRY
  {
    Handle fapl = sharedAccess(ranks);
    file = Handle(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get()));
  }
  H5E_END_TRY;
  return file;
}

/// The root's attributes: the format, its version, the model, and the run attributes.
Status writeRootAttributes(hid_t f, const StateHeader& header, int version)
{
  Status s = writeStringAttribute(f, sf::FormatAttribute, sf::Name);
  if (s)
  {
    s = writeScalarAttribute<int>(f, sf::VersionAttribute, H5T_NATIVE_INT, version);
  }
  if (s)
  {
    s = writeStringAttribute(f, sf::ModelAttribute, header.model);
  }
  if (s)
  {
    s = writeScalarAttribute<int>(f, sf::CoordinatesAttribute, H5T_NATIVE_INT,
                                  header.coordinatesPerStrand);
  }
  for (const auto& [name, value] : header.attributes)
  {
    if (s)
    {
      s = writeScalarAttribute<double>(f, name.c_str(), H5T_NATIVE_DOUBLE, value);
    }
  }
  return s;
}

/// One dataset [S, 3] of /strands per strand vector (created by every rank of a shared
/// file, written by one: `write`).
Status writeStrandVectors(hid_t strands, const StateHeader& header, bool write)
{
  for (const auto& [name, values] : header.strandVectors)
  {
    if (!writeRows(strands, name.c_str(), values.size(), 3,
                   values.empty() ? nullptr : values[0].data(), write))
    {
      return Status::Error("cannot write " + sf::inGroup(sf::Strands, name) + ".");
    }
  }
  return Status::Ok();
}

/// A per-frame dataset: growing by one frame at a time (one writer), or with room for
/// `room` frames from the start (a shared file: Hdf5.h, createFixed; NaN where not written
/// when `fill`).
struct PerFrame
{
  hsize_t room = 0; ///< 0: growing
  Handle make(hid_t parent, const char* name, const std::vector<hsize_t>& frameShape,
              bool fill = false, hid_t type = H5T_NATIVE_DOUBLE) const
  {
    return room == 0 ? createGrowing(parent, name, frameShape, type)
                     : createFixed(parent, name, room, frameShape, fill, type);
  }
};

/// One per-frame array of the file as the writer holds it: its dataset, whether it is kept
/// in single precision, and a buffer for that conversion (reused from frame to frame).
struct Dataset
{
  Handle handle;
  bool single = false;
  std::vector<float> narrow;
  /// The frame's numbers as the dataset takes them: `data` itself, or narrowed.
  const void* values(const double* data, std::size_t count)
  {
    if (!single)
    {
      return data;
    }
    narrow.resize(count);
    for (std::size_t i = 0; i < count; ++i)
    {
      narrow[i] = static_cast<float>(data[i]);
    }
    return narrow.data();
  }
  hid_t memoryType() const { return single ? H5T_NATIVE_FLOAT : H5T_NATIVE_DOUBLE; }
};

/// One dataset of /frames per array of the frame's schema the header has (frameFields(),
/// then the per-point scalars), by path.
Status createFrameArrays(hid_t file, const StateHeader& header, const PerFrame& kind,
                         std::map<std::string, Dataset>& datasets)
{
  for (const std::string& name : header.pointData)
  {
    if (isFrameField(name) ||
        std::count(header.pointData.begin(), header.pointData.end(), name) > 1)
    {
      return Status::Error("the per-point array name '" + name + "' is reserved or repeated.");
    }
  }
  StateFrame none;
  Status made = Status::Ok();
  forEachArray(header, none, false,
               [&](const FrameArray& a)
               {
                 if (!made)
                 {
                   return;
                 }
                 Dataset& d = datasets[a.name];
                 d.single = a.field && a.field->singlePrecision(header);
                 std::vector<hsize_t> shape{a.perPoint ? header.numberOfPoints()
                                                       : header.numberOfStrands()};
                 if (a.field)
                 {
                   shape.push_back(a.width);
                 }
                 d.handle = kind.make(file, a.name.c_str(), shape, false,
                                      d.single ? H5T_NATIVE_FLOAT : H5T_NATIVE_DOUBLE);
                 if (!d.handle.valid())
                 {
                   made = Status::Error("cannot create " + a.name + ".");
                 }
               });
  return made;
}

/// /strands: the offsets, then one dataset per strand parameter and per strand vector.
Status writeStrands(hid_t strands, const StateHeader& header, bool write)
{
  if (!writeArray(strands, sf::Offsets, H5T_NATIVE_INT64, header.offsets.size(),
                  header.offsets.data(), write))
  {
    return Status::Error(std::string("cannot write ") + sf::Offsets + ".");
  }
  for (const auto& [name, values] : header.strandParameters)
  {
    if (!writeArray(strands, name.c_str(), H5T_NATIVE_DOUBLE, values.size(), values.data(), write))
    {
      return Status::Error("cannot write " + sf::inGroup(sf::Strands, name) + ".");
    }
  }
  return writeStrandVectors(strands, header, write);
}

/// One dataset of /energy per term: the required ones and `extraTerms`.
Status createEnergy(hid_t energy, const std::vector<std::string>& extraTerms, const PerFrame& kind,
                    std::map<std::string, Handle>& datasets)
{
  std::vector<std::string> terms(std::begin(RequiredEnergyTerms), std::end(RequiredEnergyTerms));
  for (const auto& t : extraTerms)
  {
    if (std::find(terms.begin(), terms.end(), t) == terms.end())
    {
      terms.push_back(t);
    }
  }
  for (const auto& t : terms)
  {
    datasets[t] = kind.make(energy, t.c_str(), {}, true);
    if (!datasets[t].valid())
    {
      return Status::Error("cannot create " + sf::inGroup(sf::Energy, t) + ".");
    }
  }
  return Status::Ok();
}

/// What a rank of a shared file writes of each per-frame dataset: its rows, as a selection
/// built once (Hdf5.h, RowSelection) and moved to each frame.
struct Piece
{
  Runs points, strands; ///< runs of this rank's points and strands in the file
  std::size_t pointCount = 0, strandCount = 0;
};

/// The runs of consecutive strands of `ids` (increasing), as runs of strands and of points.
Piece pieceOf(const StateHeader& header, const std::vector<std::int64_t>& ids)
{
  Piece p;
  for (std::size_t i = 0; i < ids.size();)
  {
    std::size_t j = i + 1;
    while (j < ids.size() && ids[j] == ids[j - 1] + 1)
    {
      ++j;
    }
    const std::int64_t first = ids[i], last = ids[j - 1] + 1;
    p.strands.emplace_back(hsize_t(first), hsize_t(last - first));
    p.points.emplace_back(hsize_t(header.offsets[first]),
                          hsize_t(header.offsets[last] - header.offsets[first]));
    p.strandCount += std::size_t(last - first);
    p.pointCount += std::size_t(header.offsets[last] - header.offsets[first]);
    i = j;
  }
  return p;
}

/// Whether another process holds `path` open for writing as a shared state file (its rank 0
/// holds a shared lock on it while the run goes on), or it cannot be locked at all.
bool lockedByAnotherRun(const std::string& path)
{
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0)
  {
    return false;
  }
  const bool locked = ::flock(fd, LOCK_EX | LOCK_NB) != 0;
  ::close(fd);
  return locked;
}
} // namespace

struct StateFileWriter::Impl
{
  Handle File, Time;
  std::map<std::string, Dataset> Arrays; ///< the per-frame arrays, by path
  std::map<std::string, Handle> Energy;
  StateHeader Header;
  std::string Path;
  hsize_t Frames = 0;
  // Shared files only.
  FileSharing Sharing;
  StateHeader PieceHeader; ///< this rank's strands (Header.piece)
  Handle WholeFrames;
  /// Per dataset (by its Handle's id), this rank's selection.
  std::map<hid_t, RowSelection> Selections;
  int Lock = -1; ///< rank 0: the file, locked shared while the run writes it
  // The continuation's slots (/resume), when the header keeps room for them: this rank's
  // strand rows of /resume/strands, and a buffer of them (reused from frame to frame).
  Handle ResumeFrame, ResumeStrands, ResumeRun;
  RowSelection ResumeRows;
  std::vector<double> ResumeBuffer;
  /// Writes `c`, frame t's continuation, into slot t mod 2 (collective when shared); `kept`
  /// false when it does not fit the room (the slot is left as it was).
  Status writeContinuation(hsize_t t, const StateContinuation& c, bool& kept,
                           const std::string& where);
  /// Opens or creates /resume's datasets and this rank's rows of them.
  bool openContinuation(hid_t f, bool create);
  /// Shared files: this rank's header (PieceHeader) and its rows of every per-frame dataset
  /// (Selections).
  bool selectPiece();
  /// Shared files, rank 0: the file locked shared while the run writes it (Lock).
  void lock();

  ~Impl()
  {
    if (Lock >= 0)
    {
      ::close(Lock);
    }
  }
  bool shared() const { return Sharing.shared(); }
  Status appendShared(const StateFrame& frame, const std::string& where,
                      const StateContinuation* continuation, bool& kept);
};

namespace
{
/// Writes `count` values into row `row` of a 2-D dataset (or one value at index `row` of a
/// 1-D one), independently of the other ranks.
bool writeRow(hid_t dataset, hsize_t row, hid_t type, const void* values, hsize_t count)
{
  Handle file(H5Dget_space(dataset));
  const int rank = H5Sget_simple_extent_ndims(file.get());
  const hsize_t start[2] = {row, 0}, size[2] = {1, count};
  Handle memory(H5Screate_simple(1, &count, nullptr));
  return rank >= 1 && rank <= 2 &&
         H5Sselect_hyperslab(file.get(), H5S_SELECT_SET, start, nullptr, size, nullptr) >= 0 &&
         H5Dwrite(dataset, type, memory.get(), file.get(), H5P_DEFAULT, values) >= 0;
}
} // namespace

bool StateFileWriter::Impl::selectPiece()
{
  PieceHeader = Header.piece(Sharing.strands);
  const Piece piece = pieceOf(Header, Sharing.strands);
  bool ok = true;
  StateFrame none;
  forEachArray(Header, none, false,
               [&](const FrameArray& a)
               {
                 const Handle& d = Arrays.at(a.name).handle;
                 ok = ok && d.valid() &&
                      Selections[d.get()].build(d.get(), a.perPoint ? piece.points : piece.strands);
               });
  return ok;
}

void StateFileWriter::Impl::lock()
{
  if (Sharing.ranks.rank() == 0)
  {
    Lock = ::open(Path.c_str(), O_RDONLY);
    if (Lock >= 0)
    {
      ::flock(Lock, LOCK_SH | LOCK_NB);
    }
  }
}

bool StateFileWriter::Impl::openContinuation(hid_t f, bool create)
{
  const hsize_t strands = Header.numberOfStrands();
  const hsize_t width = hsize_t(Header.continuationWidth);
  const hsize_t run = hsize_t(std::max(0, Header.continuationRunValues));
  if (create)
  {
    Handle group(H5Gcreate2(f, sf::Resume, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
    ResumeFrame = createFixed(f, sf::ResumeFrame, 2, {}, false, H5T_NATIVE_INT64);
    ResumeStrands = createFixed(f, sf::ResumeStrands, 2, {strands, width}, false);
    ResumeRun = createFixed(f, sf::ResumeRun, 2, {run}, true);
    const std::int64_t none[2] = {-1, -1};
    const bool writes = !shared() || Sharing.ranks.rank() == 0;
    if (!group.valid() || !ResumeFrame.valid() ||
        (writes &&
         H5Dwrite(ResumeFrame.get(), H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, none) < 0))
    {
      return false;
    }
  }
  else
  {
    ResumeFrame = Handle(H5Dopen2(f, sf::ResumeFrame, H5P_DEFAULT));
    ResumeStrands = Handle(H5Dopen2(f, sf::ResumeStrands, H5P_DEFAULT));
    ResumeRun = Handle(H5Dopen2(f, sf::ResumeRun, H5P_DEFAULT));
  }
  if (!ResumeFrame.valid() || !ResumeStrands.valid() || !ResumeRun.valid() ||
      extent(ResumeStrands.get()) != std::vector<hsize_t>{2, strands, width} ||
      extent(ResumeRun.get()) != std::vector<hsize_t>{2, run})
  {
    return false;
  }
  Runs rows;
  if (shared())
  {
    rows = pieceOf(Header, Sharing.strands).strands;
  }
  else
  {
    rows.emplace_back(0, strands);
  }
  return ResumeRows.build(ResumeStrands.get(), rows);
}

Status StateFileWriter::Impl::writeContinuation(hsize_t t, const StateContinuation& c, bool& kept,
                                                const std::string& where)
{
  const Ranks& ranks = Sharing.ranks;
  const std::size_t width = std::size_t(Header.continuationWidth);
  const std::size_t rows = std::size_t(ResumeRows.values / std::max<std::size_t>(width, 1));
  bool fits = c.strands.size() == rows &&
              c.run.size() == std::size_t(std::max(0, Header.continuationRunValues));
  for (std::size_t k = 0; fits && k < rows; ++k)
  {
    fits = c.strands[k].size() + 1 <= width;
  }
  kept = !(shared() ? ranks.any(!fits) : !fits);
  if (!kept)
  {
    return Status::Ok(); // the slot keeps the continuation of two frames before
  }
  ResumeBuffer.assign(rows * width, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t k = 0; k < rows; ++k)
  {
    double* row = ResumeBuffer.data() + k * width;
    row[0] = double(c.strands[k].size());
    std::copy(c.strands[k].begin(), c.strands[k].end(), row + 1);
  }
  const hsize_t slot = t % 2;
  const bool writer = !shared() || ranks.rank() == 0;
  const std::int64_t none = -1, frame = std::int64_t(t);
  const hid_t f = File.get();
  bool ok = true;
  H5E_BEGIN_TRY
  {
    // The slot says "none" before its numbers change, and names the frame once they are
    // all in the file: a run killed between the two leaves the other slot, the last whole
    // frame's, to resume from.
    ok = !writer || writeRow(ResumeFrame.get(), slot, H5T_NATIVE_INT64, &none, 1);
    ok = ok && (shared() || H5Fflush(f, H5F_SCOPE_GLOBAL) >= 0);
  }
  H5E_END_TRY;
  const std::string failed =
      where + "writing its continuation failed (is the disk full?); the frames before it are kept.";
  if (Status st = shared() ? ranks.agree(ok ? Status::Ok() : Status::Error(failed))
                           : (ok ? Status::Ok() : Status::Error(failed));
      !st)
  {
    return st;
  }
  H5E_BEGIN_TRY
  {
    Handle xfer(H5Pcreate(H5P_DATASET_XFER));
    if (shared())
    {
      H5Pset_dxpl_mpio(xfer.get(), H5FD_MPIO_COLLECTIVE);
    }
    ok = ResumeRows.moveToFrame(slot) &&
         H5Dwrite(ResumeStrands.get(), H5T_NATIVE_DOUBLE, ResumeRows.memory.get(),
                  ResumeRows.file.get(), xfer.get(),
                  ResumeBuffer.empty() ? nullptr : ResumeBuffer.data()) >= 0;
    if (writer && !c.run.empty())
    {
      ok = ok && writeRow(ResumeRun.get(), slot, H5T_NATIVE_DOUBLE, c.run.data(), c.run.size());
    }
    ok = ok && (shared() || H5Fflush(f, H5F_SCOPE_GLOBAL) >= 0);
  }
  H5E_END_TRY;
  if (Status st = shared() ? ranks.agree(ok ? Status::Ok() : Status::Error(failed))
                           : (ok ? Status::Ok() : Status::Error(failed));
      !st)
  {
    return st;
  }
  H5E_BEGIN_TRY
  {
    ok = !writer || writeRow(ResumeFrame.get(), slot, H5T_NATIVE_INT64, &frame, 1);
  }
  H5E_END_TRY;
  return ok ? Status::Ok() : Status::Error(failed);
}

StateFileWriter::StateFileWriter() : P(std::make_unique<Impl>()) {}
StateFileWriter::~StateFileWriter()
{
  close();
}
bool StateFileWriter::isOpen() const
{
  return P->File.valid();
}
bool StateFileWriter::shared() const
{
  return P->File.valid() && P->shared();
}
std::int64_t StateFileWriter::numberOfFrames() const
{
  return std::int64_t(P->Frames);
}

namespace
{
/// The check of create(): what is at `path` already, and whether it may be replaced.
Status checkExisting(const std::string& path, StateFileWriter::Existing existing)
{
  struct stat info;
  if (::stat(path.c_str(), &info) != 0)
  {
    return Status::Ok();
  }
  if (!S_ISREG(info.st_mode))
  {
    return Status::Error("exists and is not a regular file: not written over; choose another "
                         "name.");
  }
  if (lockedByAnotherRun(path))
  {
    return Status::Error("is locked: another run is writing it; it is not written over, choose "
                         "another name.");
  }
  StateFileReader old;
  if (Status s = old.open(path); !s)
  {
    return Status::Error("exists and is not a HairDynamics state file that can be read (" +
                         s.message() +
                         "), or another run is writing it: it is not written over; choose "
                         "another name.");
  }
  if (existing != StateFileWriter::Existing::ReplaceStateFile)
  {
    return Status::Error("exists (a state file of " + std::to_string(old.numberOfFrames()) +
                         " frames): it is kept; choose another name, or allow the run to "
                         "replace it (Hair Simulation's Overwrite State File).");
  }
  return Status::Ok();
}
} // namespace

Status StateFileWriter::create(const std::string& path, const StateHeader& header,
                               const std::vector<std::string>& extraEnergyTerms, Existing existing,
                               const FileSharing& sharing)
{
  close();
  const Ranks& ranks = sharing.ranks;
  const bool shared = sharing.shared();
  auto fail = [&](const std::string& what)
  {
    P = std::make_unique<Impl>();
    return Status::Error("the state file '" + path + "': " + what);
  };
  Status valid = header.validate();
  if (valid && shared)
  {
    const std::vector<std::int64_t>& ids = sharing.strands;
    if (sharing.frames < 1)
    {
      valid = Status::Error("a shared state file needs the number of frames of the run.");
    }
    for (std::size_t i = 0; valid && i < ids.size(); ++i)
    {
      if (ids[i] < 0 || std::size_t(ids[i]) >= header.numberOfStrands() ||
          (i > 0 && ids[i] <= ids[i - 1]))
      {
        valid = Status::Error("this rank's strands must be increasing numbers of the run's " +
                              std::to_string(header.numberOfStrands()) + " strands.");
      }
    }
  }
  if (Status s = ranks.agree(valid); !s)
  {
    return shared ? fail(s.message()) : s;
  }
  // What is at the path: looked at by one rank, the answer given to all.
  Status there = ranks.rank() == 0 ? checkExisting(path, existing) : Status::Ok();
  if (Status s = shared ? ranks.agree(there) : there; !s)
  {
    return fail(s.message());
  }
  P->File = shared ? createSharedFile(path, ranks) : createFile(path);
  if (Status s = ranks.agree(P->File.valid() ? Status::Ok() : Status::Error(""));
      !s || !P->File.valid())
  {
    return fail("cannot be created: check that its folder exists and is writable, and that no "
                "other run is writing the same file.");
  }
  P->Header = header;
  P->Path = path;
  P->Sharing = sharing;
  const bool writes = !shared || ranks.rank() == 0; // who writes what every rank has
  const hid_t f = P->File.get();
  // HDF5's error stack is never printed: each failure is returned as a message.
  Status made = Status::Ok();
  H5E_BEGIN_TRY
  {
    made = [&]() -> Status
    {
      if (Status s = writeRootAttributes(f, header, sf::Version); !s)
      {
        return s;
      }
      Handle strands(H5Gcreate2(f, sf::Strands, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
      Handle frames(H5Gcreate2(f, sf::Frames, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
      Handle energy(H5Gcreate2(f, sf::Energy, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
      if (Status s = writeStrands(strands.get(), header, writes); !s)
      {
        return s;
      }
      if (Status s = detail::writeGroom(f, header); !s)
      {
        return s;
      }
      const PerFrame kind{shared ? hsize_t(sharing.frames) : 0};
      P->Time = kind.make(f, sf::Time, {}, true);
      if (!P->Time.valid())
      {
        return Status::Error(std::string("cannot create ") + sf::Time + ".");
      }
      if (Status s = createFrameArrays(f, header, kind, P->Arrays); !s)
      {
        return s;
      }
      if (Status s = createEnergy(energy.get(), extraEnergyTerms, kind, P->Energy); !s)
      {
        return s;
      }
      if (header.continuationWidth > 0 && !P->openContinuation(f, true))
      {
        return Status::Error(std::string("cannot create ") + sf::Resume + ".");
      }
      return Status::Ok();
    }();
  }
  H5E_END_TRY;
  // Every rank creates the datasets together (collective under MPI): a failure on one is
  // every rank's.
  if (Status s = shared ? ranks.agree(made) : made; !s)
  {
    return fail(s.message());
  }
  if (!shared)
  {
    herr_t swmr;
    H5E_BEGIN_TRY
    {
      swmr = H5Fstart_swmr_write(f);
    }
    H5E_END_TRY;
    if (swmr < 0)
    {
      return fail("cannot start single-writer/multiple-reader mode.");
    }
    return Status::Ok();
  }

  // Shared: the count of whole frames (0), this rank's selections, and then the file's whole
  // structure written and flushed, once: frames write raw data only.
  bool ok = true;
  H5E_BEGIN_TRY
  {
    Handle space(H5Screate(H5S_SCALAR));
    Handle props(H5Pcreate(H5P_DATASET_CREATE));
    H5Pset_layout(props.get(), H5D_CONTIGUOUS);
    H5Pset_alloc_time(props.get(), H5D_ALLOC_TIME_EARLY);
    H5Pset_obj_track_times(props.get(), 0);
    const std::int64_t zero = 0;
    H5Pset_fill_value(props.get(), H5T_NATIVE_INT64, &zero);
    H5Pset_fill_time(props.get(), H5D_FILL_TIME_ALLOC);
    P->WholeFrames = Handle(H5Dcreate2(f, sf::WholeFrames, H5T_NATIVE_INT64, space.get(),
                                       H5P_DEFAULT, props.get(), H5P_DEFAULT));
    ok = P->WholeFrames.valid() && P->selectPiece();
    ok = ok && H5Fflush(f, H5F_SCOPE_GLOBAL) >= 0;
  }
  H5E_END_TRY;
  if (Status s = ranks.agree(ok ? Status::Ok() : Status::Error("cannot create its datasets.")); !s)
  {
    return fail(s.message());
  }
  P->lock();
  return Status::Ok();
}

namespace
{
/// Opens an existing state file for writing: shared by `ranks` (MPI-IO, as createSharedFile),
/// or by one writer, clearing the mark an unclosed single-writer file keeps in its superblock
/// (as HDF5's h5clear does: the run that wrote it was killed). Invalid if it cannot.
Handle openForWriting(const std::string& path, const Ranks& ranks, bool shared)
{
  Handle file;
  H5E_BEGIN_TRY
  {
    Handle fapl = shared ? sharedAccess(ranks) : Handle(H5Pcreate(H5P_FILE_ACCESS));
    if (!shared)
    {
      H5Pset_libver_bounds(fapl.get(), H5F_LIBVER_LATEST, H5F_LIBVER_LATEST);
      hbool_t clear = 1;
      H5Pset(fapl.get(), "clear_status_flags", &clear);
    }
    file = Handle(H5Fopen(path.c_str(), H5F_ACC_RDWR, fapl.get()));
  }
  H5E_END_TRY;
  return file;
}
} // namespace

Status StateFileWriter::reopen(const std::string& path, const StateHeader& header,
                               const std::vector<std::string>& extraEnergyTerms, std::int64_t keep,
                               const FileSharing& sharing)
{
  close();
  const Ranks& ranks = sharing.ranks;
  const bool shared = sharing.shared();
  auto fail = [&](const std::string& what)
  {
    P = std::make_unique<Impl>();
    return Status::Error("the state file '" + path + "': " + what);
  };
  Status there = header.validate();
  if (there && keep < 1)
  {
    there = Status::Error("a run is resumed after at least one frame.");
  }
  if (there && ranks.rank() == 0 && lockedByAnotherRun(path))
  {
    there = Status::Error("is locked: another run is writing it; it is resumed once that run "
                          "has stopped.");
  }
  if (Status s = ranks.agree(there); !s)
  {
    return fail(s.message());
  }
  P->File = openForWriting(path, ranks, shared);
  if (Status s = ranks.agree(P->File.valid() ? Status::Ok() : Status::Error(""));
      !s || !P->File.valid())
  {
    return fail("cannot be opened for writing: check that it is writable and that no other "
                "process has it open.");
  }
  // A file grows in SWMR mode when one process writes it, and has room for the run's frames
  // when MPI ranks write it together (/whole_frames): it goes on as it was written.
  htri_t counted = -1;
  H5E_BEGIN_TRY
  {
    counted = H5Lexists(P->File.get(), sf::WholeFrames, H5P_DEFAULT);
  }
  H5E_END_TRY;
  Status kind = Status::Ok();
  if (counted > 0 && !shared)
  {
    kind = Status::Error("was written by MPI ranks together (with room for the run's frames "
                         "from the start): it is resumed under MPI, on 2 ranks or more.");
  }
  else if (counted == 0 && shared)
  {
    kind = Status::Error("was written by one process (it grows as frames are added): it is "
                         "resumed by one process, not by " +
                         std::to_string(ranks.size()) + " MPI ranks.");
  }
  if (Status s = ranks.agree(kind); !s)
  {
    return fail(s.message());
  }
  P->Header = header;
  P->Path = path;
  P->Sharing = sharing;
  const hid_t f = P->File.get();
  bool ok = true;
  H5E_BEGIN_TRY
  {
    auto open = [&](Handle& d, const std::string& name)
    {
      d = Handle(H5Dopen2(f, name.c_str(), H5P_DEFAULT));
      ok = ok && d.valid();
    };
    open(P->Time, sf::Time);
    StateFrame none;
    forEachArray(header, none, false,
                 [&](const FrameArray& a)
                 {
                   Dataset& d = P->Arrays[a.name];
                   d.single = a.field && a.field->singlePrecision(header);
                   open(d.handle, a.name);
                 });
    std::vector<std::string> terms(std::begin(RequiredEnergyTerms), std::end(RequiredEnergyTerms));
    terms.insert(terms.end(), extraEnergyTerms.begin(), extraEnergyTerms.end());
    for (const std::string& t : terms)
    {
      open(P->Energy[t], sf::inGroup(sf::Energy, t));
    }
    ok = ok && (header.continuationWidth < 1 || P->openContinuation(f, false));
  }
  H5E_END_TRY;
  if (Status s = ranks.agree(ok ? Status::Ok()
                                : Status::Error("its datasets are not those of this run's "
                                                "frames: it cannot be continued."));
      !s)
  {
    return fail(s.message());
  }
  if (!shared)
  {
    // The frames after the kept ones (a frame being written when the run stopped) dropped.
    H5E_BEGIN_TRY
    {
      auto cut = [&](const Handle& d)
      {
        std::vector<hsize_t> dims = extent(d.get());
        ok = ok && !dims.empty() && dims[0] >= hsize_t(keep);
        if (ok)
        {
          dims[0] = hsize_t(keep);
          ok = H5Dset_extent(d.get(), dims.data()) >= 0;
        }
      };
      cut(P->Time);
      for (auto& [name, d] : P->Arrays)
      {
        cut(d.handle);
      }
      for (auto& [name, d] : P->Energy)
      {
        cut(d);
      }
      ok = ok && H5Fflush(f, H5F_SCOPE_GLOBAL) >= 0 && H5Fstart_swmr_write(f) >= 0;
    }
    H5E_END_TRY;
    if (!ok)
    {
      return fail("its frames after frame " + std::to_string(keep - 1) +
                  " cannot be dropped, or single-writer/multiple-reader mode cannot start.");
    }
    P->Frames = hsize_t(keep);
    return Status::Ok();
  }

  // Shared: the room the file was made with, then the count of whole frames set back to
  // `keep` (the frames after it are written over), and this rank's selections.
  const std::vector<hsize_t> room = extent(P->Time.get());
  Status roomy = Status::Ok();
  if (room.empty() || std::int64_t(room[0]) < sharing.frames)
  {
    roomy = Status::Error("has room for " + std::to_string(room.empty() ? 0 : room[0]) +
                          " frames (the run it was started for), and this run would have " +
                          std::to_string(sharing.frames) +
                          ": resume with a Duration that ends within the room, or start a new "
                          "run.");
  }
  if (Status s = ranks.agree(roomy); !s)
  {
    return fail(s.message());
  }
  H5E_BEGIN_TRY
  {
    P->WholeFrames = Handle(H5Dopen2(f, sf::WholeFrames, H5P_DEFAULT));
    ok = P->WholeFrames.valid();
    if (ok && ranks.rank() == 0)
    {
      const std::int64_t whole = keep;
      ok = H5Dwrite(P->WholeFrames.get(), H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT,
                    &whole) >= 0;
    }
    ok = ok && P->selectPiece();
  }
  H5E_END_TRY;
  if (Status s = ranks.agree(ok ? Status::Ok()
                                : Status::Error("its count of whole frames cannot be set back."));
      !s)
  {
    return fail(s.message());
  }
  P->Frames = hsize_t(keep);
  P->lock();
  return Status::Ok();
}

namespace
{
/// The checks of append() on a frame of the strands `h` describes (a rank's piece of a
/// shared file); `where` names the file and the frame.
Status checkFrame(const StateHeader& h, const std::map<std::string, Handle>& energy,
                  const StateFrame& frame, const std::string& where)
{
  if (!std::isfinite(frame.time))
  {
    return Status::Error(where + "its time is not finite.");
  }
  Status checked = Status::Ok();
  forEachArray(h, frame,
               [&](const FrameArray& a)
               {
                 if (!checked)
                 {
                   return;
                 }
                 const std::size_t want = a.rowsIn(h) * a.width;
                 if (a.size != want)
                 {
                   checked = Status::Error(where + a.name + ": expected " + std::to_string(want) +
                                           " values, got " + std::to_string(a.size) + ".");
                 }
                 else if (a.firstNonFinite() < a.size)
                 {
                   checked = Status::Error(where + "NaN or infinite values in " + a.name +
                                           ": the frame is not written, the frames before it "
                                           "are kept.");
                 }
               });
  if (!checked)
  {
    return checked;
  }
  for (const auto& [name, value] : frame.energy)
  {
    if (energy.find(name) == energy.end())
    {
      return Status::Error(where + "the energy term '" + name +
                           "' was not declared when the file was created.");
    }
  }
  return Status::Ok();
}

/// Writes one scalar of a frame at t of a shared file's dataset (the writing rank only).
bool writeScalar(hid_t dataset, hsize_t t, hid_t type, const void* value)
{
  Handle file(H5Dget_space(dataset));
  const int rank = H5Sget_simple_extent_ndims(file.get());
  if (rank > 0)
  {
    const hsize_t one = 1;
    H5Sselect_hyperslab(file.get(), H5S_SELECT_SET, &t, nullptr, &one, nullptr);
  }
  const hsize_t one = 1;
  Handle memory(H5Screate_simple(1, &one, nullptr));
  return H5Dwrite(dataset, type, memory.get(), file.get(), H5P_DEFAULT, value) >= 0;
}
} // namespace

Status StateFileWriter::append(const StateFrame& frame, const StateContinuation* continuation,
                               bool* continuationKept)
{
  bool kept = false;
  if (continuationKept)
  {
    *continuationKept = false;
  }
  if (!P->File.valid())
  {
    return Status::Error("the state file is not open: create it first.");
  }
  const std::string where = "the state file '" + P->Path + "', frame " + std::to_string(P->Frames) +
                            " (t = " + std::to_string(frame.time) + " s): ";
  const bool continues = continuation && P->ResumeFrame.valid();
  if (P->shared())
  {
    Status s = P->appendShared(frame, where, continues ? continuation : nullptr, kept);
    if (s && continuationKept)
    {
      *continuationKept = kept;
    }
    return s;
  }
  const StateHeader& h = P->Header;
  if (Status s = checkFrame(h, P->Energy, frame, where); !s)
  {
    return s;
  }
  const hsize_t t = P->Frames;
  if (continues)
  {
    if (Status s = P->writeContinuation(t, *continuation, kept, where); !s)
    {
      return s;
    }
  }
  bool ok = true;
  H5E_BEGIN_TRY
  {
    forEachArray(h, frame,
                 [&](const FrameArray& a)
                 {
                   Dataset& d = P->Arrays.at(a.name);
                   ok = ok &&
                        appendSlab(d.handle.get(), t, d.values(a.data, a.size), d.memoryType());
                 });
    for (auto& [name, dataset] : P->Energy)
    {
      if (ok)
      {
        const auto it = frame.energy.find(name);
        const double value = it == frame.energy.end() ? 0.0 : it->second;
        ok = appendSlab(dataset.get(), t, &value);
      }
    }
    // The frame's data reach the disk before /time names the frame: /time's length is the
    // number of whole frames.
    ok = ok && H5Fflush(P->File.get(), H5F_SCOPE_GLOBAL) >= 0;
    ok = ok && appendSlab(P->Time.get(), t, &frame.time);
    ok = ok && H5Fflush(P->File.get(), H5F_SCOPE_GLOBAL) >= 0;
  }
  H5E_END_TRY;
  if (!ok)
  {
    return Status::Error(where + "writing failed (is the disk full?); the frames before it are "
                                 "kept.");
  }
  ++P->Frames;
  if (continuationKept)
  {
    *continuationKept = kept;
  }
  return Status::Ok();
}

Status StateFileWriter::Impl::appendShared(const StateFrame& frame, const std::string& where,
                                           const StateContinuation* continuation, bool& kept)
{
  const Ranks& ranks = Sharing.ranks;
  const StateHeader& h = PieceHeader;
  Status checked = checkFrame(h, Energy, frame, where);
  if (checked && Frames >= hsize_t(Sharing.frames))
  {
    checked = Status::Error(where + "the file has room for the run's " +
                            std::to_string(Sharing.frames) + " frames only.");
  }
  // A frame one rank refuses is written by none: no rank is left in a collective write.
  if (Status s = ranks.agree(checked); !s)
  {
    return s;
  }
  const hsize_t t = Frames;
  const bool writer = ranks.rank() == 0;
  if (continuation)
  {
    if (Status s = writeContinuation(t, *continuation, kept, where); !s)
    {
      return s;
    }
  }
  bool ok = true;
  H5E_BEGIN_TRY
  {
    Handle collective(H5Pcreate(H5P_DATASET_XFER));
    H5Pset_dxpl_mpio(collective.get(), H5FD_MPIO_COLLECTIVE);
    forEachArray(h, frame,
                 [&](const FrameArray& a)
                 {
                   Dataset& d = Arrays.at(a.name);
                   RowSelection& sel = Selections.at(d.handle.get());
                   ok = ok && sel.moveToFrame(t) &&
                        H5Dwrite(d.handle.get(), d.memoryType(), sel.memory.get(), sel.file.get(),
                                 collective.get(), d.values(a.data, a.size)) >= 0;
                 });
    // The run's numbers of the frame (the same on every rank): written by one.
    if (writer)
    {
      for (auto& [name, dataset] : Energy)
      {
        const auto it = frame.energy.find(name);
        const double value = it == frame.energy.end() ? 0.0 : it->second;
        ok = ok && writeScalar(dataset.get(), t, H5T_NATIVE_DOUBLE, &value);
      }
      ok = ok && writeScalar(Time.get(), t, H5T_NATIVE_DOUBLE, &frame.time);
    }
  }
  H5E_END_TRY;
  // Every rank's part of the frame is written (the collective writes have returned on every
  // rank, aggregators included) before the count says the frame is whole.
  const std::string failed =
      where + "writing failed (is the disk full?); the frames before it are kept.";
  if (Status s = ranks.agree(ok ? Status::Ok() : Status::Error(failed)); !s)
  {
    return s;
  }
  if (writer)
  {
    const std::int64_t whole = std::int64_t(t) + 1;
    H5E_BEGIN_TRY
    {
      ok = writeScalar(WholeFrames.get(), 0, H5T_NATIVE_INT64, &whole);
    }
    H5E_END_TRY;
  }
  if (Status s = ranks.agree(ok ? Status::Ok() : Status::Error(failed)); !s)
  {
    return s;
  }
  ++Frames;
  return Status::Ok();
}

Status StateFileWriter::readPiece(std::int64_t index, StateFrame& frame) const
{
  if (!shared())
  {
    return Status::Error("only a shared state file is read back through its writer.");
  }
  if (index < 0 || hsize_t(index) >= P->Frames)
  {
    return Status::Error("the state file '" + P->Path + "' has " + std::to_string(P->Frames) +
                         " whole frames; frame " + std::to_string(index) + " does not exist.");
  }
  const StateHeader& h = P->PieceHeader;
  const hsize_t t = hsize_t(index);
  StateFrame out;
  bool ok = true;
  H5E_BEGIN_TRY
  {
    Handle collective(H5Pcreate(H5P_DATASET_XFER));
    H5Pset_dxpl_mpio(collective.get(), H5FD_MPIO_COLLECTIVE);
    forEachArray(h, out, true,
                 [&](const FrameArray& a)
                 {
                   const Handle& d = P->Arrays.at(a.name).handle;
                   RowSelection& sel = P->Selections.at(d.get());
                   ok = ok && sel.values == a.size && sel.moveToFrame(t) &&
                        H5Dread(d.get(), H5T_NATIVE_DOUBLE, sel.memory.get(), sel.file.get(),
                                collective.get(), a.data) >= 0;
                 });
    // The run's numbers, written by rank 0: read by every rank.
    auto scalar = [&](const Handle& d, double& value)
    {
      Handle file(H5Dget_space(d.get()));
      const hsize_t one = 1;
      H5Sselect_hyperslab(file.get(), H5S_SELECT_SET, &t, nullptr, &one, nullptr);
      Handle memory(H5Screate_simple(1, &one, nullptr));
      ok = ok &&
           H5Dread(d.get(), H5T_NATIVE_DOUBLE, memory.get(), file.get(), H5P_DEFAULT, &value) >= 0;
    };
    scalar(P->Time, out.time);
    for (auto& [name, dataset] : P->Energy)
    {
      scalar(dataset, out.energy[name]);
    }
  }
  H5E_END_TRY;
  if (Status s = P->Sharing.ranks.agree(ok ? Status::Ok()
                                           : Status::Error("the state file '" + P->Path +
                                                           "': frame " + std::to_string(index) +
                                                           " cannot be read back."));
      !s)
  {
    return s;
  }
  frame = std::move(out);
  return Status::Ok();
}

Status StateFileWriter::close()
{
  if (!P->File.valid())
  {
    return Status::Ok();
  }
  P->Energy.clear();
  P->Arrays.clear();
  P->Selections.clear();
  P->Time.reset();
  P->WholeFrames.reset();
  P->ResumeRows = RowSelection();
  P->ResumeFrame.reset();
  P->ResumeStrands.reset();
  P->ResumeRun.reset();
  // A shared file is closed collectively; after MPI_Finalize (a writer outliving it) HDF5
  // has closed it already, at MPI_Finalize. Its structure has been on disk since create().
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!P->shared() || !finalized)
  {
    P->File.reset();
  }
  P = std::make_unique<Impl>();
  return Status::Ok();
}

} // namespace hair
