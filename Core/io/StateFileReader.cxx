// StateFileReader (StateFile.h): opens a state file in steps, each of which refuses the file
// with a message that says what is wrong, then reads frames on demand.
#include "io/StateFile.h"

#include "common/Partition.h"
#include "io/Hdf5.h"
#include "io/StateFormat.h"

#include <algorithm>
#include <fstream>

namespace hair
{

using namespace hdf5;
namespace sf = stateformat;

namespace
{
/// What open() reads and readFrame() uses.
struct Contents
{
  Handle File;
  int Version = 0;
  StateHeader Header;
  std::int64_t Frames = 0;
  std::vector<double> Times;
  std::map<std::string, std::vector<double>> Energies;
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

Status openFile(const std::string& path, Handle& file)
{
  if (H5Fis_hdf5(path.c_str()) <= 0)
  {
    return Status::Error("is not an HDF5 file, so not a HairDynamics state file.");
  }
  // A file still being written (or whose writer was killed) opens in SWMR-read mode; a file
  // written otherwise (h5py, a copy) opens normally.
  file = Handle(H5Fopen(path.c_str(), H5F_ACC_RDONLY | H5F_ACC_SWMR_READ, H5P_DEFAULT));
  if (!file.valid())
  {
    file = Handle(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  }
  if (!file.valid())
  {
    return Status::Error("is damaged or truncated: HDF5 cannot open it.");
  }
  return Status::Ok();
}

/// The root's format and format_version attributes (version 1, or 2: written by several
/// MPI ranks).
Status checkFormat(hid_t f, int& version)
{
  std::string format;
  if (!readStringAttribute(f, sf::FormatAttribute, format) || format != sf::Name)
  {
    return Status::Error(
        std::string("is an HDF5 file but not a HairDynamics state file (its root has no "
                    "attribute ") +
        sf::FormatAttribute + " = \"" + sf::Name + "\").");
  }
  version = 0;
  if (!readIntAttribute(f, sf::VersionAttribute, version) ||
      (version != sf::Version && version != sf::SharedVersion))
  {
    return Status::Error("has state-file format version " + std::to_string(version) +
                         "; this HairDynamics reads versions " + std::to_string(sf::Version) +
                         " and " + std::to_string(sf::SharedVersion) + ".");
  }
  return Status::Ok();
}

Status openDataset(hid_t f, const char* path, Handle& dataset)
{
  if (H5Lexists(f, path, H5P_DEFAULT) <= 0)
  {
    return damaged(std::string(path) + " is missing.");
  }
  dataset = Handle(H5Dopen2(f, path, H5P_DEFAULT));
  if (!dataset.valid())
  {
    return damaged(std::string(path) + " cannot be opened.");
  }
  return Status::Ok();
}

Status openFixedDatasets(hid_t f, FixedDatasets& d)
{
  Status s = openDataset(f, sf::Offsets, d.Offsets);
  if (s)
  {
    s = openDataset(f, sf::Time, d.Time);
  }
  if (s)
  {
    s = openDataset(f, sf::Positions, d.Positions);
  }
  if (s)
  {
    s = openDataset(f, sf::Velocities, d.Velocities);
  }
  return s;
}

/// Every numeric attribute of the root but the format's own is a run attribute.
void readRunAttributes(hid_t f, std::map<std::string, double>& attributes)
{
  for (const std::string& name : attributeNames(f))
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
}

/// Per-strand parameters: every other dataset of /strands with one value per strand.
void readStrandParameters(hid_t f, StateHeader& header)
{
  Handle strands(H5Gopen2(f, sf::Strands, H5P_DEFAULT));
  std::vector<std::string> names;
  linkNames(strands.get(), names);
  for (const std::string& name : names)
  {
    if (sf::inGroup(sf::Strands, name) == sf::Offsets)
    {
      continue;
    }
    Handle d(H5Dopen2(strands.get(), name.c_str(), H5P_DEFAULT));
    const auto dims = extent(d.get());
    if (dims.size() == 1 && dims[0] == header.numberOfStrands())
    {
      std::vector<double> v(dims[0]);
      if (readWhole(d.get(), H5T_NATIVE_DOUBLE, v.data()))
      {
        header.strandParameters[name] = std::move(v);
      }
    }
  }
}

/// Per-strand vectors: every dataset of /strands shaped [S, 3].
void readStrandVectors(hid_t f, StateHeader& header)
{
  Handle strands(H5Gopen2(f, sf::Strands, H5P_DEFAULT));
  std::vector<std::string> names;
  linkNames(strands.get(), names);
  for (const std::string& name : names)
  {
    Handle d(H5Dopen2(strands.get(), name.c_str(), H5P_DEFAULT));
    const auto dims = extent(d.get());
    if (dims.size() == 2 && dims[0] == header.numberOfStrands() && dims[1] == 3)
    {
      std::vector<Eigen::Vector3d> v(dims[0]);
      if (readWhole(d.get(), H5T_NATIVE_DOUBLE, v.data()))
      {
        header.strandVectors[name] = std::move(v);
      }
    }
  }
}

/// Everything of the header but the per-point scalars, which need the number of frames.
Status readHeader(hid_t f, hid_t offsets, StateHeader& header)
{
  readStringAttribute(f, sf::ModelAttribute, header.model);
  readIntAttribute(f, sf::CoordinatesAttribute, header.coordinatesPerStrand);
  readRunAttributes(f, header.attributes);
  const auto n = extent(offsets);
  header.offsets.resize(n.empty() ? 0 : n[0]);
  if (n.size() != 1 || !readWhole(offsets, H5T_NATIVE_INT64, header.offsets.data()))
  {
    return damaged(std::string(sf::Offsets) + " cannot be read.");
  }
  if (Status s = header.validate(); !s)
  {
    return s;
  }
  readStrandParameters(f, header);
  readStrandVectors(f, header);
  return Status::Ok();
}

/// Whole frames: version 1, the length of /time, written last in every frame; version 2,
/// /whole_frames, written once every rank's part of a frame is (/time is as long as the
/// run). Positions and velocities must hold at least as many frames, of the header's points.
Status checkShapes(hid_t f, int version, const FixedDatasets& d, const StateHeader& header,
                   std::int64_t& frames)
{
  const auto tdims = extent(d.Time.get());
  frames = tdims.size() == 1 ? std::int64_t(tdims[0]) : -1;
  if (version == sf::SharedVersion && frames >= 0)
  {
    Handle whole;
    if (Status s = openDataset(f, sf::WholeFrames, whole); !s)
    {
      return s;
    }
    std::int64_t count = -1;
    if (!extent(whole.get()).empty() || !readWhole(whole.get(), H5T_NATIVE_INT64, &count) ||
        count < 0 || count > frames)
    {
      return damaged(std::string(sf::WholeFrames) + " is not a count of " + sf::Time +
                     "'s frames.");
    }
    frames = count;
  }
  const auto pdims = extent(d.Positions.get()), vdims = extent(d.Velocities.get());
  const hsize_t points = header.numberOfPoints();
  if (frames < 0 || pdims.size() != 3 || vdims.size() != 3 || pdims[1] != points ||
      vdims[1] != points || pdims[2] != 3 || vdims[2] != 3 ||
      std::int64_t(std::min(pdims[0], vdims[0])) < frames)
  {
    return damaged(std::string(sf::Time) + ", " + sf::Positions + " and " + sf::Velocities +
                   " do not agree in shape.");
  }
  return Status::Ok();
}

Status readTimes(hid_t time, std::int64_t frames, std::vector<double>& times)
{
  times.resize(frames);
  if (frames > 0 && !readFirst(time, hsize_t(frames), times.data()))
  {
    return damaged(std::string(sf::Time) + " cannot be read.");
  }
  return Status::Ok();
}

/// Per-point scalars: every other dataset of /frames shaped [T', P].
void findPointData(hid_t f, std::int64_t frames, StateHeader& header)
{
  Handle group(H5Gopen2(f, sf::Frames, H5P_DEFAULT));
  std::vector<std::string> names;
  linkNames(group.get(), names);
  for (const std::string& name : names)
  {
    if (sf::isFrameDataset(name))
    {
      continue;
    }
    Handle d(H5Dopen2(group.get(), name.c_str(), H5P_DEFAULT));
    const auto dims = extent(d.get());
    if (dims.size() == 2 && dims[1] == header.numberOfPoints() && std::int64_t(dims[0]) >= frames)
    {
      header.pointData.push_back(name);
    }
  }
}

/// The optional root datasets: used when both are there, shaped [T', S, 12] and [T', S, 6]
/// with T' ≥ `frames`; a file without them (or with others) reads without them.
void findRootFrames(hid_t f, std::int64_t frames, StateHeader& header)
{
  auto shaped = [&](const char* path, hsize_t values)
  {
    if (H5Lexists(f, path, H5P_DEFAULT) <= 0)
    {
      return false;
    }
    Handle d(H5Dopen2(f, path, H5P_DEFAULT));
    const auto dims = extent(d.get());
    return dims.size() == 3 && std::int64_t(dims[0]) >= frames &&
           dims[1] == header.numberOfStrands() && dims[2] == values;
  };
  header.rootFrames =
      shaped(sf::RootFrames, RootFrameValues) && shaped(sf::RootVelocities, RootVelocityValues);
}

/// Every dataset of /energy, each of at least `frames` values.
Status readEnergies(hid_t f, std::int64_t frames, std::map<std::string, std::vector<double>>& out)
{
  Handle energy(H5Gopen2(f, sf::Energy, H5P_DEFAULT));
  std::vector<std::string> names;
  if (!energy.valid() || !linkNames(energy.get(), names))
  {
    return damaged(std::string(sf::Energy) + " is missing.");
  }
  for (const std::string& name : names)
  {
    Handle d(H5Dopen2(energy.get(), name.c_str(), H5P_DEFAULT));
    const auto dims = extent(d.get());
    std::vector<double> v(frames);
    if (dims.size() != 1 || std::int64_t(dims[0]) < frames)
    {
      return damaged(sf::inGroup(sf::Energy, name) + " is shorter than " + sf::Time + ".");
    }
    if (frames > 0)
    {
      readFirst(d.get(), hsize_t(frames), v.data());
    }
    out[name] = std::move(v);
  }
  return Status::Ok();
}

/// The steps of open(), in order; the first that fails refuses the file.
Status readFile(const std::string& path, Contents& c)
{
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
  if (Status s = openFixedDatasets(f, d); !s)
  {
    return s;
  }
  if (Status s = readHeader(f, d.Offsets.get(), c.Header); !s)
  {
    return s;
  }
  if (Status s = checkShapes(f, c.Version, d, c.Header, c.Frames); !s)
  {
    return s;
  }
  if (Status s = readTimes(d.Time.get(), c.Frames, c.Times); !s)
  {
    return s;
  }
  findPointData(f, c.Frames, c.Header);
  findRootFrames(f, c.Frames, c.Header);
  return readEnergies(f, c.Frames, c.Energies);
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
  if (!std::ifstream(path))
  {
    return fail("cannot be opened: check the path.");
  }
  auto r = std::make_unique<Impl>();
  r->Path = path;
  Status result = Status::Ok();
  H5E_BEGIN_TRY
  {
    result = readFile(path, *r);
  }
  H5E_END_TRY;
  if (!result)
  {
    return fail(result.message());
  }
  P = std::move(r);
  return Status::Ok();
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
    const std::vector<int> part = bisect(roots->second, std::vector<double>(strands, 1.0), pieces);
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

Status StateFileReader::readFrame(std::int64_t index, StateFrame& frame) const
{
  if (!P->File.valid())
  {
    return Status::Error("the state file is not open.");
  }
  if (index < 0 || index >= P->Frames)
  {
    return Status::Error("the state file '" + P->Path + "' has " + std::to_string(P->Frames) +
                         " whole frames; frame " + std::to_string(index) + " does not exist.");
  }
  StateFrame out;
  out.time = P->Times[index];
  bool ok = true;
  H5E_BEGIN_TRY
  {
    const hid_t f = P->File.get();
    std::vector<double> buffer;
    auto vectors = [&](const char* name, std::vector<Eigen::Vector3d>& v)
    {
      Handle d(H5Dopen2(f, name, H5P_DEFAULT));
      if (!d.valid() || !readSlab(d.get(), hsize_t(index), buffer))
      {
        return false;
      }
      v.resize(buffer.size() / 3);
      for (std::size_t i = 0; i < v.size(); ++i)
      {
        v[i] = Eigen::Vector3d(buffer[3 * i], buffer[3 * i + 1], buffer[3 * i + 2]);
      }
      return true;
    };
    ok = vectors(sf::Positions, out.positions) && vectors(sf::Velocities, out.velocities);
    if (ok && P->Header.coordinatesPerStrand > 0)
    {
      Handle q(H5Dopen2(f, sf::Q, H5P_DEFAULT)), qd(H5Dopen2(f, sf::QDot, H5P_DEFAULT));
      ok = q.valid() && qd.valid() && readSlab(q.get(), hsize_t(index), out.q) &&
           readSlab(qd.get(), hsize_t(index), out.qdot);
    }
    if (ok && P->Header.rootFrames)
    {
      Handle r(H5Dopen2(f, sf::RootFrames, H5P_DEFAULT));
      Handle v(H5Dopen2(f, sf::RootVelocities, H5P_DEFAULT));
      ok = r.valid() && v.valid() && readSlab(r.get(), hsize_t(index), out.rootFrames) &&
           readSlab(v.get(), hsize_t(index), out.rootVelocities);
    }
    for (const std::string& name : P->Header.pointData)
    {
      Handle d(ok ? H5Dopen2(f, sf::inGroup(sf::Frames, name).c_str(), H5P_DEFAULT) : -1);
      ok = ok && d.valid() && readSlab(d.get(), hsize_t(index), out.pointData[name]);
    }
  }
  H5E_END_TRY;
  if (!ok)
  {
    return Status::Error("the state file '" + P->Path + "': frame " + std::to_string(index) +
                         " cannot be read: the file is damaged.");
  }
  for (const auto& [name, values] : P->Energies)
  {
    out.energy[name] = values[index];
  }
  frame = std::move(out);
  return Status::Ok();
}

} // namespace hair

namespace hair
{

Status StateFileReader::readPiece(std::int64_t index, const std::vector<std::int64_t>& strands,
                                  StateFrame& frame) const
{
  if (!P->File.valid())
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
    points.emplace_back(hsize_t(h.offsets[first]), hsize_t(h.offsets[last] - h.offsets[first]));
    i = j;
  }
  StateFrame out;
  out.time = P->Times[index];
  bool ok = true;
  H5E_BEGIN_TRY
  {
    const hid_t f = P->File.get();
    auto read = [&](const char* name, const Runs& runs, std::vector<double>& data)
    {
      Handle d(ok ? H5Dopen2(f, name, H5P_DEFAULT) : -1);
      RowSelection sel;
      ok = ok && d.valid() && sel.build(d.get(), runs) && sel.moveToFrame(hsize_t(index));
      if (ok)
      {
        data.resize(sel.values);
        ok = H5Dread(d.get(), H5T_NATIVE_DOUBLE, sel.memory.get(), sel.file.get(), H5P_DEFAULT,
                     data.data()) >= 0;
      }
    };
    auto vectors = [&](const char* name, std::vector<Eigen::Vector3d>& v)
    {
      std::vector<double> buffer;
      read(name, points, buffer);
      v.resize(buffer.size() / 3);
      for (std::size_t i = 0; i < v.size(); ++i)
      {
        v[i] = Eigen::Vector3d(buffer[3 * i], buffer[3 * i + 1], buffer[3 * i + 2]);
      }
    };
    vectors(sf::Positions, out.positions);
    vectors(sf::Velocities, out.velocities);
    if (h.coordinatesPerStrand > 0)
    {
      read(sf::Q, rows, out.q);
      read(sf::QDot, rows, out.qdot);
    }
    if (h.rootFrames)
    {
      read(sf::RootFrames, rows, out.rootFrames);
      read(sf::RootVelocities, rows, out.rootVelocities);
    }
    for (const std::string& name : h.pointData)
    {
      read(sf::inGroup(sf::Frames, name).c_str(), points, out.pointData[name]);
    }
  }
  H5E_END_TRY;
  if (!ok)
  {
    return Status::Error("the state file '" + P->Path + "': frame " + std::to_string(index) +
                         " cannot be read: the file is damaged.");
  }
  for (const auto& [name, values] : P->Energies)
  {
    out.energy[name] = values[index];
  }
  frame = std::move(out);
  return Status::Ok();
}

} // namespace hair
