// StateFileReader (StateFile.h): opens a state file in steps, each of which refuses the file
// with a message that says what is wrong, then reads frames on demand.
#include "io/StateFile.h"

#include "common/Partition.h"
#include "io/CheckedReadDriver.h"
#include "io/Hdf5.h"
#include "io/StateFormat.h"
#include "io/StateGroom.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>

namespace hair
{

using namespace hdf5;
namespace sf = stateformat;

namespace
{
/// Metadata read attempts on a single-writer/multiple-reader open. HDF5 retries a metadata
/// read whose checksum fails (it may be one the writer is rewriting) and sleeps between
/// attempts, each sleep twice the one before, from 1 ns; its default of 100 attempts makes a
/// damaged file wait for days (issue 24: one waited 15 minutes and more). 24 attempts wait
/// at most 2^24 ns ≈ 17 ms per metadata object, ample for a writer's flush of one frame.
constexpr unsigned MetadataReadAttempts = 24;

/// The largest ratio of a filtered (compressed) dataset's values to its bytes in the file
/// allowed: deflate's own limit (1032:1, the zlib technical details), the only compression
/// HDF5 builds in.
constexpr double MaxCompression = 1032;

/// What open() reads and readFrame() uses.
struct Contents
{
  Handle File;
  int Version = 0;
  StateHeader Header;
  std::int64_t Frames = 0;
  std::vector<double> Times;
  std::map<std::string, std::vector<double>> Energies;
  /// The file's size and the memory any one read may take (bytes).
  double FileBytes = 0, MemoryBytes = 0;
  /// Why the file's /resume cannot be read (empty: it can, or there is none).
  std::string ContinuationProblem;
  /// Written by several MPI ranks together (/whole_frames counts its whole frames).
  bool Shared = false;
};

/// The datasets every state file has.
struct FixedDatasets
{
  Handle Offsets, Time, Positions, Velocities;
};

Status damaged(const std::string& what)
{
  return Status::Error("is a damaged state file: " + what);
}

std::string megabytes(double bytes)
{
  char text[64];
  std::snprintf(text, sizeof(text), "%.3g MB", bytes / 1e6);
  return text;
}

/// Half this machine's memory: what a single read of a file may take at most.
double memoryForOneRead()
{
  const long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && size > 0 ? 0.5 * double(pages) * double(size) : 4e9;
}

/// What the path names, before HDF5 sees it: a FIFO, a device or a folder would make HDF5
/// block or fail obscurely, so only a readable regular file goes on.
Status checkPath(const std::string& path, double& bytes)
{
  struct stat info;
  if (::stat(path.c_str(), &info) != 0)
  {
    return Status::Error(errno == ENOENT
                             ? std::string("cannot be opened: it does not exist; check the path.")
                             : "cannot be opened (" + std::string(std::strerror(errno)) +
                                   "): check the path.");
  }
  if (S_ISDIR(info.st_mode))
  {
    return Status::Error("is a folder, not a state file: give the path of a .h5 file.");
  }
  if (!S_ISREG(info.st_mode))
  {
    return Status::Error("is not a regular file (a pipe, a device or a socket): it is not read; "
                         "give the path of a state file.");
  }
  if (::access(path.c_str(), R_OK) != 0)
  {
    return Status::Error("cannot be read (" + std::string(std::strerror(errno)) +
                         "): check its permissions.");
  }
  bytes = double(info.st_size);
  return Status::Ok();
}

Status openFile(const std::string& path, Handle& file)
{
  if (H5Fis_hdf5(path.c_str()) <= 0)
  {
    return Status::Error("is not an HDF5 file, so not a HairDynamics state file.");
  }
  // A file still being written (or whose writer was killed) opens in SWMR-read mode, with
  // bounded retries; a file written otherwise (h5py, a copy), or whose SWMR open fails,
  // opens normally (no retries).
  // Both through the checked driver (io/CheckedReadDriver.h), which refuses a damaged
  // global heap before HDF5 decodes it.
  Handle swmr(checkedReadAccess(MetadataReadAttempts));
  if (!swmr.valid())
  {
    return Status::Error("cannot be opened: HDF5 refused HairDynamics' read-only file driver.");
  }
  file = Handle(H5Fopen(path.c_str(), H5F_ACC_RDONLY | H5F_ACC_SWMR_READ, swmr.get()));
  if (!file.valid())
  {
    Handle plain(checkedReadAccess(1));
    file = Handle(plain.valid() ? H5Fopen(path.c_str(), H5F_ACC_RDONLY, plain.get()) : -1);
  }
  if (!file.valid())
  {
    return Status::Error("is damaged or truncated: HDF5 cannot open it.");
  }
  // The driver checks global heaps with 8-byte lengths, what HDF5 (and h5py) write on every
  // 64-bit system; a file with other sizes is not one of ours.
  Handle fcpl(H5Fget_create_plist(file.get()));
  std::size_t addressBytes = 0, lengthBytes = 0;
  if (!fcpl.valid() || H5Pget_sizes(fcpl.get(), &addressBytes, &lengthBytes) < 0 ||
      addressBytes != 8 || lengthBytes != 8)
  {
    file.reset();
    return Status::Error("stores " + std::to_string(addressBytes) + "-byte addresses and " +
                         std::to_string(lengthBytes) +
                         "-byte lengths; a state file has 8-byte ones: it is not a "
                         "HairDynamics state file, or it is damaged.");
  }
  return Status::Ok();
}

/// The root's format and format_version attributes (version 1, or 2: written by several
/// MPI ranks; 3, states at the model's nodes, by one writer or several).
Status checkFormat(hid_t f, int& version)
{
  std::string format;
  if (Status s = readStringAttribute(f, sf::FormatAttribute, format); !s || format != sf::Name)
  {
    return Status::Error(std::string("is an HDF5 file but not a HairDynamics state file (its "
                                     "root needs the attribute ") +
                         sf::FormatAttribute + " = \"" + sf::Name + "\"; " +
                         (s ? "it is \"" + format + "\"" : s.message()) + ").");
  }
  version = 0;
  if (Status s = readIntAttribute(f, sf::VersionAttribute, version); !s)
  {
    return damaged(s.message() + " (the format version, one integer).");
  }
  if (version != sf::Version && version != sf::SharedVersion && version != sf::OneWriterVersion)
  {
    return Status::Error("has state-file format version " + std::to_string(version) +
                         "; this HairDynamics reads versions " +
                         std::to_string(sf::OneWriterVersion) + ", " +
                         std::to_string(sf::SharedVersion) + " and " + std::to_string(sf::Version) +
                         ": open it with the HairDynamics that wrote it.");
  }
  return Status::Ok();
}

constexpr int AnyRank = -1;

/// Opens the dataset at `path` and checks, from its metadata only, that it is an array of
/// numbers (integers when `integers`) of rank `rank` (any: AnyRank).
Status openArray(hid_t f, const std::string& path, int rank, bool integers, Handle& dataset,
                 DatasetInfo& info)
{
  if (H5Lexists(f, path.c_str(), H5P_DEFAULT) <= 0)
  {
    return damaged(path + " is missing.");
  }
  dataset = Handle(H5Dopen2(f, path.c_str(), H5P_DEFAULT));
  if (!dataset.valid())
  {
    return damaged(path + " is not a dataset that can be opened.");
  }
  if (!describe(dataset.get(), info))
  {
    return damaged(path + ": its type or shape cannot be read.");
  }
  const bool number = info.typeClass == H5T_INTEGER || (!integers && info.typeClass == H5T_FLOAT);
  if (!number || info.typeSize < 1 || info.typeSize > 16)
  {
    const char* held = info.typeClass == H5T_FLOAT    ? "floating-point numbers"
                       : info.typeClass == H5T_STRING ? "strings"
                       : info.typeClass == H5T_INTEGER
                           ? "integers of an unusual size"
                           : "values of a compound, array or other non-numeric type";
    return damaged(path + " holds " + held + " where " + (integers ? "integers" : "numbers") +
                   " are expected.");
  }
  if (!info.simple || (rank != AnyRank && int(info.dims.size()) != rank))
  {
    return damaged(path + " has " + std::to_string(info.dims.size()) + " dimensions where " +
                   std::to_string(rank) + " are expected.");
  }
  if (!info.storageMatches)
  {
    return damaged(path + ": the space it has in the file does not hold its values.");
  }
  return Status::Ok();
}

/// Whether reading `values` values of a dataset is sensible before anything is allocated:
/// they must be in the file (no more bytes than the file has, or than deflate could pack
/// into it), its chunks no larger, and the memory at most half this machine's.
Status checkBytes(const Contents& c, const std::string& path, const DatasetInfo& info,
                  double values)
{
  const double inFile = values * double(info.typeSize);
  const double ratio = info.filters > 0 ? MaxCompression : 1.0;
  if (inFile > ratio * c.FileBytes)
  {
    return damaged(path + " declares " + megabytes(inFile) + " of values" +
                   (info.filters > 0 ? " (compressed)" : "") + " but the file has " +
                   megabytes(c.FileBytes) + ".");
  }
  if (values * sizeof(double) > c.MemoryBytes)
  {
    return Status::Error("is too large to read here: " + path + " would take " +
                         megabytes(values * sizeof(double)) +
                         " of memory, more than half of "
                         "this machine's (" +
                         megabytes(2 * c.MemoryBytes) + ").");
  }
  const double chunk = double(info.chunkValues) * double(info.typeSize);
  if (chunk > std::max(1e6, ratio * c.FileBytes))
  {
    return damaged(path + " declares chunks of " + megabytes(chunk) + " in a file of " +
                   megabytes(c.FileBytes) + ".");
  }
  return Status::Ok();
}

/// A dataset of frames, [T', dims…] with T' ≥ the whole frames: checked that T' covers them,
/// that each frame is shaped `frame`, and that every whole frame's values can be read.
Status checkFrames(const Contents& c, const std::string& path, const DatasetInfo& info,
                   const std::vector<hsize_t>& frame)
{
  std::string shape = "[T";
  double perFrame = 1;
  bool same = info.dims.size() == frame.size() + 1;
  for (std::size_t k = 0; k < frame.size(); ++k)
  {
    shape += ", " + std::to_string(frame[k]);
    perFrame *= double(frame[k]);
    same = same && info.dims[k + 1] == frame[k];
  }
  shape += "]";
  if (!same || std::int64_t(info.dims[0]) < c.Frames || info.dims[0] > hsize_t(INT64_MAX))
  {
    std::string dims;
    for (hsize_t d : info.dims)
    {
      dims += (dims.empty() ? "" : ", ") + std::to_string(d);
    }
    return damaged(path + " is [" + dims + "] where " + shape + " with T ≥ " +
                   std::to_string(c.Frames) + " (the length of " + sf::Time + ") is expected.");
  }
  return checkBytes(c, path, info, perFrame * double(c.Frames));
}

/// Reads a whole 1-D dataset of `count` values as doubles, or says it cannot.
Status readValues(hid_t dataset, const std::string& path, hsize_t count, std::vector<double>& v)
{
  v.assign(count, 0.0);
  if (count > 0 && !readFirst(dataset, count, v.data()))
  {
    return damaged(path + " cannot be read.");
  }
  return Status::Ok();
}

/// Every numeric attribute of the root but the format's own is a run attribute.
Status readRunAttributes(hid_t f, std::map<std::string, double>& attributes)
{
  std::vector<std::string> names;
  if (!attributeNames(f, names))
  {
    return damaged("the root's attributes cannot be listed (one of them is damaged).");
  }
  for (const std::string& name : names)
  {
    if (std::find_if(std::begin(sf::RootAttributes), std::end(sf::RootAttributes),
                     [&](const char* x) { return name == x; }) != std::end(sf::RootAttributes))
    {
      continue;
    }
    double value = 0;
    if (readNumericAttribute(f, name.c_str(), value))
    {
      attributes[name] = value;
    }
  }
  return Status::Ok();
}

/// Per-strand parameters and vectors: every other dataset of /strands holding numbers, shaped
/// [S] (a parameter) or [S, 3] (a vector); others are skipped (a later format may add them).
/// Their values must be finite.
Status readStrandData(const Contents& c, hid_t f, StateHeader& header)
{
  Handle strands(H5Gopen2(f, sf::Strands, H5P_DEFAULT));
  std::vector<std::string> names;
  if (!strands.valid() || !linkNames(strands.get(), names))
  {
    return damaged(std::string(sf::Strands) + " cannot be listed.");
  }
  const hsize_t count = header.numberOfStrands();
  for (const std::string& name : names)
  {
    const std::string path = sf::inGroup(sf::Strands, name);
    if (path == sf::Offsets || H5Oexists_by_name(f, path.c_str(), H5P_DEFAULT) <= 0)
    {
      continue;
    }
    H5O_info_t object{};
    if (H5Oget_info_by_name(f, path.c_str(), &object, H5P_DEFAULT) < 0 ||
        object.type != H5O_TYPE_DATASET)
    {
      continue;
    }
    Handle d;
    DatasetInfo info;
    if (!openArray(f, path, AnyRank, false, d, info))
    {
      continue;
    }
    const std::size_t rank = info.dims.size();
    const bool parameter = rank == 1 && info.dims[0] == count;
    const bool vector = rank == 2 && info.dims[0] == count && info.dims[1] == 3;
    if (!parameter && !vector)
    {
      continue;
    }
    if (Status s = checkBytes(c, path, info, double(count) * (vector ? 3 : 1)); !s)
    {
      return s;
    }
    std::vector<double> v(count * (vector ? 3 : 1));
    if (!readWhole(d.get(), H5T_NATIVE_DOUBLE, v.data()))
    {
      return damaged(path + " cannot be read.");
    }
    const auto bad = std::find_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); });
    if (bad != v.end())
    {
      return damaged(path + " holds a NaN or infinite value (strand " +
                     std::to_string((bad - v.begin()) / (vector ? 3 : 1)) + ").");
    }
    if (parameter)
    {
      header.strandParameters[name] = std::move(v);
    }
    else
    {
      std::vector<Eigen::Vector3d> vectors(count);
      for (hsize_t k = 0; k < count; ++k)
      {
        vectors[k] = Eigen::Vector3d(v[3 * k], v[3 * k + 1], v[3 * k + 2]);
      }
      header.strandVectors[name] = std::move(vectors);
    }
  }
  return Status::Ok();
}

/// The largest coordinates per strand a file may declare: three per element (Super-Helix) of
/// at most GuideStrand::maxElements (1000) elements.
constexpr int MaxCoordinates = 3000;

/// Everything of the header but the per-point scalars, which need the number of frames.
Status readHeader(const Contents& c, hid_t f, hid_t offsets, StateHeader& header)
{
  if (Status s = readStringAttribute(f, sf::ModelAttribute, header.model); !s)
  {
    return damaged(s.message() + " (the model's name, one string).");
  }
  if (Status s = readIntAttribute(f, sf::CoordinatesAttribute, header.coordinatesPerStrand); !s)
  {
    return damaged(s.message() + " (the coordinates per strand, one integer).");
  }
  if (header.coordinatesPerStrand < 0 || header.coordinatesPerStrand > MaxCoordinates)
  {
    return damaged(std::string(sf::CoordinatesAttribute) + " is " +
                   std::to_string(header.coordinatesPerStrand) + ", outside [0, " +
                   std::to_string(MaxCoordinates) + "].");
  }
  if (Status s = readRunAttributes(f, header.attributes); !s)
  {
    return s;
  }
  DatasetInfo info;
  if (!describe(offsets, info))
  {
    return damaged(std::string(sf::Offsets) + ": its type or shape cannot be read.");
  }
  const hsize_t n = info.dims.empty() ? 0 : info.dims[0];
  if (Status s = checkBytes(c, sf::Offsets, info, double(n)); !s)
  {
    return s;
  }
  header.offsets.resize(n);
  if (n > 0 && !readWhole(offsets, H5T_NATIVE_INT64, header.offsets.data()))
  {
    return damaged(std::string(sf::Offsets) + " cannot be read.");
  }
  if (Status s = header.validate(); !s)
  {
    return damaged(std::string(sf::Offsets) + ": " + s.message());
  }
  if (Status s = readStrandData(c, f, header); !s)
  {
    return s;
  }
  detail::readGroom(f, header,
                    std::min(MaxCompression * c.FileBytes, c.MemoryBytes / sizeof(double)));
  return Status::Ok();
}

/// Whole frames: one writer (version 1, or 3 without /whole_frames), the length of /time,
/// written last in every frame; several ranks (version 2, or 3 with it), /whole_frames,
/// written once every rank's part of a frame is (/time is as long as the run).
/// The times of the whole frames must be finite and increasing; positions and velocities must
/// hold at least as many frames, of the header's points.
Status readTimes(Contents& c, hid_t f, const FixedDatasets& d)
{
  DatasetInfo time, positions, velocities;
  if (!describe(d.Time.get(), time) || !describe(d.Positions.get(), positions) ||
      !describe(d.Velocities.get(), velocities))
  {
    return damaged("the type or shape of " + std::string(sf::Time) + " or of the positions " +
                   "cannot be read.");
  }
  c.Frames = std::int64_t(std::min<hsize_t>(time.dims[0], INT64_MAX));
  if (Status s = checkBytes(c, sf::Time, time, double(c.Frames)); !s)
  {
    return s;
  }
  if (c.Version == sf::SharedVersion ||
      (c.Version == sf::Version && H5Lexists(f, sf::WholeFrames, H5P_DEFAULT) > 0))
  {
    c.Shared = true;
    // Written by several ranks: /time is as long as the run from the start; /whole_frames,
    // one int64 written once every rank's part of a frame is, counts the whole frames.
    if (H5Lexists(f, sf::WholeFrames, H5P_DEFAULT) <= 0)
    {
      return damaged(std::string(sf::WholeFrames) + " is missing (format version 2 counts its " +
                     "whole frames there).");
    }
    Handle whole(H5Dopen2(f, sf::WholeFrames, H5P_DEFAULT));
    DatasetInfo count;
    if (!whole.valid() || !describe(whole.get(), count) || count.typeClass != H5T_INTEGER ||
        !count.dims.empty() ||
        H5Sget_simple_extent_type(Handle(H5Dget_space(whole.get())).get()) != H5S_SCALAR)
    {
      return damaged(std::string(sf::WholeFrames) + " is not one integer (a scalar dataset).");
    }
    std::int64_t n = -1;
    if (!readWhole(whole.get(), H5T_NATIVE_INT64, &n) || n < 0 || n > c.Frames)
    {
      return damaged(std::string(sf::WholeFrames) + " is " + std::to_string(n) +
                     ", not a count of whole frames between 0 and the length of " + sf::Time +
                     ", " + std::to_string(c.Frames) + ".");
    }
    c.Frames = n;
  }
  const hsize_t points = c.Header.numberOfPoints();
  // Version 3 keeps the points of a model drawn from q in single precision.
  c.Header.singlePrecisionPoints = positions.typeSize == sizeof(float);
  if (Status s = checkFrames(c, sf::Positions, positions, {points, 3}); !s)
  {
    return s;
  }
  if (Status s = checkFrames(c, sf::Velocities, velocities, {points, 3}); !s)
  {
    return s;
  }
  if (Status s = readValues(d.Time.get(), sf::Time, hsize_t(c.Frames), c.Times); !s)
  {
    return s;
  }
  for (std::size_t k = 0; k < c.Times.size(); ++k)
  {
    if (!std::isfinite(c.Times[k]))
    {
      return damaged(std::string(sf::Time) + ": the time of frame " + std::to_string(k) + " is " +
                     std::to_string(c.Times[k]) + ".");
    }
    if (k > 0 && !(c.Times[k] > c.Times[k - 1]))
    {
      return damaged(std::string(sf::Time) + " does not increase: frame " + std::to_string(k) +
                     " is at " + std::to_string(c.Times[k]) + " s, frame " + std::to_string(k - 1) +
                     " at " + std::to_string(c.Times[k - 1]) + " s.");
    }
  }
  return Status::Ok();
}

/// /frames/q and /frames/qdot, [T', S, C], when the header has coordinates.
Status checkCoordinates(const Contents& c, hid_t f)
{
  const int coordinates = c.Header.coordinatesPerStrand;
  for (const char* path : {sf::Q, sf::QDot})
  {
    if (coordinates == 0)
    {
      continue;
    }
    Handle d;
    DatasetInfo info;
    Status s = openArray(f, path, 3, false, d, info);
    if (s)
    {
      s = checkFrames(c, path, info, {c.Header.numberOfStrands(), hsize_t(coordinates)});
    }
    if (!s)
    {
      return Status::Error(s.message().substr(0, s.message().size() - 1) + " (" +
                           sf::CoordinatesAttribute + " is " + std::to_string(coordinates) + ").");
    }
  }
  return Status::Ok();
}

/// Per-point scalars: every other dataset of /frames holding numbers, shaped [T', P]; a
/// dataset of another shape or type is skipped (a later format may add it).
Status findPointData(const Contents& c, hid_t f, StateHeader& header)
{
  Handle group(H5Gopen2(f, sf::Frames, H5P_DEFAULT));
  std::vector<std::string> names;
  if (!group.valid() || !linkNames(group.get(), names))
  {
    return damaged(std::string(sf::Frames) + " cannot be listed.");
  }
  for (const std::string& name : names)
  {
    const std::string path = sf::inGroup(sf::Frames, name);
    if (isFrameField(name) || H5Oexists_by_name(f, path.c_str(), H5P_DEFAULT) <= 0)
    {
      continue;
    }
    Handle d;
    DatasetInfo info;
    if (!openArray(f, path, 2, false, d, info) || info.dims[1] != header.numberOfPoints() ||
        std::int64_t(info.dims[0]) < c.Frames)
    {
      continue;
    }
    if (Status s = checkFrames(c, path, info, {header.numberOfPoints()}); !s)
    {
      return s;
    }
    header.pointData.push_back(name);
  }
  return Status::Ok();
}

/// The optional root datasets: used when both are there, shaped [T', S, 12] and [T', S, 6]
/// with T' ≥ the whole frames; a file without them (or with others) reads without them.
Status findRootFrames(const Contents& c, hid_t f, StateHeader& header)
{
  const hsize_t strands = header.numberOfStrands();
  bool both = true;
  for (auto [path, values] :
       {std::pair<const char*, hsize_t>{sf::RootFrames, RootFrameValues},
        std::pair<const char*, hsize_t>{sf::RootVelocities, RootVelocityValues}})
  {
    Handle d;
    DatasetInfo info;
    const bool shaped = H5Lexists(f, path, H5P_DEFAULT) > 0 &&
                        openArray(f, path, 3, false, d, info) && info.dims[1] == strands &&
                        info.dims[2] == values && std::int64_t(info.dims[0]) >= c.Frames;
    if (shaped)
    {
      if (Status s = checkFrames(c, path, info, {strands, values}); !s)
      {
        return s;
      }
    }
    both = both && shaped;
  }
  header.rootFrames = both;
  return Status::Ok();
}

/// Every dataset of /energy, each of at least as many values as whole frames; the required
/// terms must be there.
Status readEnergies(Contents& c, hid_t f)
{
  Handle energy(H5Gopen2(f, sf::Energy, H5P_DEFAULT));
  std::vector<std::string> names;
  if (!energy.valid() || !linkNames(energy.get(), names))
  {
    return damaged(std::string(sf::Energy) + " is missing.");
  }
  for (const char* term : RequiredEnergyTerms)
  {
    if (std::find(names.begin(), names.end(), term) == names.end())
    {
      return damaged(sf::inGroup(sf::Energy, term) + " is missing.");
    }
  }
  for (const std::string& name : names)
  {
    const std::string path = sf::inGroup(sf::Energy, name);
    Handle d;
    DatasetInfo info;
    if (Status s = openArray(f, path, 1, false, d, info); !s)
    {
      return s;
    }
    if (std::int64_t(info.dims[0]) < c.Frames)
    {
      return damaged(path + " is shorter than " + sf::Time + ".");
    }
    if (Status s = checkBytes(c, path, info, double(c.Frames)); !s)
    {
      return s;
    }
    if (Status s = readValues(d.get(), path, hsize_t(c.Frames), c.Energies[name]); !s)
    {
      return s;
    }
  }
  return Status::Ok();
}

/// The runs of consecutive strands of `strands` (increasing numbers of `h`'s strands, else
/// refused) as rows of a per-strand dataset and, with `points`, of a per-point one.
Status strandRuns(const StateHeader& h, const std::vector<std::int64_t>& strands, Runs& rows,
                  Runs* points)
{
  for (std::size_t i = 0; i < strands.size();)
  {
    if (strands[i] < 0 || std::size_t(strands[i]) >= h.numberOfStrands() ||
        (i > 0 && strands[i] <= strands[i - 1]))
    {
      return Status::Error("the strands of a piece must be increasing numbers of the file's " +
                           std::to_string(h.numberOfStrands()) + " strands.");
    }
    std::size_t j = i + 1;
    while (j < strands.size() && strands[j] == strands[j - 1] + 1)
    {
      ++j;
    }
    const std::int64_t first = strands[i], last = strands[j - 1] + 1;
    rows.emplace_back(hsize_t(first), hsize_t(last - first));
    if (points)
    {
      points->emplace_back(hsize_t(h.offsets[first]), hsize_t(h.offsets[last] - h.offsets[first]));
    }
    i = j;
  }
  return Status::Ok();
}

/// The continuation's slots (/resume), when there are any: the header's continuationWidth
/// and continuationRunValues from their shapes. A /resume that does not fit the file leaves
/// the file readable (its frames are whole) but not resumable: the problem is kept for
/// readContinuation's message.
void findContinuation(Contents& c, hid_t f)
{
  StateHeader& h = c.Header;
  if (H5Lexists(f, sf::Resume, H5P_DEFAULT) <= 0)
  {
    return;
  }
  Handle frame, strands, run;
  DatasetInfo fi, si, ri;
  Status s = openArray(f, sf::ResumeFrame, 1, true, frame, fi);
  s = s ? openArray(f, sf::ResumeStrands, 3, false, strands, si) : s;
  s = s ? openArray(f, sf::ResumeRun, 2, false, run, ri) : s;
  if (s &&
      (fi.dims[0] != 2 || si.dims[0] != 2 || ri.dims[0] != 2 || si.dims[1] != h.numberOfStrands() ||
       si.dims[2] < 1 || si.dims[2] > (1u << 24) || ri.dims[1] > 1024))
  {
    s = damaged(std::string(sf::Resume) + "'s datasets are not shaped [2], [2, " +
                std::to_string(h.numberOfStrands()) + ", W] and [2, K].");
  }
  s = s ? checkBytes(c, sf::ResumeStrands, si, 2.0 * double(si.dims[1]) * double(si.dims[2])) : s;
  if (!s)
  {
    c.ContinuationProblem = s.message();
    return;
  }
  h.continuationWidth = int(si.dims[2]);
  h.continuationRunValues = int(ri.dims[1]);
}

/// The steps of open(), in order; the first that fails refuses the file. Every dataset's
/// type and shape are checked against the others' and the file's size before it is read.
Status readFile(const std::string& path, Contents& c)
{
  if (Status s = checkPath(path, c.FileBytes); !s)
  {
    return s;
  }
  c.MemoryBytes = memoryForOneRead();
  if (Status s = openFile(path, c.File); !s)
  {
    return s;
  }
  const hid_t f = c.File.get();
  if (Status s = checkFormat(f, c.Version); !s)
  {
    return s;
  }
  // The fixed datasets are all opened before any is read, so that a missing one is reported
  // before a malformed one.
  FixedDatasets d;
  DatasetInfo info;
  Status s = openArray(f, sf::Offsets, 1, true, d.Offsets, info);
  if (s)
  {
    s = openArray(f, sf::Time, 1, false, d.Time, info);
  }
  if (s)
  {
    s = openArray(f, sf::Positions, 3, false, d.Positions, info);
  }
  if (s)
  {
    s = openArray(f, sf::Velocities, 3, false, d.Velocities, info);
  }
  if (s)
  {
    s = readHeader(c, f, d.Offsets.get(), c.Header);
  }
  if (s)
  {
    s = readTimes(c, f, d);
  }
  if (s)
  {
    s = checkCoordinates(c, f);
  }
  if (s)
  {
    s = findPointData(c, f, c.Header);
  }
  if (s)
  {
    s = findRootFrames(c, f, c.Header);
  }
  s = s ? readEnergies(c, f) : s;
  if (s)
  {
    findContinuation(c, f);
  }
  return s;
}
} // namespace

struct StateFileReader::Impl : Contents
{
  std::string Path;
};

StateFileReader::StateFileReader() : P(std::make_unique<Impl>()) {}
StateFileReader::~StateFileReader() = default;
void StateFileReader::close()
{
  P = std::make_unique<Impl>();
}
const StateHeader& StateFileReader::header() const
{
  return P->Header;
}
std::int64_t StateFileReader::numberOfFrames() const
{
  return P->Frames;
}
const std::vector<double>& StateFileReader::times() const
{
  return P->Times;
}
const std::map<std::string, std::vector<double>>& StateFileReader::energies() const
{
  return P->Energies;
}

Status StateFileReader::open(const std::string& path)
{
  close();
  auto fail = [&](const std::string& what)
  {
    close();
    return Status::Error("'" + path + "' " + what);
  };
  auto r = std::make_unique<Impl>();
  r->Path = path;
  Status result = Status::Ok();
  H5E_BEGIN_TRY
  {
    result = readFile(path, *r);
    // Not kept open: HDF5 shares one open file between every handle of a process, with the
    // metadata it read first, so a handle kept here would show a second reader of the same
    // file (and this one, reopened) the frames of the first open only (issue 24).
    // readFrame() opens the file again.
    r->File.reset();
  }
  H5E_END_TRY;
  if (!result)
  {
    return fail(result.message());
  }
  P = std::move(r);
  return Status::Ok();
}

bool StateFileReader::sharedByRanks() const
{
  return P->Shared;
}

int StateFileReader::version() const
{
  return P->Version;
}

std::vector<std::int64_t> StateFileReader::pieceStrands(int piece, int pieces) const
{
  const std::size_t strands = P->Header.numberOfStrands();
  std::vector<std::int64_t> mine;
  if (pieces <= 1)
  {
    for (std::size_t k = 0; k < strands; ++k)
    {
      mine.push_back(std::int64_t(k));
    }
    return mine;
  }
  const auto roots = P->Header.strandVectors.find("rest_root");
  if (roots != P->Header.strandVectors.end())
  {
    const std::vector<int> part =
        shareAlongCurve(roots->second, std::vector<double>(strands, 1.0), pieces);
    for (std::size_t k = 0; k < strands; ++k)
    {
      if (part[k] == piece)
      {
        mine.push_back(std::int64_t(k));
      }
    }
    return mine;
  }
  const std::size_t first = strands * std::size_t(piece) / std::size_t(pieces);
  const std::size_t last = strands * std::size_t(piece + 1) / std::size_t(pieces);
  for (std::size_t k = first; k < last; ++k)
  {
    mine.push_back(std::int64_t(k));
  }
  return mine;
}

/// Frame `index` as read (`out`, the whole run or a piece of it) checked and given its
/// energies: the writer refuses non-finite values, so one here is damage.
static Status finishFrame(const Contents& r, const StateHeader& header, const std::string& path,
                          std::int64_t index, StateFrame& out, StateFrame& frame)
{
  // The writer refuses non-finite values, so one here is damage: the frame is refused
  // rather than shown with points at NaN (which breaks the view's bounds and every filter
  // after it).
  std::string bad;
  forEachArray(header, out,
               [&](const FrameArray& a)
               {
                 const std::size_t i = a.firstNonFinite();
                 if (bad.empty() && i < a.size)
                 {
                   bad = a.what + " " + std::to_string(i / a.width);
                 }
               });
  if (!bad.empty())
  {
    return Status::Error("the state file '" + path + "': frame " + std::to_string(index) +
                         " is damaged: " + bad + " is NaN or infinite.");
  }
  for (const auto& [name, values] : r.Energies)
  {
    out.energy[name] = values[index];
  }
  frame = std::move(out);
  return Status::Ok();
}

Status StateFileReader::readFrame(std::int64_t index, StateFrame& frame) const
{
  if (P->Path.empty())
  {
    return Status::Error("the state file is not open.");
  }
  if (index < 0 || index >= P->Frames)
  {
    return Status::Error("the state file '" + P->Path + "' has " + std::to_string(P->Frames) +
                         " whole frames; frame " + std::to_string(index) + " does not exist.");
  }
  const StateHeader& h = P->Header;
  StateFrame out;
  out.time = P->Times[index];
  bool ok = true;
  H5E_BEGIN_TRY
  {
    Handle file;
    double bytes = 0;
    ok = checkPath(P->Path, bytes) && openFile(P->Path, file);
    const hid_t f = file.get();
    // Frame `index` of each array, if each of its frames still holds as many values as the
    // header says (the file may have been replaced since open()).
    std::vector<double> buffer;
    forEachArray(h, out, true,
                 [&](const FrameArray& a)
                 {
                   Handle d(ok ? H5Dopen2(f, a.name.c_str(), H5P_DEFAULT) : -1);
                   const auto dims = extent(d.get());
                   double per = dims.empty() ? 0 : 1;
                   for (std::size_t k = 1; k < dims.size(); ++k)
                   {
                     per *= double(dims[k]);
                   }
                   ok = ok && d.valid() && dims.size() >= 2 && dims[0] > hsize_t(index) &&
                        per == double(a.size) && readSlab(d.get(), hsize_t(index), buffer) &&
                        buffer.size() == a.size;
                   if (ok)
                   {
                     std::copy(buffer.begin(), buffer.end(), a.data);
                   }
                 });
  }
  H5E_END_TRY;
  if (!ok)
  {
    return Status::Error("the state file '" + P->Path + "': frame " + std::to_string(index) +
                         " cannot be read: the file is damaged, or was replaced since it was "
                         "opened (open it again).");
  }
  return finishFrame(*P, h, P->Path, index, out, frame);
}

} // namespace hair

namespace hair
{

Status StateFileReader::readPiece(std::int64_t index, const std::vector<std::int64_t>& strands,
                                  StateFrame& frame) const
{
  if (P->Path.empty())
  {
    return Status::Error("the state file is not open.");
  }
  if (index < 0 || index >= P->Frames)
  {
    return Status::Error("the state file '" + P->Path + "' has " + std::to_string(P->Frames) +
                         " whole frames; frame " + std::to_string(index) + " does not exist.");
  }
  const StateHeader& h = P->Header;
  Runs points, rows;
  if (Status s = strandRuns(h, strands, rows, &points); !s)
  {
    return s;
  }
  const StateHeader piece = h.piece(strands);
  StateFrame out;
  out.time = P->Times[index];
  bool ok = true;
  H5E_BEGIN_TRY
  {
    // Opened for this read, as readFrame does (the file may have grown or been replaced).
    Handle file;
    double bytes = 0;
    ok = checkPath(P->Path, bytes) && openFile(P->Path, file);
    const hid_t f = file.get();
    forEachArray(piece, out, true,
                 [&](const FrameArray& a)
                 {
                   Handle d(ok ? H5Dopen2(f, a.name.c_str(), H5P_DEFAULT) : -1);
                   RowSelection sel;
                   ok = ok && d.valid() && sel.build(d.get(), a.perPoint ? points : rows) &&
                        sel.moveToFrame(hsize_t(index)) && sel.values == a.size &&
                        H5Dread(d.get(), H5T_NATIVE_DOUBLE, sel.memory.get(), sel.file.get(),
                                H5P_DEFAULT, a.data) >= 0;
                 });
  }
  H5E_END_TRY;
  if (!ok)
  {
    return Status::Error("the state file '" + P->Path + "': frame " + std::to_string(index) +
                         " cannot be read: the file is damaged, or was replaced since it was "
                         "opened (open it again).");
  }
  return finishFrame(*P, piece, P->Path, index, out, frame);
}

Status StateFileReader::readContinuation(const std::vector<std::int64_t>* strands,
                                         StateContinuation& out) const
{
  const StateHeader& h = P->Header;
  const std::string file = "the state file '" + P->Path + "'";
  if (P->Path.empty())
  {
    return Status::Error("the state file is not open.");
  }
  if (h.continuationWidth < 1)
  {
    return Status::Error(
        file + " keeps no continuation of its frames, so it cannot be resumed: " +
        (P->ContinuationProblem.empty()
             ? "it was written by a HairDynamics that did not keep one (format version " +
                   std::to_string(P->Version) + "), or without a state file's room for it."
             : P->ContinuationProblem));
  }
  std::vector<std::int64_t> all;
  if (!strands)
  {
    all.resize(h.numberOfStrands());
    for (std::size_t k = 0; k < all.size(); ++k)
    {
      all[k] = std::int64_t(k);
    }
    strands = &all;
  }
  Runs rows;
  if (Status s = strandRuns(h, *strands, rows, nullptr); !s)
  {
    return s;
  }
  const std::size_t width = std::size_t(h.continuationWidth);
  std::int64_t slots[2] = {-1, -1};
  std::vector<double> values(strands->size() * width);
  StateContinuation c;
  c.run.resize(std::size_t(h.continuationRunValues));
  int slot = -1;
  bool ok = true;
  H5E_BEGIN_TRY
  {
    Handle f;
    double bytes = 0;
    ok = checkPath(P->Path, bytes) && openFile(P->Path, f);
    Handle frame(ok ? H5Dopen2(f.get(), sf::ResumeFrame, H5P_DEFAULT) : -1);
    ok = ok && frame.valid() && readWhole(frame.get(), H5T_NATIVE_INT64, slots);
    // The newest whole frame's (a slot names a frame before its numbers are whole only after
    // they are written; one naming a frame past the whole ones was being written).
    for (int i = 0; ok && i < 2; ++i)
    {
      if (slots[i] >= 0 && slots[i] < P->Frames && (slot < 0 || slots[i] > slots[slot]))
      {
        slot = i;
      }
    }
    if (ok && slot >= 0)
    {
      Handle d(H5Dopen2(f.get(), sf::ResumeStrands, H5P_DEFAULT));
      RowSelection sel;
      ok = d.valid() && sel.build(d.get(), rows) && sel.moveToFrame(hsize_t(slot)) &&
           sel.values == values.size() &&
           (values.empty() || H5Dread(d.get(), H5T_NATIVE_DOUBLE, sel.memory.get(), sel.file.get(),
                                      H5P_DEFAULT, values.data()) >= 0);
      Handle r(H5Dopen2(f.get(), sf::ResumeRun, H5P_DEFAULT));
      ok = ok && r.valid();
      if (ok && !c.run.empty())
      {
        Handle space(H5Dget_space(r.get()));
        const hsize_t start[2] = {hsize_t(slot), 0}, count[2] = {1, c.run.size()};
        const hsize_t n = c.run.size();
        Handle memory(H5Screate_simple(1, &n, nullptr));
        ok =
            H5Sselect_hyperslab(space.get(), H5S_SELECT_SET, start, nullptr, count, nullptr) >= 0 &&
            H5Dread(r.get(), H5T_NATIVE_DOUBLE, memory.get(), space.get(), H5P_DEFAULT,
                    c.run.data()) >= 0;
      }
    }
  }
  H5E_END_TRY;
  if (!ok)
  {
    return Status::Error(file + ": its continuation (" + sf::Resume +
                         ") cannot be read: the file is damaged.");
  }
  if (slot < 0)
  {
    return Status::Error(file + " has no whole frame with its continuation (" + sf::Resume +
                         " names frames " + std::to_string(slots[0]) + " and " +
                         std::to_string(slots[1]) + " of " + std::to_string(P->Frames) +
                         "): it cannot be resumed.");
  }
  c.frame = slots[slot];
  c.strands.resize(strands->size());
  for (std::size_t k = 0; k < strands->size(); ++k)
  {
    const double* row = values.data() + k * width;
    if (!(row[0] >= 0 && row[0] <= double(width - 1)))
    {
      return Status::Error(file + ": the continuation of strand " + std::to_string((*strands)[k]) +
                           " is damaged (its count, " + std::to_string(row[0]) +
                           ", does not fit its " + std::to_string(width - 1) + " places).");
    }
    c.strands[k].assign(row + 1, row + 1 + std::size_t(row[0]));
  }
  out = std::move(c);
  return Status::Ok();
}

} // namespace hair
