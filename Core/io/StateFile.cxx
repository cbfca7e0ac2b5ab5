#include "io/StateFile.h"

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <fstream>

namespace hair
{

const char* const RequiredEnergyTerms[5] = {"kinetic", "elastic", "gravitational", "dissipated",
                                            "external_work"};

namespace
{
constexpr const char* FormatName = "HairDynamics states";
constexpr int FormatVersion = 1;

/// Closes an HDF5 handle of any kind when it goes out of scope.
class Handle
{
public:
  Handle() = default;
  explicit Handle(hid_t id) : Id(id) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& o) noexcept : Id(o.Id) { o.Id = -1; }
  Handle& operator=(Handle&& o) noexcept
  {
    reset();
    Id = o.Id;
    o.Id = -1;
    return *this;
  }
  ~Handle() { reset(); }
  void reset()
  {
    if (Id >= 0)
    {
      H5E_BEGIN_TRY
      {
        switch (H5Iget_type(Id))
        {
        case H5I_FILE:
          H5Fclose(Id);
          break;
        case H5I_GROUP:
          H5Gclose(Id);
          break;
        case H5I_DATASET:
          H5Dclose(Id);
          break;
        case H5I_DATASPACE:
          H5Sclose(Id);
          break;
        case H5I_DATATYPE:
          H5Tclose(Id);
          break;
        case H5I_ATTR:
          H5Aclose(Id);
          break;
        case H5I_GENPROP_LST:
          H5Pclose(Id);
          break;
        default:
          break;
        }
      }
      H5E_END_TRY;
    }
    Id = -1;
  }
  hid_t get() const { return Id; }
  bool valid() const { return Id >= 0; }

private:
  hid_t Id = -1;
};

Status writeStringAttribute(hid_t obj, const char* name, const std::string& value)
{
  // Variable-length UTF-8: h5py reads it as a str, not bytes.
  Handle type(H5Tcopy(H5T_C_S1));
  H5Tset_size(type.get(), H5T_VARIABLE);
  H5Tset_cset(type.get(), H5T_CSET_UTF8);
  Handle space(H5Screate(H5S_SCALAR));
  Handle attr(H5Acreate2(obj, name, type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT));
  const char* text = value.c_str();
  if (!attr.valid() || H5Awrite(attr.get(), type.get(), &text) < 0)
  {
    return Status::Error(std::string("cannot write the attribute ") + name);
  }
  return Status::Ok();
}

template <typename T>
Status writeScalarAttribute(hid_t obj, const char* name, hid_t type, T value)
{
  Handle space(H5Screate(H5S_SCALAR));
  Handle attr(H5Acreate2(obj, name, type, space.get(), H5P_DEFAULT, H5P_DEFAULT));
  if (!attr.valid() || H5Awrite(attr.get(), type, &value) < 0)
  {
    return Status::Error(std::string("cannot write the attribute ") + name);
  }
  return Status::Ok();
}

bool readStringAttribute(hid_t obj, const char* name, std::string& value)
{
  if (H5Aexists(obj, name) <= 0)
  {
    return false;
  }
  Handle attr(H5Aopen(obj, name, H5P_DEFAULT));
  Handle type(H5Aget_type(attr.get()));
  if (H5Tget_class(type.get()) != H5T_STRING)
  {
    return false;
  }
  if (H5Tis_variable_str(type.get()) > 0)
  {
    char* s = nullptr;
    Handle memType(H5Tcopy(H5T_C_S1));
    H5Tset_size(memType.get(), H5T_VARIABLE);
    H5Tset_cset(memType.get(), H5Tget_cset(type.get()));
    if (H5Aread(attr.get(), memType.get(), &s) < 0 || s == nullptr)
    {
      return false;
    }
    value = s;
    H5free_memory(s);
    return true;
  }
  const std::size_t size = H5Tget_size(type.get());
  std::string buffer(size + 1, '\0');
  Handle memType(H5Tcopy(H5T_C_S1));
  H5Tset_size(memType.get(), size + 1);
  H5Tset_cset(memType.get(), H5Tget_cset(type.get()));
  if (H5Aread(attr.get(), memType.get(), buffer.data()) < 0)
  {
    return false;
  }
  value = buffer.c_str();
  return true;
}

/// A dataset that grows by one frame along its first dimension.
Handle createGrowing(hid_t parent, const char* name, const std::vector<hsize_t>& frameShape)
{
  std::vector<hsize_t> dims{0}, maxDims{H5S_UNLIMITED}, chunk{1};
  for (hsize_t d : frameShape)
  {
    dims.push_back(d);
    maxDims.push_back(d);
    chunk.push_back(std::max<hsize_t>(d, 1));
  }
  if (frameShape.empty())
  {
    chunk[0] = 1024; // scalars per frame: chunks of many frames
  }
  Handle space(H5Screate_simple(int(dims.size()), dims.data(), maxDims.data()));
  Handle props(H5Pcreate(H5P_DATASET_CREATE));
  H5Pset_chunk(props.get(), int(chunk.size()), chunk.data());
  return Handle(H5Dcreate2(parent, name, H5T_NATIVE_DOUBLE, space.get(), H5P_DEFAULT, props.get(),
                           H5P_DEFAULT));
}

/// Writes one frame's slab at index t, growing the dataset to t + 1 frames first.
bool appendSlab(hid_t dataset, hsize_t t, const double* data)
{
  Handle space(H5Dget_space(dataset));
  const int rank = H5Sget_simple_extent_ndims(space.get());
  std::vector<hsize_t> dims(rank);
  H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr);
  dims[0] = t + 1;
  if (H5Dset_extent(dataset, dims.data()) < 0)
  {
    return false;
  }
  Handle fileSpace(H5Dget_space(dataset));
  std::vector<hsize_t> start(rank, 0), count = dims;
  start[0] = t;
  count[0] = 1;
  H5Sselect_hyperslab(fileSpace.get(), H5S_SELECT_SET, start.data(), nullptr, count.data(),
                      nullptr);
  Handle memSpace(H5Screate_simple(rank, count.data(), nullptr));
  return H5Dwrite(dataset, H5T_NATIVE_DOUBLE, memSpace.get(), fileSpace.get(), H5P_DEFAULT, data) >=
         0;
}

bool readSlab(hid_t dataset, hsize_t t, std::vector<double>& data)
{
  Handle fileSpace(H5Dget_space(dataset));
  const int rank = H5Sget_simple_extent_ndims(fileSpace.get());
  std::vector<hsize_t> dims(rank);
  H5Sget_simple_extent_dims(fileSpace.get(), dims.data(), nullptr);
  if (rank < 1 || dims[0] <= t)
  {
    return false;
  }
  std::vector<hsize_t> start(rank, 0), count = dims;
  start[0] = t;
  count[0] = 1;
  hsize_t n = 1;
  for (int k = 1; k < rank; ++k)
  {
    n *= dims[k];
  }
  data.resize(n);
  H5Sselect_hyperslab(fileSpace.get(), H5S_SELECT_SET, start.data(), nullptr, count.data(),
                      nullptr);
  Handle memSpace(H5Screate_simple(rank, count.data(), nullptr));
  return H5Dread(dataset, H5T_NATIVE_DOUBLE, memSpace.get(), fileSpace.get(), H5P_DEFAULT,
                 data.data()) >= 0;
}

std::vector<hsize_t> extent(hid_t dataset)
{
  Handle space(H5Dget_space(dataset));
  const int rank = H5Sget_simple_extent_ndims(space.get());
  std::vector<hsize_t> dims(std::max(rank, 0));
  if (rank > 0)
  {
    H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr);
  }
  return dims;
}

bool readWhole(hid_t dataset, hid_t memType, void* data)
{
  return H5Dread(dataset, memType, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0;
}

bool finite(const std::vector<double>& v)
{
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}
} // namespace

Status StateHeader::validate() const
{
  if (offsets.size() < 2 || offsets.front() != 0)
  {
    return Status::Error("the state has no strands (offsets must start at 0 and name at least "
                         "one strand): grow strands before simulating.");
  }
  for (std::size_t k = 1; k < offsets.size(); ++k)
  {
    if (offsets[k] <= offsets[k - 1])
    {
      return Status::Error("strand " + std::to_string(k - 1) + " has no points in the state.");
    }
  }
  if (coordinatesPerStrand < 0)
  {
    return Status::Error("a negative number of coordinates per strand.");
  }
  for (const auto& [name, values] : strandParameters)
  {
    if (values.size() != numberOfStrands())
    {
      return Status::Error("the strand parameter '" + name + "' has " +
                           std::to_string(values.size()) + " values for " +
                           std::to_string(numberOfStrands()) + " strands.");
    }
  }
  return Status::Ok();
}

// ---------------------------------------------------------------------------------------
struct StateFileWriter::Impl
{
  Handle File, Time, Positions, Velocities, Q, QDot;
  std::map<std::string, Handle> PointData;
  std::map<std::string, Handle> Energy;
  StateHeader Header;
  std::string Path;
  hsize_t Frames = 0;
};

StateFileWriter::StateFileWriter() : P(std::make_unique<Impl>()) {}
StateFileWriter::~StateFileWriter()
{
  close();
}
bool StateFileWriter::isOpen() const
{
  return P->File.valid();
}
std::int64_t StateFileWriter::numberOfFrames() const
{
  return std::int64_t(P->Frames);
}

Status StateFileWriter::create(const std::string& path, const StateHeader& header,
                               const std::vector<std::string>& extraEnergyTerms)
{
  close();
  if (Status s = header.validate(); !s)
  {
    return s;
  }
  auto fail = [&](const std::string& what)
  {
    P = std::make_unique<Impl>();
    return Status::Error("the state file '" + path + "': " + what);
  };
  H5E_BEGIN_TRY
  {
    Handle fapl(H5Pcreate(H5P_FILE_ACCESS));
    // The latest format is what single-writer/multiple-reader mode needs.
    H5Pset_libver_bounds(fapl.get(), H5F_LIBVER_LATEST, H5F_LIBVER_LATEST);
    P->File = Handle(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get()));
  }
  H5E_END_TRY;
  if (!P->File.valid())
  {
    return fail("cannot be created: check that its folder exists and is writable.");
  }
  P->Header = header;
  P->Path = path;
  const hid_t f = P->File.get();
  Status s = writeStringAttribute(f, "format", FormatName);
  if (s)
  {
    s = writeScalarAttribute<int>(f, "format_version", H5T_NATIVE_INT, FormatVersion);
  }
  if (s)
  {
    s = writeStringAttribute(f, "model", header.model);
  }
  if (s)
  {
    s = writeScalarAttribute<int>(f, "coordinates_per_strand", H5T_NATIVE_INT,
                                  header.coordinatesPerStrand);
  }
  for (const auto& [name, value] : header.attributes)
  {
    if (s)
    {
      s = writeScalarAttribute<double>(f, name.c_str(), H5T_NATIVE_DOUBLE, value);
    }
  }
  if (!s)
  {
    return fail(s.message());
  }
  Handle strands(H5Gcreate2(f, "strands", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  Handle frames(H5Gcreate2(f, "frames", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  Handle energy(H5Gcreate2(f, "energy", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  {
    const hsize_t n = header.offsets.size();
    Handle space(H5Screate_simple(1, &n, nullptr));
    Handle d(H5Dcreate2(strands.get(), "offsets", H5T_NATIVE_INT64, space.get(), H5P_DEFAULT,
                        H5P_DEFAULT, H5P_DEFAULT));
    if (!d.valid() || H5Dwrite(d.get(), H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT,
                               header.offsets.data()) < 0)
    {
      return fail("cannot write /strands/offsets.");
    }
  }
  for (const auto& [name, values] : header.strandParameters)
  {
    const hsize_t n = values.size();
    Handle space(H5Screate_simple(1, &n, nullptr));
    Handle d(H5Dcreate2(strands.get(), name.c_str(), H5T_NATIVE_DOUBLE, space.get(), H5P_DEFAULT,
                        H5P_DEFAULT, H5P_DEFAULT));
    if (!d.valid() ||
        H5Dwrite(d.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0)
    {
      return fail("cannot write /strands/" + name + ".");
    }
  }
  const hsize_t points = header.numberOfPoints(), strandCount = header.numberOfStrands();
  P->Time = createGrowing(f, "time", {});
  P->Positions = createGrowing(frames.get(), "positions", {points, 3});
  P->Velocities = createGrowing(frames.get(), "velocities", {points, 3});
  if (header.coordinatesPerStrand > 0)
  {
    const hsize_t c = hsize_t(header.coordinatesPerStrand);
    P->Q = createGrowing(frames.get(), "q", {strandCount, c});
    P->QDot = createGrowing(frames.get(), "qdot", {strandCount, c});
  }
  for (const std::string& name : header.pointData)
  {
    if (name == "positions" || name == "velocities" || name == "q" || name == "qdot" ||
        P->PointData.count(name))
    {
      return fail("the per-point array name '" + name + "' is reserved or repeated.");
    }
    P->PointData[name] = createGrowing(frames.get(), name.c_str(), {points});
    if (!P->PointData[name].valid())
    {
      return fail("cannot create /frames/" + name + ".");
    }
  }
  std::vector<std::string> terms(std::begin(RequiredEnergyTerms), std::end(RequiredEnergyTerms));
  for (const auto& t : extraEnergyTerms)
  {
    if (std::find(terms.begin(), terms.end(), t) == terms.end())
    {
      terms.push_back(t);
    }
  }
  for (const auto& t : terms)
  {
    P->Energy[t] = createGrowing(energy.get(), t.c_str(), {});
    if (!P->Energy[t].valid())
    {
      return fail("cannot create /energy/" + t + ".");
    }
  }
  if (!P->Time.valid() || !P->Positions.valid() || !P->Velocities.valid() ||
      (header.coordinatesPerStrand > 0 && (!P->Q.valid() || !P->QDot.valid())))
  {
    return fail("cannot create the per-frame datasets.");
  }
  strands.reset();
  frames.reset();
  energy.reset();
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

Status StateFileWriter::append(const StateFrame& frame)
{
  if (!P->File.valid())
  {
    return Status::Error("the state file is not open: create it first.");
  }
  const StateHeader& h = P->Header;
  const std::string where = "the state file '" + P->Path + "', frame " + std::to_string(P->Frames) +
                            " (t = " + std::to_string(frame.time) + " s): ";
  if (frame.positions.size() != h.numberOfPoints() || frame.velocities.size() != h.numberOfPoints())
  {
    return Status::Error(where + "expected " + std::to_string(h.numberOfPoints()) +
                         " positions and velocities, got " +
                         std::to_string(frame.positions.size()) + " and " +
                         std::to_string(frame.velocities.size()) + ".");
  }
  const std::size_t nq = h.numberOfStrands() * std::size_t(h.coordinatesPerStrand);
  if (frame.q.size() != nq || frame.qdot.size() != nq)
  {
    return Status::Error(where + "expected " + std::to_string(nq) + " values of q and qdot.");
  }
  auto flat = [](const std::vector<Eigen::Vector3d>& v)
  {
    std::vector<double> out(3 * v.size());
    for (std::size_t i = 0; i < v.size(); ++i)
    {
      out[3 * i] = v[i].x();
      out[3 * i + 1] = v[i].y();
      out[3 * i + 2] = v[i].z();
    }
    return out;
  };
  const std::vector<double> pos = flat(frame.positions), vel = flat(frame.velocities);
  if (!std::isfinite(frame.time) || !finite(pos) || !finite(vel) || !finite(frame.q) ||
      !finite(frame.qdot))
  {
    return Status::Error(
        where + "NaN or infinite values: the frame is not written, the frames before it are kept.");
  }
  for (const auto& [name, dataset] : P->PointData)
  {
    const auto it = frame.pointData.find(name);
    if (it == frame.pointData.end() || it->second.size() != h.numberOfPoints() ||
        !finite(it->second))
    {
      return Status::Error(where + "the per-point array '" + name +
                           "' is missing, of the "
                           "wrong size, or not finite.");
    }
  }
  for (const auto& [name, value] : frame.energy)
  {
    if (P->Energy.find(name) == P->Energy.end())
    {
      return Status::Error(where + "the energy term '" + name +
                           "' was not declared when the file was created.");
    }
  }
  const hsize_t t = P->Frames;
  bool ok = true;
  H5E_BEGIN_TRY
  {
    ok = appendSlab(P->Positions.get(), t, pos.data()) &&
         appendSlab(P->Velocities.get(), t, vel.data());
    if (ok && h.coordinatesPerStrand > 0)
    {
      ok = appendSlab(P->Q.get(), t, frame.q.data()) &&
           appendSlab(P->QDot.get(), t, frame.qdot.data());
    }
    for (auto& [name, dataset] : P->PointData)
    {
      ok = ok && appendSlab(dataset.get(), t, frame.pointData.at(name).data());
    }
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
  return Status::Ok();
}

Status StateFileWriter::close()
{
  if (!P->File.valid())
  {
    return Status::Ok();
  }
  P->Energy.clear();
  P->PointData.clear();
  P->Time.reset();
  P->Positions.reset();
  P->Velocities.reset();
  P->Q.reset();
  P->QDot.reset();
  P->File.reset();
  P->Frames = 0;
  return Status::Ok();
}

// ---------------------------------------------------------------------------------------
struct StateFileReader::Impl
{
  Handle File;
  StateHeader Header;
  std::string Path;
  std::int64_t Frames = 0;
  std::vector<double> Times;
  std::map<std::string, std::vector<double>> Energies;
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
    if (H5Fis_hdf5(path.c_str()) <= 0)
    {
      result = Status::Error("is not an HDF5 file, so not a HairDynamics state file.");
    }
    else
    {
      // A file still being written (or whose writer was killed) opens in SWMR-read mode; a
      // file written otherwise (h5py, a copy) opens normally.
      r->File = Handle(H5Fopen(path.c_str(), H5F_ACC_RDONLY | H5F_ACC_SWMR_READ, H5P_DEFAULT));
      if (!r->File.valid())
      {
        r->File = Handle(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
      }
      if (!r->File.valid())
      {
        result = Status::Error("is damaged or truncated: HDF5 cannot open it.");
      }
    }
    std::string format;
    const hid_t f = r->File.get();
    if (result && (!readStringAttribute(f, "format", format) || format != FormatName))
    {
      result = Status::Error("is an HDF5 file but not a HairDynamics state file (its root has "
                             "no attribute format = \"HairDynamics states\").");
    }
    int version = 0;
    if (result)
    {
      Handle attr(H5Aexists(f, "format_version") > 0 ? H5Aopen(f, "format_version", H5P_DEFAULT)
                                                     : -1);
      if (!attr.valid() || H5Aread(attr.get(), H5T_NATIVE_INT, &version) < 0 ||
          version != FormatVersion)
      {
        result = Status::Error("has state-file format version " + std::to_string(version) +
                               "; this HairDynamics reads version " +
                               std::to_string(FormatVersion) + ".");
      }
    }
    if (result)
    {
      readStringAttribute(f, "model", r->Header.model);
      Handle attr(H5Aexists(f, "coordinates_per_strand") > 0
                      ? H5Aopen(f, "coordinates_per_strand", H5P_DEFAULT)
                      : -1);
      if (attr.valid())
      {
        H5Aread(attr.get(), H5T_NATIVE_INT, &r->Header.coordinatesPerStrand);
      }
      // Every other numeric attribute of the root is a run attribute.
      const char* fixed[] = {"format", "format_version", "model", "coordinates_per_strand"};
      std::vector<std::string> names;
      H5Aiterate2(
          f, H5_INDEX_NAME, H5_ITER_INC, nullptr,
          [](hid_t, const char* name, const H5A_info_t*, void* data) -> herr_t
          {
            static_cast<std::vector<std::string>*>(data)->push_back(name);
            return 0;
          },
          &names);
      for (const std::string& name : names)
      {
        if (std::find_if(std::begin(fixed), std::end(fixed),
                         [&](const char* x) { return name == x; }) != std::end(fixed))
        {
          continue;
        }
        Handle at(H5Aopen(f, name.c_str(), H5P_DEFAULT));
        Handle type(H5Aget_type(at.get()));
        double value = 0;
        if (H5Tget_class(type.get()) == H5T_FLOAT || H5Tget_class(type.get()) == H5T_INTEGER)
        {
          if (H5Aread(at.get(), H5T_NATIVE_DOUBLE, &value) >= 0)
          {
            r->Header.attributes[name] = value;
          }
        }
      }
    }
    auto open = [&](const char* name) -> Handle
    {
      if (!result)
      {
        return Handle();
      }
      if (H5Lexists(f, name, H5P_DEFAULT) <= 0)
      {
        result = Status::Error(std::string("is a damaged state file: ") + name + " is missing.");
        return Handle();
      }
      Handle d(H5Dopen2(f, name, H5P_DEFAULT));
      if (!d.valid())
      {
        result =
            Status::Error(std::string("is a damaged state file: ") + name + " cannot be opened.");
      }
      return d;
    };
    Handle offsets = open("/strands/offsets");
    Handle time = open("/time");
    Handle positions = open("/frames/positions");
    Handle velocities = open("/frames/velocities");
    if (result)
    {
      const auto n = extent(offsets.get());
      r->Header.offsets.resize(n.empty() ? 0 : n[0]);
      if (n.size() != 1 || !readWhole(offsets.get(), H5T_NATIVE_INT64, r->Header.offsets.data()))
      {
        result = Status::Error("is a damaged state file: /strands/offsets cannot be read.");
      }
    }
    if (result)
    {
      result = r->Header.validate();
    }
    if (result)
    {
      // Per-strand parameters: every other dataset of /strands.
      Handle strands(H5Gopen2(f, "/strands", H5P_DEFAULT));
      H5G_info_t ginfo;
      H5Gget_info(strands.get(), &ginfo);
      for (hsize_t k = 0; k < ginfo.nlinks; ++k)
      {
        char name[256] = {0};
        H5Lget_name_by_idx(strands.get(), ".", H5_INDEX_NAME, H5_ITER_INC, k, name, sizeof(name),
                           H5P_DEFAULT);
        if (std::string(name) == "offsets")
        {
          continue;
        }
        Handle d(H5Dopen2(strands.get(), name, H5P_DEFAULT));
        const auto dims = extent(d.get());
        if (dims.size() == 1 && dims[0] == r->Header.numberOfStrands())
        {
          std::vector<double> v(dims[0]);
          if (readWhole(d.get(), H5T_NATIVE_DOUBLE, v.data()))
          {
            r->Header.strandParameters[name] = std::move(v);
          }
        }
      }
    }
    if (result)
    {
      // Whole frames: the length of /time, written last in every frame.
      const auto tdims = extent(time.get());
      r->Frames = tdims.size() == 1 ? std::int64_t(tdims[0]) : -1;
      const auto pdims = extent(positions.get()), vdims = extent(velocities.get());
      const hsize_t points = r->Header.numberOfPoints();
      if (r->Frames < 0 || pdims.size() != 3 || vdims.size() != 3 || pdims[1] != points ||
          vdims[1] != points || pdims[2] != 3 || vdims[2] != 3 ||
          std::int64_t(std::min(pdims[0], vdims[0])) < r->Frames)
      {
        result = Status::Error("is a damaged state file: /time, /frames/positions and "
                               "/frames/velocities do not agree in shape.");
      }
    }
    if (result)
    {
      r->Times.resize(r->Frames);
      if (r->Frames > 0)
      {
        Handle fileSpace(H5Dget_space(time.get()));
        const hsize_t start = 0, count = hsize_t(r->Frames);
        H5Sselect_hyperslab(fileSpace.get(), H5S_SELECT_SET, &start, nullptr, &count, nullptr);
        Handle memSpace(H5Screate_simple(1, &count, nullptr));
        if (H5Dread(time.get(), H5T_NATIVE_DOUBLE, memSpace.get(), fileSpace.get(), H5P_DEFAULT,
                    r->Times.data()) < 0)
        {
          result = Status::Error("is a damaged state file: /time cannot be read.");
        }
      }
    }
    if (result)
    {
      // Per-point scalars: every other dataset of /frames shaped [T', P].
      Handle frames(H5Gopen2(f, "/frames", H5P_DEFAULT));
      H5G_info_t ginfo{};
      H5Gget_info(frames.get(), &ginfo);
      for (hsize_t k = 0; k < ginfo.nlinks; ++k)
      {
        char name[256] = {0};
        H5Lget_name_by_idx(frames.get(), ".", H5_INDEX_NAME, H5_ITER_INC, k, name, sizeof(name),
                           H5P_DEFAULT);
        const std::string n = name;
        if (n == "positions" || n == "velocities" || n == "q" || n == "qdot")
        {
          continue;
        }
        Handle d(H5Dopen2(frames.get(), name, H5P_DEFAULT));
        const auto dims = extent(d.get());
        if (dims.size() == 2 && dims[1] == r->Header.numberOfPoints() &&
            std::int64_t(dims[0]) >= r->Frames)
        {
          r->Header.pointData.push_back(n);
        }
      }
    }
    if (result)
    {
      Handle energy(H5Gopen2(f, "/energy", H5P_DEFAULT));
      H5G_info_t ginfo{};
      if (!energy.valid() || H5Gget_info(energy.get(), &ginfo) < 0)
      {
        result = Status::Error("is a damaged state file: /energy is missing.");
      }
      for (hsize_t k = 0; result && k < ginfo.nlinks; ++k)
      {
        char name[256] = {0};
        H5Lget_name_by_idx(energy.get(), ".", H5_INDEX_NAME, H5_ITER_INC, k, name, sizeof(name),
                           H5P_DEFAULT);
        Handle d(H5Dopen2(energy.get(), name, H5P_DEFAULT));
        const auto dims = extent(d.get());
        std::vector<double> v(r->Frames);
        if (dims.size() != 1 || std::int64_t(dims[0]) < r->Frames)
        {
          result = Status::Error(std::string("is a damaged state file: /energy/") + name +
                                 " is shorter than /time.");
          break;
        }
        if (r->Frames > 0)
        {
          Handle fileSpace(H5Dget_space(d.get()));
          const hsize_t start = 0, count = hsize_t(r->Frames);
          H5Sselect_hyperslab(fileSpace.get(), H5S_SELECT_SET, &start, nullptr, &count, nullptr);
          Handle memSpace(H5Screate_simple(1, &count, nullptr));
          H5Dread(d.get(), H5T_NATIVE_DOUBLE, memSpace.get(), fileSpace.get(), H5P_DEFAULT,
                  v.data());
        }
        r->Energies[name] = std::move(v);
      }
    }
  }
  H5E_END_TRY;
  if (!result)
  {
    return fail(result.message());
  }
  P = std::move(r);
  return Status::Ok();
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
    ok = vectors("/frames/positions", out.positions) &&
         vectors("/frames/velocities", out.velocities);
    if (ok && P->Header.coordinatesPerStrand > 0)
    {
      Handle q(H5Dopen2(f, "/frames/q", H5P_DEFAULT)), qd(H5Dopen2(f, "/frames/qdot", H5P_DEFAULT));
      ok = q.valid() && qd.valid() && readSlab(q.get(), hsize_t(index), out.q) &&
           readSlab(qd.get(), hsize_t(index), out.qdot);
    }
    for (const std::string& name : P->Header.pointData)
    {
      Handle d(ok ? H5Dopen2(f, ("/frames/" + name).c_str(), H5P_DEFAULT) : -1);
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
