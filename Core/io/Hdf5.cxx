#include "io/Hdf5.h"

#include <algorithm>
#include <limits>

namespace hair::hdf5
{

void Handle::reset()
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

// ---- Attributes -------------------------------------------------------------------------

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

namespace
{
/// Whether the attribute holds exactly one value (the readers below read one into a
/// scalar: an attribute of another shape would overrun it).
bool holdsOneValue(hid_t attr)
{
  Handle space(H5Aget_space(attr));
  return space.valid() && H5Sget_simple_extent_type(space.get()) != H5S_NULL &&
         H5Sget_simple_extent_npoints(space.get()) == 1;
}

/// The number of values an attribute holds, for messages (−1 if its space cannot be read).
long long valueCount(hid_t attr)
{
  Handle space(H5Aget_space(attr));
  if (!space.valid())
  {
    return -1;
  }
  return H5Sget_simple_extent_type(space.get()) == H5S_NULL
             ? 0
             : static_cast<long long>(H5Sget_simple_extent_npoints(space.get()));
}

const char* className(H5T_class_t c)
{
  switch (c)
  {
  case H5T_INTEGER:
    return "an integer";
  case H5T_FLOAT:
    return "a floating-point number";
  case H5T_STRING:
    return "a string";
  default:
    return "of a type that is neither a number nor a string";
  }
}

/// Opens attribute `name` of `obj` holding one value of class `wanted`, or says what is
/// wrong with it.
Status openOne(hid_t obj, const char* name, H5T_class_t wanted, Handle& attr, Handle& type)
{
  const std::string what = std::string("its attribute '") + name + "' ";
  const htri_t exists = H5Aexists(obj, name);
  if (exists < 0)
  {
    return Status::Error(what + "cannot be read (the object header holding it is damaged)");
  }
  if (exists == 0)
  {
    return Status::Error(what + "is missing");
  }
  attr = Handle(H5Aopen(obj, name, H5P_DEFAULT));
  type = Handle(attr.valid() ? H5Aget_type(attr.get()) : -1);
  if (!attr.valid() || !type.valid())
  {
    return Status::Error(what + "cannot be read");
  }
  if (!holdsOneValue(attr.get()))
  {
    return Status::Error(what + "holds " + std::to_string(valueCount(attr.get())) +
                         " values where one is expected");
  }
  const H5T_class_t c = H5Tget_class(type.get());
  if (c != wanted)
  {
    return Status::Error(what + "is " + className(c) + " where " + className(wanted) +
                         " is expected");
  }
  return Status::Ok();
}
} // namespace

Status readStringAttribute(hid_t obj, const char* name, std::string& value)
{
  Handle attr, type;
  if (Status s = openOne(obj, name, H5T_STRING, attr, type); !s)
  {
    return s;
  }
  const std::string unreadable = std::string("its attribute '") + name + "' cannot be read";
  if (H5Tis_variable_str(type.get()) > 0)
  {
    char* s = nullptr;
    Handle memType(H5Tcopy(H5T_C_S1));
    H5Tset_size(memType.get(), H5T_VARIABLE);
    H5Tset_cset(memType.get(), H5Tget_cset(type.get()));
    if (H5Aread(attr.get(), memType.get(), &s) < 0 || s == nullptr)
    {
      return Status::Error(unreadable + " (the global heap holding its text is "
                                        "damaged or unreadable)");
    }
    value = s;
    H5free_memory(s);
    return Status::Ok();
  }
  // Fixed length: at most 64 KiB (the largest attribute HDF5's compact storage holds),
  // read into a buffer one longer, so that a string without a terminating null ends.
  const std::size_t size = H5Tget_size(type.get());
  if (size == 0 || size > 65536)
  {
    return Status::Error(unreadable + " (a fixed-length string of " + std::to_string(size) +
                         " bytes)");
  }
  std::string buffer(size + 1, '\0');
  Handle memType(H5Tcopy(H5T_C_S1));
  H5Tset_size(memType.get(), size + 1);
  H5Tset_cset(memType.get(), H5Tget_cset(type.get()));
  if (H5Aread(attr.get(), memType.get(), buffer.data()) < 0)
  {
    return Status::Error(unreadable);
  }
  value = buffer.c_str();
  return Status::Ok();
}

Status readIntAttribute(hid_t obj, const char* name, int& value)
{
  Handle attr, type;
  if (Status s = openOne(obj, name, H5T_INTEGER, attr, type); !s)
  {
    return s;
  }
  // Read as a 64-bit integer, then checked to fit an int (HDF5 would clip silently).
  long long read = 0;
  if (H5Aread(attr.get(), H5T_NATIVE_LLONG, &read) < 0)
  {
    return Status::Error(std::string("its attribute '") + name + "' cannot be read");
  }
  if (read < std::numeric_limits<int>::min() || read > std::numeric_limits<int>::max())
  {
    return Status::Error(std::string("its attribute '") + name + "' is " + std::to_string(read) +
                         ", out of range");
  }
  value = static_cast<int>(read);
  return Status::Ok();
}

bool readNumericAttribute(hid_t obj, const char* name, double& value)
{
  Handle attr(H5Aopen(obj, name, H5P_DEFAULT));
  if (!attr.valid() || !holdsOneValue(attr.get()))
  {
    return false;
  }
  Handle type(H5Aget_type(attr.get()));
  const H5T_class_t typeClass = H5Tget_class(type.get());
  if (typeClass != H5T_FLOAT && typeClass != H5T_INTEGER)
  {
    return false;
  }
  double read = 0;
  if (H5Aread(attr.get(), H5T_NATIVE_DOUBLE, &read) < 0)
  {
    return false;
  }
  value = read;
  return true;
}

namespace
{
/// A name no attribute of a state file has (control characters included): attributeNames
/// looks it up to have HDF5 decode every attribute message.
constexpr char NoSuchAttribute[] = "\x01hairdynamics: no attribute has this name\x01";

/// Collects names, at most MaxLinks of them (then stops the iteration with an error).
herr_t collect(const char* name, void* data)
{
  auto* names = static_cast<std::vector<std::string>*>(data);
  if (names->size() >= MaxLinks)
  {
    return -1;
  }
  names->push_back(name);
  return 0;
}
} // namespace

bool attributeNames(hid_t obj, std::vector<std::string>& names)
{
  names.clear();
  // Every attribute message decoded first, by a look-up of a name no attribute has: HDF5
  // 1.10.8 looks a name up message by message, decoding each, and returns an error if one
  // cannot be decoded. H5Aiterate2 copies the attributes of a header's compact storage into
  // a table first, and when a message after the first cannot be decoded it releases the
  // table's slots past the last one filled, uninitialized memory: a segfault inside HDF5 on
  // damaged files written by MPI ranks (version 1 object headers, which carry no checksum;
  // Testing/Fuzz/regressions/crash-attribute-table-release).
  if (H5Aexists(obj, NoSuchAttribute) != 0)
  {
    return false;
  }
  // In the order stored (H5_ITER_NATIVE), then sorted: for dense storage HDF5 then builds no
  // table (its sorted table of a damaged object's dense storage crashed in HDF5 itself).
  hsize_t at = 0;
  if (H5Aiterate2(
          obj, H5_INDEX_NAME, H5_ITER_NATIVE, &at,
          [](hid_t, const char* name, const H5A_info_t*, void* data) -> herr_t
          { return collect(name, data); },
          &names) < 0)
  {
    names.clear();
    return false;
  }
  std::sort(names.begin(), names.end());
  return true;
}

// ---- Groups -----------------------------------------------------------------------------

bool linkNames(hid_t group, std::vector<std::string>& names)
{
  // In the order stored (H5_ITER_NATIVE), then sorted: a sorted look-up by index builds a
  // table of every link first, whose release crashed inside HDF5 1.10.8 on a damaged group
  // in dense storage (Testing/Fuzz/regressions/crash-dense-link-table).
  names.clear();
  hsize_t at = 0;
  const herr_t status = H5Literate(
      group, H5_INDEX_NAME, H5_ITER_NATIVE, &at,
      [](hid_t, const char* name, const H5L_info_t*, void* data) -> herr_t
      { return collect(name, data); },
      &names);
  if (status < 0)
  {
    names.clear();
    return false;
  }
  std::sort(names.begin(), names.end());
  return true;
}

// ---- Datasets ---------------------------------------------------------------------------

bool writeArray(hid_t parent, const char* name, hid_t type, hsize_t count, const void* data,
                bool write)
{
  Handle space(H5Screate_simple(1, &count, nullptr));
  Handle d(H5Dcreate2(parent, name, type, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  return d.valid() && (!write || H5Dwrite(d.get(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0);
}

bool writeRows(hid_t parent, const char* name, hsize_t rows, hsize_t columns, const double* data,
               bool write)
{
  const hsize_t dims[2] = {rows, columns};
  Handle space(H5Screate_simple(2, dims, nullptr));
  Handle d(H5Dcreate2(parent, name, H5T_NATIVE_DOUBLE, space.get(), H5P_DEFAULT, H5P_DEFAULT,
                      H5P_DEFAULT));
  return d.valid() &&
         (!write || H5Dwrite(d.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0);
}

Handle createGrowing(hid_t parent, const char* name, const std::vector<hsize_t>& frameShape,
                     hid_t type)
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
  return Handle(H5Dcreate2(parent, name, type, space.get(), H5P_DEFAULT, props.get(), H5P_DEFAULT));
}

bool appendSlab(hid_t dataset, hsize_t t, const void* data, hid_t memType)
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
  return H5Dwrite(dataset, memType, memSpace.get(), fileSpace.get(), H5P_DEFAULT, data) >= 0;
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

Handle createFixed(hid_t parent, const char* name, hsize_t frames,
                   const std::vector<hsize_t>& frameShape, bool fill, hid_t type)
{
  std::vector<hsize_t> dims{frames};
  dims.insert(dims.end(), frameShape.begin(), frameShape.end());
  Handle space(H5Screate_simple(int(dims.size()), dims.data(), nullptr));
  Handle props(H5Pcreate(H5P_DATASET_CREATE));
  H5Pset_layout(props.get(), H5D_CONTIGUOUS);
  H5Pset_alloc_time(props.get(), H5D_ALLOC_TIME_EARLY);
  // No times in the object header: nothing there to change after it is created.
  H5Pset_obj_track_times(props.get(), 0);
  if (fill)
  {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    H5Pset_fill_value(props.get(), H5T_NATIVE_DOUBLE, &nan);
    H5Pset_fill_time(props.get(), H5D_FILL_TIME_ALLOC);
  }
  else
  {
    H5Pset_fill_time(props.get(), H5D_FILL_TIME_NEVER);
  }
  return Handle(H5Dcreate2(parent, name, type, space.get(), H5P_DEFAULT, props.get(), H5P_DEFAULT));
}

bool RowSelection::build(hid_t dataset, const Runs& runs)
{
  file = Handle(H5Dget_space(dataset));
  const int rank = H5Sget_simple_extent_ndims(file.get());
  if (rank < 2)
  {
    return false;
  }
  std::vector<hsize_t> dims(rank);
  H5Sget_simple_extent_dims(file.get(), dims.data(), nullptr);
  hsize_t perRow = 1;
  for (int k = 2; k < rank; ++k)
  {
    perRow *= dims[k];
  }
  Rows = runs;
  values = 0;
  for (const auto& run : runs)
  {
    values += run.second * perRow;
  }
  const hsize_t n = std::max<hsize_t>(values, 1);
  memory = Handle(H5Screate_simple(1, &n, nullptr));
  if (values == 0)
  {
    H5Sselect_none(memory.get());
  }
  return file.valid() && memory.valid() && select(0);
}

bool RowSelection::moveToFrame(hsize_t t)
{
  return t == Frame || select(t);
}

bool RowSelection::select(hsize_t t)
{
  const int rank = H5Sget_simple_extent_ndims(file.get());
  std::vector<hsize_t> dims(rank);
  H5Sget_simple_extent_dims(file.get(), dims.data(), nullptr);
  H5Sselect_none(file.get());
  std::vector<hsize_t> start(rank, 0), count = dims;
  start[0] = t;
  count[0] = 1;
  for (const auto& [first, rows] : Rows)
  {
    start[1] = first;
    count[1] = rows;
    if (H5Sselect_hyperslab(file.get(), H5S_SELECT_OR, start.data(), nullptr, count.data(),
                            nullptr) < 0)
    {
      return false;
    }
  }
  Frame = t;
  return true;
}

bool readFirst(hid_t dataset, hsize_t count, double* data)
{
  Handle fileSpace(H5Dget_space(dataset));
  const hsize_t start = 0;
  H5Sselect_hyperslab(fileSpace.get(), H5S_SELECT_SET, &start, nullptr, &count, nullptr);
  Handle memSpace(H5Screate_simple(1, &count, nullptr));
  return H5Dread(dataset, H5T_NATIVE_DOUBLE, memSpace.get(), fileSpace.get(), H5P_DEFAULT, data) >=
         0;
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

bool describe(hid_t dataset, DatasetInfo& info)
{
  info = DatasetInfo{};
  Handle type(H5Dget_type(dataset)), space(H5Dget_space(dataset)),
      dcpl(H5Dget_create_plist(dataset));
  if (!type.valid() || !space.valid() || !dcpl.valid())
  {
    return false;
  }
  info.typeClass = H5Tget_class(type.get());
  info.typeSize = H5Tget_size(type.get());
  info.simple = H5Sget_simple_extent_type(space.get()) == H5S_SIMPLE;
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank < 0 || rank > H5S_MAX_RANK)
  {
    return false;
  }
  info.dims.resize(rank);
  if (rank > 0 && H5Sget_simple_extent_dims(space.get(), info.dims.data(), nullptr) < 0)
  {
    return false;
  }
  info.filters = H5Pget_nfilters(dcpl.get());
  const H5D_layout_t layout = H5Pget_layout(dcpl.get());
  if (layout == H5D_CONTIGUOUS || layout == H5D_COMPACT)
  {
    // Its values' bytes, all of them, in the file (contiguous) or in its header (compact): a
    // damaged layout whose size disagrees with the dataspace is read past its buffer by
    // HDF5 1.10.8. (A contiguous dataset never written has none either.)
    const hssize_t points = H5Sget_simple_extent_npoints(space.get());
    const hsize_t stored = H5Dget_storage_size(dataset);
    const double want = points > 0 ? double(points) * double(info.typeSize) : 0.0;
    info.storageMatches = double(stored) == want && (want == 0 || layout == H5D_COMPACT ||
                                                     H5Dget_offset(dataset) != HADDR_UNDEF);
  }
  if (H5Pget_layout(dcpl.get()) == H5D_CHUNKED)
  {
    hsize_t chunk[H5S_MAX_RANK] = {0};
    const int chunkRank = H5Pget_chunk(dcpl.get(), H5S_MAX_RANK, chunk);
    // Saturating: a damaged file may declare chunks whose product overflows.
    info.chunkValues = chunkRank > 0 ? 1 : 0;
    for (int k = 0; k < chunkRank; ++k)
    {
      const hsize_t most = std::numeric_limits<hsize_t>::max();
      info.chunkValues =
          chunk[k] != 0 && info.chunkValues > most / chunk[k] ? most : info.chunkValues * chunk[k];
    }
  }
  return info.filters >= 0;
}

bool readWhole(hid_t dataset, hid_t memType, void* data)
{
  return H5Dread(dataset, memType, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0;
}

} // namespace hair::hdf5
